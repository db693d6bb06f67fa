#pragma once
// Cameras and camera paths of the hybridwalk library. A pinhole camera in the
// conventions of Zheng et al. 1999 §1.1 (docs/how-it-works.md "Camera"):
// eye E and orthonormal axes U (right), V (up), W (view direction), in scene
// units, Y up; vertical field of view in radians; the frame's size in pixels;
// near and far planes (scene units, 0 < near < far). Row 0 of a frame is its
// top row; pixel (i, j) has its centre at (i + 0.5, j + 0.5).
#include <string>
#include <vector>

#include "hybridwalk/result.h"

namespace hybridwalk {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

struct Camera {
  Vec3 eye{0, 0, 0};
  Vec3 right{1, 0, 0};                      // U
  Vec3 up{0, 1, 0};                         // V
  Vec3 forward{0, 0, -1};                   // W, the view direction
  double fovYRadians = 1.0471975511965976;  // 60°
  int width = 512, height = 512;            // frame size, pixels (1 … 16384)
  double nearPlane = 0.1, farPlane = 1000.0;

  // The camera at `eye` looking at `target`, `upHint` giving the up side.
  // Error when target == eye, the view is along upHint, a value is not
  // finite, fov is outside (0, π), the size outside 1 … 16384, or not
  // 0 < near < far.
  static Result<Camera> lookAt(const Vec3& eye, const Vec3& target, const Vec3& upHint = {0, 1, 0},
                               double fovYRadians = 1.0471975511965976, int width = 512,
                               int height = 512, double nearPlane = 0.1, double farPlane = 1000.0);
};

// A camera per frame, and where the keyframes go: frame k is a keyframe
// when k % keyframeEvery == 0, and so is the last frame (every other frame
// lies between two keyframes).
struct Path {
  std::vector<Camera> cameras;  // all of one size
  int keyframeEvery = 10;       // ≥ 1
};

// A camera path file (JSON, docs/camera-path.md: control points sampled at
// constant speed along a Catmull-Rom curve), as `hybridwalk walk --path`
// reads it. Errors name the file and what is wrong (unknown keys, bad
// values, unreadable file).
Result<Path> loadPath(const std::string& file);

}  // namespace hybridwalk
