#include "scenes/default_paths.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hw::scenes {

CameraPath flythroughPathFor(const Scene& scene) {
  const glm::dvec3 lo(scene.boundsMin), hi(scene.boundsMax);
  const glm::dvec3 c = 0.5 * (lo + hi), ext = hi - lo;
  double diag = glm::length(ext);
  if (!(diag > 0.0) || !std::isfinite(diag)) diag = 1.0;
  double rx = 0.3 * ext.x, rz = 0.3 * ext.z;
  if (rx < 0.05 * diag && rz < 0.05 * diag) rx = rz = 0.5 * diag;
  rx = std::max(rx, 0.05 * diag);  // never through the centre being looked at
  rz = std::max(rz, 0.05 * diag);
  // Flat scenes (a terrain, a floor plan) are circled from above.
  const double eyeY = ext.y < 0.05 * diag ? c.y + 0.3 * diag : lo.y + 0.5 * ext.y;
  CameraPath p;
  p.nearPlane = std::max(1e-4, 1e-3 * diag);
  p.farPlane = 3.0 * diag;
  p.frames = 120;
  p.keyframeEvery = 10;
  constexpr int kKeys = 8;
  for (int k = 0; k <= kKeys; ++k) {
    const double t = 2.0 * 3.14159265358979323846 * k / kKeys;
    p.keys.push_back({{c.x + rx * std::cos(t), eyeY, c.z + rz * std::sin(t)}, c});
  }
  return p;
}

namespace {
constexpr int kSightRays = 12;  // per side of a key's view

bool keySees(const TriangleGrid& grid, const CameraPath& path, const CameraKey& k) {
  const glm::dvec3 forward = k.lookAt - k.eye;
  if (!(glm::length(forward) > 0)) return false;
  return openViewFraction(grid, k.eye, forward, path.fovYDeg, path.farPlane, kSightRays,
                          /*frontOnly=*/true) < 1.0;
}
}  // namespace

int keysSeeingSurfaces(const TriangleGrid& grid, const CameraPath& path) {
  int n = 0;
  for (const CameraKey& k : path.keys) n += keySees(grid, path, k);
  return n;
}

CameraPath objectOrbitFor(const Scene& scene, const TriangleGrid& grid) {
  const glm::dvec3 lo(scene.boundsMin), hi(scene.boundsMax);
  const glm::dvec3 c = 0.5 * (lo + hi);
  double radius = 0.5 * glm::length(hi - lo);
  if (!(radius > 0.0) || !std::isfinite(radius)) radius = 0.5;
  CameraPath p;
  p.frames = 120;
  p.keyframeEvery = 10;
  // The bounding sphere's silhouette fills the view's height, 10 % spare.
  const double distance = 1.1 * radius / std::sin(0.5 * p.fovYDeg * std::numbers::pi / 180.0);
  p.nearPlane = std::max(1e-4 * radius, 0.5 * (distance - radius));
  p.farPlane = distance + 2.0 * radius;
  const double elevation = 25.0 * std::numbers::pi / 180.0;
  constexpr int kKeys = 8;
  auto eyeAt = [&](double t) {
    return c + distance * glm::dvec3(std::cos(elevation) * std::cos(t), std::sin(elevation),
                                     std::cos(elevation) * std::sin(t));
  };
  // Start where the view covers the most drawn surface (a one-sided flat
  // model seen edge-on, or from behind, shows nothing).
  double start = 0.0, bestOpen = 2.0;
  for (int k = 0; k < kKeys; ++k) {
    const double t = 2.0 * std::numbers::pi * k / kKeys;
    const double open = openViewFraction(grid, eyeAt(t), c - eyeAt(t), p.fovYDeg, p.farPlane,
                                         kSightRays, /*frontOnly=*/true);
    if (open < bestOpen) bestOpen = open, start = t;
  }
  for (int k = 0; k <= kKeys; ++k)
    p.keys.push_back({eyeAt(start + 2.0 * std::numbers::pi * k / kKeys), c});
  // A model seen from one side only (a one-sided flat model): swing ±60°
  // in front of it instead of going round.
  if (2 * keysSeeingSurfaces(grid, p) < static_cast<int>(p.keys.size())) {
    p.keys.clear();
    for (int k = 0; k <= kKeys; ++k)
      p.keys.push_back(
          {eyeAt(start + std::numbers::pi / 3.0 * std::sin(2.0 * std::numbers::pi * k / kKeys)),
           c});
  }
  return p;
}

CameraPath framedDefaultPath(const Scene& scene, CameraPath path, std::vector<std::string>* notes) {
  const int keys = static_cast<int>(path.keys.size());
  if (keys == 0 || scene.triangleCount() == 0) return path;
  const TriangleGrid grid(scene, std::max(1e-6, 0.02 * glm::length(glm::dvec3(scene.boundsMax) -
                                                                   glm::dvec3(scene.boundsMin))));
  const int seen = keysSeeingSurfaces(grid, path);
  if (2 * seen >= keys) return path;
  CameraPath orbit = objectOrbitFor(scene, grid);
  const int orbitKeys = static_cast<int>(orbit.keys.size());
  const int orbitSeen = keysSeeingSurfaces(grid, orbit);
  auto say = [&](const std::string& s) {
    if (notes) notes->push_back(scene.name + ": " + s);
  };
  int shown = seen;
  if (orbitSeen * keys > seen * orbitKeys) {
    say("the default path would show no drawn surface at " + std::to_string(keys - seen) + " of " +
        std::to_string(keys) +
        " keys (a small single object); orbiting outside the model's "
        "bounds instead, looking at its centre");
    path = std::move(orbit);
    shown = orbitSeen;
  }
  const int n = static_cast<int>(path.keys.size());
  if (2 * shown < n)
    say("warning: the default path shows no drawn surface at " + std::to_string(n - shown) +
        " of " + std::to_string(n) +
        " keys: frames there are the background colour (back faces are not drawn: the model may "
        "face inward, or be seen edge-on); give a camera path with --path");
  return path;
}

}  // namespace hw::scenes
