#pragma once
// Keyframe export (DESIGN.md "Keyframe export", a contract other tools read):
// the keyframes of a camera path as NAME.png (RGB), NAME.depth.pfm (float32
// eye-space z along W, 0 where empty) and cameras.json (intrinsics in pixels,
// world_from_camera 4×4 row-major with OpenCV axes), so other view-synthesis
// methods can be run on exactly the inputs of Zheng et al. 1999 §2.
#include <nlohmann/json.hpp>
#include <string>

#include "core/camera.h"
#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::session {

struct ExportOptions {
  // Also export every in-between frame's camera and geometry reference image
  // (frame_NNNN.png), for comparing other tools' output with ours.
  bool inBetween = true;
  int maxFrames = 0;     // 0 = all frames of the path; else the first maxFrames
                         // (the last of them becomes a keyframe, as in a walk)
  bool progress = true;  // a progress line (frames done, ETA) on stderr
  // Keyframe depth buffer; the exported depth is eye-space z whatever the mode
  // (Float32 gives more precise far depths than the paper's 24-bit buffer).
  DepthMode depthMode = kDefaultDepthMode;
};

// Writes to `outDir` (created if missing; checked writable before anything is
// rendered):
//   key_NNNN.png, key_NNNN.depth.pfm  for each keyframe of
//       KeyframeSchedule{frames, path.keyframeEvery} (NNNN = frame index);
//   frame_NNNN.png                    for each in-between frame (inBetween);
//   cameras.json = {"format": "hybridwalk-keyframes", "version": 1,
//                   "keyframes": [...], "in_between": [...]}
// Each camera entry: name, frame, is_keyframe, width, height, fx, fy, cx, cy,
// near, far, world_from_camera; in-between entries add "keyframes": [name of
// the keyframe before, name of the one after]. "in_between" is [] when
// inBetween is off. Every file is written atomically and cameras.json last,
// so a folder with a cameras.json is complete. A GL context must be current.
Status exportKeyframes(const scenes::Scene& scene, const scenes::CameraPath& path,
                       const std::string& outDir, const ExportOptions& options = {});

// One cameras.json entry (name, width, height, fx, fy, cx, cy, near, far,
// world_from_camera) for `camera`; no GL. world_from_camera[r][c] is row r:
// columns are the camera's x (right), y (down), z (forward) axes and eye in world.
nlohmann::json exportCameraJson(const std::string& name, const Camera& camera);

// "key_0007" / "frame_0007".
std::string exportKeyframeName(int frame);
std::string exportFrameName(int frame);

}  // namespace hw::session
