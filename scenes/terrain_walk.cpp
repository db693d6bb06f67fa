#include "scenes/terrain_walk.h"

#include <algorithm>
#include <cmath>

#include "core/short_number.h"

namespace hw::scenes {

Result<CameraPath> terrainWalkPath(const TriangleGrid& grid,
                                   const std::vector<glm::dvec2>& waypointsXZ,
                                   const TerrainWalkOptions& options) {
  if (waypointsXZ.size() < 2) return makeError("terrain walk: need at least 2 waypoints");
  std::vector<glm::dvec2> pts;
  for (std::size_t i = 0; i + 1 < waypointsXZ.size(); ++i) {
    const glm::dvec2 a = waypointsXZ[i], b = waypointsXZ[i + 1];
    const int n =
        std::max(1, static_cast<int>(std::ceil(glm::length(b - a) / options.keySpacingMetres)));
    for (int k = 0; k < n; ++k) pts.push_back(a + (b - a) * (static_cast<double>(k) / n));
  }
  pts.push_back(waypointsXZ.back());
  auto ground = [&](const glm::dvec2& xz) -> Result<double> {
    const auto hits = grid.hitsBelow(glm::dvec3(xz.x, 1e6, xz.y));
    if (hits.empty())
      return makeError("terrain walk: no ground below x=" + shortNumber(xz.x) +
                       ", z=" + shortNumber(xz.y));
    return hits.back();
  };
  CameraPath path;
  path.nearPlane = 0.1;
  path.farPlane = 1000.0;
  path.frames = options.frames;
  path.keyframeEvery = options.keyframeEvery;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto g = ground(pts[i]);
    if (!g) return g.error();
    glm::dvec2 d = i + 1 < pts.size() ? pts[i + 1] - pts[i] : pts[i] - pts[i - 1];
    d = glm::normalize(d);
    const glm::dvec3 eye(pts[i].x, *g + options.eyeHeightMetres, pts[i].y);
    path.keys.push_back({eye, eye + glm::dvec3(d.x, 0.0, d.y) * options.lookAheadMetres});
  }
  // Look along the way: the average of the directions in and out of a key.
  for (std::size_t i = 1; i + 1 < path.keys.size(); ++i) {
    glm::dvec3 din = path.keys[i].eye - path.keys[i - 1].eye;
    glm::dvec3 dout = path.keys[i + 1].eye - path.keys[i].eye;
    din.y = dout.y = 0;
    glm::dvec3 d = glm::normalize(glm::normalize(din) + glm::normalize(dout));
    if (!std::isfinite(d.x)) d = glm::normalize(dout);
    path.keys[i].lookAt = path.keys[i].eye + d * options.lookAheadMetres;
  }
  return path;
}

}  // namespace hw::scenes
