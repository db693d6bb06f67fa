#pragma once
// The viewer's fly controls as plain maths (DESIGN.md "Viewer conventions"):
// an eye position plus yaw and pitch about the scene's +Y up axis, updated
// once per displayed frame from mouse deltas and movement keys. The camera
// basis is rebuilt from yaw/pitch every update, never accumulated, so it stays
// orthonormal to rounding however long the session; yaw is wrapped into
// (−π, π] and pitch clamped, so neither grows without bound (
// tests/cpu/app_fly_pose_test.cpp runs 10,000 updates).
#include <glm/glm.hpp>

#include "core/camera.h"

namespace hw::app {

// Pitch stays this far from the poles (radians, 89°), where yaw is undefined
// and cross(forward, +Y) vanishes.
inline constexpr double kMaxFlyPitch = 89.0 * 3.14159265358979323846 / 180.0;

struct FlyPose {
  glm::dvec3 eye{0.0};  // scene units
  double yaw = 0;       // radians in (−π, π]; 0 looks along −Z, +π/2 along +X
  double pitch = 0;     // radians in [−kMaxFlyPitch, kMaxFlyPitch]; + looks up
};

// Unit view direction of (yaw, pitch).
glm::dvec3 flyForward(double yaw, double pitch);

// Pose looking along `c.forward` from `c.eye` (pitch clamped).
FlyPose flyPoseFromCamera(const Camera& c);

// One frame of fly input: turn by dYaw, dPitch (radians; pitch clamped, yaw
// wrapped), then move `step` scene units times `move` = (right, up, forward)
// in the turned view: forward along the view direction, right horizontal,
// up along +Y. `move` components are usually −1, 0 or 1 (keys held).
void flyUpdate(FlyPose& pose, double dYaw, double dPitch, const glm::dvec3& move, double step);

// Camera at `pose` with the intrinsics (fov, size, near, far) of `base`. The
// basis is built from yaw/pitch directly, so it does not depend on the eye's
// magnitude: U = normalize(W × Y), V = U × W.
Camera flyCamera(const FlyPose& pose, const Camera& base);

}  // namespace hw::app
