#pragma once
// Camera path: the DESIGN.md "Camera path (JSON)" contract. Frames are sampled
// at constant speed (arc length) along a centripetal-free uniform Catmull-Rom
// curve through the control points' eyes and look-at points.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/result.h"

namespace hw::scenes {

struct CameraKey {
  glm::dvec3 eye{0.0};
  glm::dvec3 lookAt{0.0, 0.0, -1.0};
};

struct CameraPath {
  int width = 512;
  int height = 512;
  double fovYDeg = 60.0;
  double nearPlane = 0.1;
  double farPlane = 1000.0;
  glm::dvec3 up{0.0, 1.0, 0.0};
  std::vector<CameraKey> keys;  // ≥ 1 (one key: a still camera)
  int frames = 120;             // ≥ 1
  int keyframeEvery = 10;       // ≥ 1; frame k is a keyframe when k % keyframeEvery == 0

  // Camera of frame `index` in [0, frames). Constant speed along the curve;
  // frame 0 is at the first key, frame frames−1 at the last.
  // Builds the arc-length table on every call: for one camera.
  Camera cameraAt(int index) const;
  // Every frame's camera, equal to cameraAt(0 … frames−1), one table for all
  // (what a walk over the path should use: no per-frame allocation).
  std::vector<Camera> cameras() const;
  bool isKeyframe(int index) const { return index % keyframeEvery == 0; }
};

// Parses and validates the JSON text. `source` names the file in messages.
// Unknown keys, wrong types, non-finite numbers, frames < 1, keyframe_every < 1,
// near ≤ 0, near ≥ far, fov outside (0, 180), width/height outside [1, 16384],
// eye == look_at, or view direction parallel to up are errors.
Result<CameraPath> parseCameraPath(const std::string& jsonText, const std::string& source);
Result<CameraPath> loadCameraPath(const std::string& file);
std::string cameraPathToJson(const CameraPath& path);

}  // namespace hw::scenes
