#pragma once
// A walk on foot over terrain: keys at eye height above the lowest surface
// found by rays cast down.
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/triangle_grid.h"

namespace hw::scenes {

struct TerrainWalkOptions {
  double eyeHeightMetres = 1.7;   // above the ground found by ray casting down
  double keySpacingMetres = 4.0;  // keys placed along the polyline at this spacing
  double lookAheadMetres = 8.0;
  int frames = 240;
  int keyframeEvery = 10;
};

// A walk through `waypointsXZ` (x, z ground positions, polyline) at eye
// height above the LOWEST surface below each key (the terrain, not the tree
// canopies over it). Error when a key has no ground below it. 512², fov 60°,
// near 0.1 m, far 1000 m.
Result<CameraPath> terrainWalkPath(const TriangleGrid& grid,
                                   const std::vector<glm::dvec2>& waypointsXZ,
                                   const TerrainWalkOptions& options = {});

}  // namespace hw::scenes
