#pragma once
// What every default camera path shares: the settings the user may change,
// and the orbit used when a scene offers nothing better.
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::scenes {

// Settings of the default paths that the user may change (zero: each kind's own).
struct DefaultPathOptions {
  // Speed along a TORCS track's centreline, metres per frame (0: 450 m over
  // the path's 240 frames, 1.9 m/frame).
  double metresPerFrame = 0.0;
  // Eye above the floor or road, in scene units (0: 1.2 m in a TORCS car,
  // 1.7 m walking a MORSE terrain, scaled from the scene's size in a model
  // file's fly-through).
  double eyeHeight = 0.0;
};

// A closed loop of 8 keys inside the scene's bounds at mid height, looking at
// the centre; near/far from the bounds' diagonal. 512×512, fov 60°, 120 frames.
CameraPath flythroughPathFor(const Scene& scene);

}  // namespace hw::scenes
