#include "warp/seen.h"

#include <algorithm>
#include <cmath>

namespace hw::warp {
namespace {

// Whether `seer` drew the surface at world point p (depth match on one of the
// 2×2 pixels around its projection).
bool seenAt(const keyframe::Keyframe& seer, const glm::dvec3& p, double tol) {
  const ProjectedPoint q = seer.camera.project(p);
  if (!(q.zEye > 0) || !std::isfinite(q.u) || !std::isfinite(q.v)) return false;
  const int w = seer.eyeZ.width(), h = seer.eyeZ.height();
  if (q.u < 0 || q.v < 0 || q.u >= w || q.v >= h) return false;
  // The pixel the point lands in, and its 4-neighbours: all must hold the
  // surface (a point near a silhouette in the seer's view is not counted as
  // seen: that is where the foreground layer leaves its holes).
  const int xc = static_cast<int>(q.u), yc = static_cast<int>(q.v);
  static constexpr int kD[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& d : kD) {
    const int x = std::clamp(xc + d[0], 0, w - 1), y = std::clamp(yc + d[1], 0, h - 1);
    if (!seer.covered(x, y)) return false;
    // Neighbours differ by the surface's slope: a looser bound for them.
    const double t = (d[0] || d[1]) ? 4 * tol : tol;
    if (std::abs(static_cast<double>(seer.eyeZ(x, y)) - q.zEye) > t * q.zEye) return false;
  }
  return true;
}

}  // namespace

void quadsSeenBy(const keyframe::Keyframe& own, const keyframe::QuadMesh& mesh,
                 const keyframe::Keyframe& seer, const SeenOptions& options,
                 std::vector<std::uint8_t>& seen) {
  seen.assign(mesh.quads.size(), 0);
  const int step = std::max(1, options.gridStepPx);
  const int w = own.eyeZ.width(), h = own.eyeZ.height();
  auto sampleSeen = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= w || y >= h || !own.covered(x, y)) return true;
    const glm::dvec3 p = own.camera.unproject(x + 0.5, y + 0.5, own.eyeZ(x, y));
    return seenAt(seer, p, options.relTolerance);
  };
  for (std::size_t i = 0; i < mesh.quads.size(); ++i) {
    const keyframe::PixelRect& r = mesh.quads[i].rect;
    const int xs[2] = {r.x0, r.x1 - 1}, ys[2] = {r.y0, r.y1 - 1};
    bool all = true;
    for (int y : ys)
      for (int x : xs) all = all && sampleSeen(x, y);
    for (int y = r.y0 + step; all && y < r.y1 - 1; y += step)
      for (int x = r.x0 + step; all && x < r.x1 - 1; x += step) all = sampleSeen(x, y);
    seen[i] = all ? 1 : 0;
  }
}

}  // namespace hw::warp
