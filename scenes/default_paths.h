#pragma once
// What every default camera path shares: the settings the user may change,
// and the orbit used when a scene offers nothing better.
#include <string>
#include <vector>

#include "scenes/camera_path.h"
#include "scenes/scene.h"
#include "scenes/triangle_grid.h"

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

// How many of the path's keys see a surface the renderer draws (a front face,
// or either side of a two-sided material, within the far plane): rays through
// a 12 × 12 grid of each key's view (scenes/triangle_grid.h).
int keysSeeingSurfaces(const TriangleGrid& grid, const CameraPath& path);

// An orbit of 8 keys outside the bounds that frames the whole model (its
// bounding sphere fills the field of view's height), 25° above it, looking
// at its centre, starting where the first view sees the most drawn surface;
// a swing of ±60° about that start instead when most of the orbit would see
// nothing drawn (a one-sided flat model from behind).
CameraPath objectOrbitFor(const Scene& scene, const TriangleGrid& grid);

// `path` when at least half its keys see a drawn surface; otherwise the
// object orbit when it sees more (a small single object: the paths made for
// walking inside a level look at nothing). Says in `notes` (may be null)
// what it changed, and when the chosen path still shows nothing at most keys.
CameraPath framedDefaultPath(const Scene& scene, CameraPath path, std::vector<std::string>* notes);

}  // namespace hw::scenes
