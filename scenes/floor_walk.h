#pragma once
// A walk inside a model file's scene: walkable floor found by casting rays
// straight down on a grid over the bounds, the floor cells joined where a
// person could step between them, and a route along the longest shortest
// path (a graph "diameter" by two breadth-first searches) through the
// largest connected floor, preferring floor with something above it (the
// inside of a level rather than its roof).
#include <string>

#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::scenes {

struct FloorWalkOptions {
  int gridCells = 64;      // cells along the longer horizontal side of the bounds
  double eyeHeight = 0.0;  // scene units above the floor; 0: min(0.05 × that side, 1.7)
  int keysEveryCells = 3;  // one path key per this many route cells
  int frames = 120;
  int keyframeEvery = 10;
};

// A path at eye height over the floor, walked the way whose first view sees
// less sky or void: each key looks towards the route two keys ahead, level,
// or up to 15° down where looking level sees mostly sky or void. Cells count as floor where a
// surface has headroom for 1.25 × the eye height above it; neighbours join when their floors differ
// by at most half the eye height (stairs) and the eye can move between them without coming within
// 0.25 × the eye height of a surface. Error (saying why) when no connected floor of at least 8
// cells is found; the caller then orbits (flythroughPathFor). 512², fov 60°, near/far from the eye
// height and bounds.
Result<CameraPath> floorWalkPath(const Scene& scene, const FloorWalkOptions& options = {});

}  // namespace hw::scenes
