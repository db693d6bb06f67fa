// The viewer's pose distance, motion estimate and path look-ahead (app/viewer_motion.h).
#include "app/viewer_motion.h"

#include <algorithm>
#include <cmath>

#include "app/fly_pose.h"

namespace hw::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
}

}  // namespace

double PoseMetric::operator()(const Camera& a, const Camera& b) const {
  return glm::length(a.eye - b.eye) / distance + angleBetween(a.forward, b.forward) / angleRadians;
}

void MotionEstimate::update(const Camera& prev, const Camera& cur, double dt) {
  if (!(dt > 1e-6)) return;
  constexpr double kSmooth = 0.5;
  const glm::dvec3 v = (cur.eye - prev.eye) / dt;
  const double py = std::atan2(prev.forward.x, -prev.forward.z);
  const double cy = std::atan2(cur.forward.x, -cur.forward.z);
  double dyaw = cy - py;
  if (dyaw > kPi) dyaw -= 2 * kPi;
  if (dyaw < -kPi) dyaw += 2 * kPi;
  const double dpitch = std::asin(std::clamp(cur.forward.y, -1.0, 1.0)) -
                        std::asin(std::clamp(prev.forward.y, -1.0, 1.0));
  velocity_ = glm::mix(velocity_, v, kSmooth);
  yawRate_ = yawRate_ + kSmooth * (dyaw / dt - yawRate_);
  pitchRate_ = pitchRate_ + kSmooth * (dpitch / dt - pitchRate_);
}

Camera MotionEstimate::extrapolate(const Camera& cur, double distance, const PoseMetric& metric,
                                   int width, int height) const {
  const double rate =
      glm::length(velocity_) / metric.distance +
      std::sqrt(yawRate_ * yawRate_ + pitchRate_ * pitchRate_) / metric.angleRadians;
  if (!(rate > 1e-9)) return cur;
  const double t = distance / rate;
  const glm::dvec3 eye = cur.eye + velocity_ * t;
  const double yaw = std::atan2(cur.forward.x, -cur.forward.z) + yawRate_ * t;
  const double pitch = std::clamp(std::asin(std::clamp(cur.forward.y, -1.0, 1.0)) + pitchRate_ * t,
                                  -kMaxFlyPitch, kMaxFlyPitch);
  return Camera::lookAt(eye, eye + flyForward(yaw, pitch), glm::dvec3(0, 1, 0), cur.fovYRadians,
                        width, height, cur.nearPlane, cur.farPlane);
}

Camera pathCameraAhead(const std::vector<Camera>& path, int next, const Camera& cur,
                       double distance, const PoseMetric& metric) {
  const int n = static_cast<int>(path.size());
  Camera best = cur;
  double bestS = -1;
  for (int k = 0; k < n - 1; ++k) {
    const Camera& c = path[static_cast<std::size_t>((next + k) % n)];
    const double s = metric(c, cur);
    if (s > bestS) best = c, bestS = s;
    if (s >= distance) break;
  }
  return best;
}

Camera pathCameraBeyond(const std::vector<Camera>& path, int next, const Camera& cur,
                        const Camera& newest, double spacing, const PoseMetric& metric) {
  const int n = static_cast<int>(path.size());
  const double sNewest = metric(newest, cur);
  Camera best = cur;
  double bestS = -1;
  for (int k = 0; k < n - 1; ++k) {
    const Camera& c = path[static_cast<std::size_t>((next + k) % n)];
    if (metric(c, cur) <= sNewest) continue;  // not past the newest yet
    const double s = metric(c, newest);
    if (s > bestS) best = c, bestS = s;
    if (s >= spacing) break;
  }
  return best;
}

}  // namespace hw::app
