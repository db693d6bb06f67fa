#include "scenes/default_paths.h"

#include <algorithm>
#include <cmath>

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

}  // namespace hw::scenes
