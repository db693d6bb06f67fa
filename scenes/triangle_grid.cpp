#include "scenes/triangle_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"

namespace hw::scenes {

double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c) {
  // Ericson, Real-Time Collision Detection, ClosestPtPointTriangle.
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(ap);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return glm::length(ap);  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return glm::length(p - (a + ab * v + ac * w));
}

namespace {

// Copies of one triangle (the same corners in the same cyclic order, so the
// same facing) answer every query alike; a model made of many copies (200000
// identical faces) would otherwise fill one cell with them and make each
// query scan them all.
template <typename Tri>
void dropCoincident(std::vector<Tri>& tris) {
  auto less = [](const glm::dvec3& p, const glm::dvec3& q) {
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
  };
  for (Tri& t : tris) {  // least corner first, winding kept
    if (less(t.b, t.a) && !less(t.c, t.b))
      t = Tri{t.b, t.c, t.a, t.twoSided};
    else if (less(t.c, t.a) && less(t.c, t.b))
      t = Tri{t.c, t.a, t.b, t.twoSided};
  }
  auto key = [&](const Tri& x, const Tri& y) {
    if (x.a != y.a) return less(x.a, y.a);
    if (x.b != y.b) return less(x.b, y.b);
    if (x.c != y.c) return less(x.c, y.c);
    return x.twoSided < y.twoSided;
  };
  std::sort(tris.begin(), tris.end(), key);
  tris.erase(std::unique(tris.begin(), tris.end(),
                         [](const Tri& x, const Tri& y) {
                           return x.a == y.a && x.b == y.b && x.c == y.c &&
                                  x.twoSided == y.twoSided;
                         }),
             tris.end());
}

}  // namespace

TriangleGrid::TriangleGrid(const Scene& scene, double cellSize) : cellSize_(cellSize) {
  HW_CHECK(cellSize > 0);
  for (const Mesh& m : scene.meshes) {
    const bool known =
        m.material >= 0 && static_cast<std::size_t>(m.material) < scene.materials.size();
    if (known && scene.materials[static_cast<std::size_t>(m.material)].sky) continue;
    const bool twoSided = known && scene.materials[static_cast<std::size_t>(m.material)].twoSided;
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
      tris_.push_back({glm::dvec3(m.vertices[m.indices[i]].position),
                       glm::dvec3(m.vertices[m.indices[i + 1]].position),
                       glm::dvec3(m.vertices[m.indices[i + 2]].position), twoSided});
  }
  if (tris_.empty()) return;
  dropCoincident(tris_);
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const Tri& t : tris_)
    for (const glm::dvec3& v : {t.a, t.b, t.c}) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  // Keep the grid under ~8M cells whatever the scene's extent.
  for (;;) {
    const glm::dvec3 d = glm::floor((hi - lo) / cellSize_) + 1.0;
    if (d.x * d.y * d.z <= 8e6) {
      dims_ = glm::ivec3(d);
      break;
    }
    cellSize_ *= 1.5;
  }
  origin_ = lo;
  cells_.resize(static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z);
  for (std::size_t i = 0; i < tris_.size(); ++i) {
    const Tri& t = tris_[i];
    const glm::ivec3 a = cellOf(glm::min(t.a, glm::min(t.b, t.c)));
    const glm::ivec3 b = cellOf(glm::max(t.a, glm::max(t.b, t.c)));
    for (int z = a.z; z <= b.z; ++z)
      for (int y = a.y; y <= b.y; ++y)
        for (int x = a.x; x <= b.x; ++x)
          cells_[(static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x].push_back(
              static_cast<std::uint32_t>(i));
  }
}

glm::ivec3 TriangleGrid::cellOf(const glm::dvec3& p) const {
  const glm::dvec3 c = glm::floor((p - origin_) / cellSize_);
  return glm::clamp(glm::ivec3(glm::clamp(c, glm::dvec3(-1.0), glm::dvec3(1e7))), glm::ivec3(0),
                    dims_ - 1);
}

std::vector<double> TriangleGrid::hitsBelow(const glm::dvec3& from) const {
  std::vector<double> hits;
  if (tris_.empty()) return hits;
  const glm::dvec3 rel = (from - origin_) / cellSize_;
  if (rel.x < 0 || rel.z < 0 || rel.x >= dims_.x || rel.z >= dims_.z) return hits;
  const glm::ivec3 top = cellOf(from);
  // A triangle spanning several cells of the column is tested once.
  std::vector<std::uint32_t> column;
  for (int y = top.y; y >= 0; --y) {
    const auto& c = cells_[(static_cast<std::size_t>(top.z) * dims_.y + y) * dims_.x + top.x];
    column.insert(column.end(), c.begin(), c.end());
  }
  std::sort(column.begin(), column.end());
  column.erase(std::unique(column.begin(), column.end()), column.end());
  for (std::uint32_t i : column) {
    const Tri& t = tris_[i];
    // 2D barycentrics in XZ.
    const double d = (t.b.z - t.c.z) * (t.a.x - t.c.x) + (t.c.x - t.b.x) * (t.a.z - t.c.z);
    if (std::abs(d) < 1e-12) continue;
    const double l1 = ((t.b.z - t.c.z) * (from.x - t.c.x) + (t.c.x - t.b.x) * (from.z - t.c.z)) / d;
    const double l2 = ((t.c.z - t.a.z) * (from.x - t.c.x) + (t.a.x - t.c.x) * (from.z - t.c.z)) / d;
    const double l3 = 1 - l1 - l2;
    // A point on a shared edge (spawns and floors on the same grid) must
    // not fall through the crack between two triangles.
    constexpr double kEdge = -1e-7;
    if (l1 < kEdge || l2 < kEdge || l3 < kEdge) continue;
    const double h = l1 * t.a.y + l2 * t.b.y + l3 * t.c.y;
    if (h <= from.y) hits.push_back(h);
  }
  std::sort(hits.begin(), hits.end(), std::greater<>());
  return hits;
}

double TriangleGrid::distanceToNearest(const glm::dvec3& p, double maxDistance) const {
  double best = maxDistance;
  if (tris_.empty()) return best;
  const glm::ivec3 a = cellOf(p - glm::dvec3(maxDistance)), b = cellOf(p + glm::dvec3(maxDistance));
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y)
      for (int x = a.x; x <= b.x; ++x)
        for (std::uint32_t i : cells_[(static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x]) {
          const Tri& t = tris_[i];
          best = std::min(best, pointTriangleDistance(p, t.a, t.b, t.c));
        }
  return best;
}

bool TriangleGrid::segmentClear(const glm::dvec3& a, const glm::dvec3& b, double clearance) const {
  const double len = glm::length(b - a);
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * clearance))));
  for (int i = 0; i <= n; ++i)
    if (distanceToNearest(a + (b - a) * (static_cast<double>(i) / n), clearance) < clearance)
      return false;
  return true;
}

std::optional<double> TriangleGrid::rayHit(const glm::dvec3& origin, const glm::dvec3& dir,
                                           double maxDistance, bool frontOnly) const {
  if (tris_.empty()) return std::nullopt;
  // March through the cells the ray crosses (Amanatides & Woo 1987), testing
  // their triangles (Möller & Trumbore 1997); the nearest hit in a cell is
  // final once it lies before the cell's exit.
  const glm::dvec3 hiB = origin_ + glm::dvec3(dims_) * cellSize_;
  double t0 = 0.0, t1 = maxDistance;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir[k]) < 1e-12) {
      if (origin[k] < origin_[k] || origin[k] > hiB[k]) return std::nullopt;
      continue;
    }
    double a = (origin_[k] - origin[k]) / dir[k], b = (hiB[k] - origin[k]) / dir[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return std::nullopt;
  glm::ivec3 c = cellOf(origin + dir * t0);
  glm::ivec3 stepI(0);
  glm::dvec3 tMax(std::numeric_limits<double>::infinity()), tDelta(tMax);
  for (int k = 0; k < 3; ++k) {
    if (dir[k] > 0) {
      stepI[k] = 1;
      tMax[k] = (origin_[k] + (c[k] + 1) * cellSize_ - origin[k]) / dir[k];
      tDelta[k] = cellSize_ / dir[k];
    } else if (dir[k] < 0) {
      stepI[k] = -1;
      tMax[k] = (origin_[k] + c[k] * cellSize_ - origin[k]) / dir[k];
      tDelta[k] = -cellSize_ / dir[k];
    }
  }
  double best = std::numeric_limits<double>::infinity();
  for (int guard = 0; guard < dims_.x + dims_.y + dims_.z + 3; ++guard) {
    for (std::uint32_t i : cells_[(static_cast<std::size_t>(c.z) * dims_.y + c.y) * dims_.x + c.x]) {
      const Tri& t = tris_[i];
      const glm::dvec3 e1 = t.b - t.a, e2 = t.c - t.a, p = glm::cross(dir, e2);
      const double det = glm::dot(e1, p);
      if (std::abs(det) < 1e-14) continue;
      // det = −dir · (e1 × e2): positive when the ray meets the front (CCW) side.
      if (frontOnly && !t.twoSided && det < 0) continue;
      const glm::dvec3 s = origin - t.a;
      const double u = glm::dot(s, p) / det;
      if (u < 0 || u > 1) continue;
      const glm::dvec3 q = glm::cross(s, e1);
      const double v = glm::dot(dir, q) / det;
      if (v < 0 || u + v > 1) continue;
      const double tt = glm::dot(e2, q) / det;
      if (tt > 1e-9 && tt < best) best = tt;
    }
    const double exit = std::min({tMax.x, tMax.y, tMax.z});
    if (best <= exit) break;
    if (exit > t1) break;
    const int k = tMax.x == exit ? 0 : tMax.y == exit ? 1 : 2;
    c[k] += stepI[k];
    if (c[k] < 0 || c[k] >= dims_[k]) break;
    tMax[k] += tDelta[k];
  }
  if (best <= maxDistance) return best;
  return std::nullopt;
}

double openViewFraction(const TriangleGrid& grid, const glm::dvec3& eye, const glm::dvec3& forward,
                        double fovYDeg, double maxDistance, int n, bool frontOnly) {
  const glm::dvec3 w = glm::normalize(forward);
  glm::dvec3 u = glm::cross(w, glm::dvec3(0, 1, 0));
  if (glm::length(u) < 1e-9) u = glm::dvec3(1, 0, 0);
  u = glm::normalize(u);
  const glm::dvec3 v = glm::cross(u, w);
  const double h = std::tan(0.5 * fovYDeg * 3.14159265358979323846 / 180.0);
  int open = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (2.0 * (i + 0.5) / n - 1.0) * h, y = (1.0 - 2.0 * (j + 0.5) / n) * h;
      if (!grid.rayHit(eye, glm::normalize(w + x * u + y * v), maxDistance, frontOnly)) ++open;
    }
  return static_cast<double>(open) / (n * n);
}

EyeCheck checkEye(const TriangleGrid& grid, const glm::dvec3& eye, double maxClearance) {
  EyeCheck c;
  const std::vector<double> hits = grid.hitsBelow(eye);
  if (!hits.empty()) c.floorDrop = eye.y - hits.front();
  c.clearance = grid.distanceToNearest(eye, maxClearance);
  return c;
}

}  // namespace hw::scenes
