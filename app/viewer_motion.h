#pragma once
// Where the viewer is heading, as plain maths: the pose distance that places
// its keyframes, the motion estimated from the frames shown (to render the
// next keyframe ahead of a flying viewer), and the cameras ahead on a played
// path. No GL.
#include <glm/glm.hpp>
#include <vector>

#include "core/camera.h"

namespace hw::app {

// Pose distance s between two cameras: eye distance over `distance` (scene
// units) plus the angle between their view directions over `angleRadians`;
// each threshold counts 1 (session/keyframe_survey.h).
struct PoseMetric {
  double distance = 1;
  double angleRadians = 0.25;
  double operator()(const Camera& a, const Camera& b) const;
};

// The viewer's velocity and yaw / pitch rates, smoothed over the frames
// (each update halves the weight of the past). Scenes are Y-up.
class MotionEstimate {
 public:
  // The viewer moved from `prev` to `cur` in `dt` seconds (ignored when dt ≤ 1e-6 s).
  void update(const Camera& prev, const Camera& cur, double dt);
  // The camera `distance` pose units ahead of `cur` along the estimated
  // motion, at width x height (pitch clamped as fly controls clamp it);
  // `cur` itself when the viewer is not moving.
  Camera extrapolate(const Camera& cur, double distance, const PoseMetric& metric, int width,
                     int height) const;
  const glm::dvec3& velocity() const { return velocity_; }  // scene units / s
  double yawRate() const { return yawRate_; }               // radians / s
  double pitchRate() const { return pitchRate_; }           // radians / s

 private:
  glm::dvec3 velocity_{0.0};
  double yawRate_ = 0, pitchRate_ = 0;
};

// A played path loops; `next` is the index of its camera shown next (the
// viewer is at `cur`) and path.size() ≥ 2. Of the path's next size − 1
// cameras: the first one at least `distance` from `cur`, else the farthest.
Camera pathCameraAhead(const std::vector<Camera>& path, int next, const Camera& cur,
                       double distance, const PoseMetric& metric);

// The keyframe after `newest`, `spacing` beyond it: of the path's next
// size − 1 cameras, those farther from `cur` than `newest` is (past it: pose
// distance along a bending path is not additive, so the distance from the
// viewer would not do), the first at least `spacing` from `newest`, else the
// farthest from it; `cur` when none is past it.
Camera pathCameraBeyond(const std::vector<Camera>& path, int next, const Camera& cur,
                        const Camera& newest, double spacing, const PoseMetric& metric);

}  // namespace hw::app
