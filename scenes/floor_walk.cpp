// Floor walk through a model's scene. See floor_walk.h.
#include "scenes/floor_walk.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <vector>

#include "scenes/triangle_grid.h"

namespace hw::scenes {

namespace {

struct FloorNode {
  int ix = 0, iz = 0;
  glm::dvec3 eye{0.0};
  bool ceiling = false;
};

// Breadth-first distances (in edges) from `from` over `adj`; -1 unreached.
std::vector<int> bfs(const std::vector<std::vector<int>>& adj, int from, std::vector<int>* parent) {
  std::vector<int> dist(adj.size(), -1);
  if (parent) parent->assign(adj.size(), -1);
  std::deque<int> q{from};
  dist[static_cast<std::size_t>(from)] = 0;
  while (!q.empty()) {
    const int n = q.front();
    q.pop_front();
    for (int m : adj[static_cast<std::size_t>(n)])
      if (dist[static_cast<std::size_t>(m)] < 0) {
        dist[static_cast<std::size_t>(m)] = dist[static_cast<std::size_t>(n)] + 1;
        if (parent) (*parent)[static_cast<std::size_t>(m)] = n;
        q.push_back(m);
      }
  }
  return dist;
}

}  // namespace

Result<CameraPath> floorWalkPath(const Scene& scene, const FloorWalkOptions& options) {
  const glm::dvec3 lo(scene.boundsMin), hi(scene.boundsMax), ext = hi - lo;
  const double side = std::max(ext.x, ext.z);
  if (!(side > 0.0) || !std::isfinite(side) || scene.triangleCount() == 0)
    return makeError(scene.name + ": no floor to walk on (the scene has no horizontal extent)");
  const double eye = options.eyeHeight > 0 ? options.eyeHeight : std::min(0.05 * side, 1.7);
  const int cellsAlong = std::clamp(options.gridCells, 4, 1024);
  const double cell = side / cellsAlong;
  const int nx = std::max(1, static_cast<int>(std::ceil(ext.x / cell)));
  const int nz = std::max(1, static_cast<int>(std::ceil(ext.z / cell)));
  const TriangleGrid grid(scene, std::max(cell, side / 256.0));

  std::vector<FloorNode> nodes;
  std::vector<std::vector<int>> nodesOfCell(static_cast<std::size_t>(nx) * nz);
  for (int iz = 0; iz < nz; ++iz)
    for (int ix = 0; ix < nx; ++ix) {
      const double x = lo.x + (ix + 0.5) * cell, z = lo.z + (iz + 0.5) * cell;
      const std::vector<double> hits = grid.hitsBelow({x, hi.y + 1.0, z});
      double above = std::numeric_limits<double>::infinity();
      for (double h : hits) {
        if (above - h >= 1.25 * eye) {
          const glm::dvec3 e(x, h + eye, z);
          if (grid.distanceToNearest(e, 0.25 * eye) >= 0.25 * eye) {
            FloorNode n{ix, iz, e, std::isfinite(above)};
            nodesOfCell[static_cast<std::size_t>(iz) * nx + ix].push_back(
                static_cast<int>(nodes.size()));
            nodes.push_back(n);
          }
        }
        above = h;
      }
    }
  // Steps between neighbouring cells.
  std::vector<std::vector<int>> adj(nodes.size());
  for (std::size_t a = 0; a < nodes.size(); ++a) {
    const FloorNode& n = nodes[a];
    for (const auto& [dx, dz] : {std::pair{1, 0}, std::pair{0, 1}}) {
      const int jx = n.ix + dx, jz = n.iz + dz;
      if (jx >= nx || jz >= nz) continue;
      for (int b : nodesOfCell[static_cast<std::size_t>(jz) * nx + jx]) {
        const FloorNode& m = nodes[static_cast<std::size_t>(b)];
        if (std::abs(m.eye.y - n.eye.y) > 0.5 * eye) continue;
        if (!grid.segmentClear(n.eye, m.eye, 0.25 * eye)) continue;
        adj[a].push_back(b);
        adj[static_cast<std::size_t>(b)].push_back(static_cast<int>(a));
      }
    }
  }
  // Connected floors; the best has the most floor, counting floor with
  // something above it four times (a level's inside over its roof).
  std::vector<int> comp(nodes.size(), -1);
  int best = -1, bestStart = -1;
  double bestScore = 0;
  std::size_t bestSize = 0;
  for (std::size_t s = 0; s < nodes.size(); ++s) {
    if (comp[s] >= 0) continue;
    const std::vector<int> d = bfs(adj, static_cast<int>(s), nullptr);
    double score = 0;
    std::size_t size = 0;
    for (std::size_t k = 0; k < d.size(); ++k)
      if (d[k] >= 0) {
        comp[k] = static_cast<int>(s);
        score += nodes[k].ceiling ? 1.0 : 0.25;
        ++size;
      }
    if (score > bestScore) {
      bestScore = score;
      best = static_cast<int>(s);
      bestStart = static_cast<int>(s);
      bestSize = size;
    }
  }
  if (best < 0 || bestSize < 8) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  ": no walkable floor found (largest connected floor %zu cells of %d x %d, "
                  "eye height %.3g; need 8)",
                  bestSize, nx, nz, eye);
    return makeError(scene.name + buf);
  }
  // The route: the longest shortest path through that floor.
  std::vector<int> d0 = bfs(adj, bestStart, nullptr);
  const int a = static_cast<int>(std::max_element(d0.begin(), d0.end()) - d0.begin());
  std::vector<int> parent;
  std::vector<int> da = bfs(adj, a, &parent);
  const int b = static_cast<int>(std::max_element(da.begin(), da.end()) - da.begin());
  std::vector<glm::dvec3> route;
  for (int n = b; n >= 0; n = parent[static_cast<std::size_t>(n)])
    route.push_back(nodes[static_cast<std::size_t>(n)].eye);
  const int every = std::max(1, options.keysEveryCells);
  std::vector<glm::dvec3> keys;
  for (std::size_t k = 0; k < route.size(); k += static_cast<std::size_t>(every))
    keys.push_back(route[k]);
  if ((route.size() - 1) % static_cast<std::size_t>(every) != 0) keys.push_back(route.back());
  if (keys.size() < 2)
    return makeError(scene.name + ": no walkable floor found (the longest route is one cell)");

  CameraPath path;
  path.frames = options.frames;
  path.keyframeEvery = options.keyframeEvery;
  path.nearPlane = std::max(1e-4, 0.05 * eye);
  path.farPlane = std::max(10.0 * path.nearPlane, 3.0 * glm::length(ext));
  auto gazeOf = [&](std::size_t k) {
    glm::dvec3 target = keys[std::min(k + 2, keys.size() - 1)];
    if (k + 1 >= keys.size()) target = keys[k] + (keys[k] - keys[k - 1]);
    glm::dvec3 d = target - keys[k];
    d.y = 0.0;  // level, along the way
    return glm::length(d) < 1e-9 ? glm::dvec3(1, 0, 0) : glm::normalize(d);
  };
  // Walk the route the way whose first view sees less sky or void.
  {
    const double fwd =
        openViewFraction(grid, keys.front(), gazeOf(0), path.fovYDeg, path.farPlane, 12);
    std::reverse(keys.begin(), keys.end());
    const double back =
        openViewFraction(grid, keys.front(), gazeOf(0), path.fovYDeg, path.farPlane, 12);
    if (fwd <= back) std::reverse(keys.begin(), keys.end());
  }
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const glm::dvec3 dir = gazeOf(k);
    // Look down a little (up to 15°) where looking level sees mostly sky.
    glm::dvec3 look = dir;
    double lookOpen = 2.0;
    for (double deg : {0.0, 5.0, 10.0, 15.0}) {
      const double pitch = deg * 3.14159265358979323846 / 180.0;
      const glm::dvec3 d = std::cos(pitch) * dir - std::sin(pitch) * glm::dvec3(0, 1, 0);
      const double open = openViewFraction(grid, keys[k], d, path.fovYDeg, path.farPlane, 12);
      if (open < lookOpen - 0.02) {
        look = d;
        lookOpen = open;
      }
      if (lookOpen < 0.4) break;
    }
    path.keys.push_back({keys[k], keys[k] + look * std::max(cell, eye)});
  }
  return path;
}

}  // namespace hw::scenes
