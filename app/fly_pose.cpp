#include "app/fly_pose.h"

#include <algorithm>
#include <cmath>

namespace hw::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Into (−π, π]. remainder() is exact (IEEE), so wrapping adds no error of its
// own beyond representing 2π.
double wrapAngle(double a) {
  a = std::remainder(a, 2 * kPi);
  return a <= -kPi ? a + 2 * kPi : a;
}

}  // namespace

glm::dvec3 flyForward(double yaw, double pitch) {
  return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
}

FlyPose flyPoseFromCamera(const Camera& c) {
  FlyPose p;
  p.eye = c.eye;
  p.yaw = wrapAngle(std::atan2(c.forward.x, -c.forward.z));
  p.pitch = std::clamp(std::asin(std::clamp(c.forward.y, -1.0, 1.0)), -kMaxFlyPitch, kMaxFlyPitch);
  return p;
}

void flyUpdate(FlyPose& pose, double dYaw, double dPitch, const glm::dvec3& move, double step) {
  pose.yaw = wrapAngle(pose.yaw + dYaw);
  pose.pitch = std::clamp(pose.pitch + dPitch, -kMaxFlyPitch, kMaxFlyPitch);
  if (move == glm::dvec3(0.0) || step == 0.0) return;
  const glm::dvec3 fwd = flyForward(pose.yaw, pose.pitch);
  // Horizontal right: W × Y has length cos(pitch) ≥ cos 89° ≈ 0.017.
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(0, 1, 0)));
  pose.eye += step * (move.z * fwd + move.x * right + move.y * glm::dvec3(0, 1, 0));
}

Camera flyCamera(const FlyPose& pose, const Camera& base) {
  Camera c = base;
  c.eye = pose.eye;
  c.forward = flyForward(pose.yaw, pose.pitch);
  c.right = glm::normalize(glm::cross(c.forward, glm::dvec3(0, 1, 0)));
  c.up = glm::cross(c.right, c.forward);
  return c;
}

}  // namespace hw::app
