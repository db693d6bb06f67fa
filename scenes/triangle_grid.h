#pragma once
// Geometric queries on a scene's triangles for camera paths: ground height
// (rays down), clearance, ray casts.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "scenes/scene.h"

namespace hw::scenes {

// Uniform grid over a scene's triangles (world space) for ground-height,
// clearance and ray queries; brute force inside cells. Sky surfaces
// (Material::sky) are left out. Built once, read-only after.
class TriangleGrid {
 public:
  explicit TriangleGrid(const Scene& scene, double cellSize = 2.0);

  // Heights (Y) of every surface hit by a ray straight down (−Y) from
  // `from`, highest first.
  std::vector<double> hitsBelow(const glm::dvec3& from) const;
  // Distance from `p` to the nearest triangle, or `maxDistance` when none is
  // closer than that.
  double distanceToNearest(const glm::dvec3& p, double maxDistance) const;
  // True when the segment a→b stays at least `clearance` from every
  // triangle (checked at steps of clearance/2).
  bool segmentClear(const glm::dvec3& a, const glm::dvec3& b, double clearance) const;
  // Distance along the unit direction `dir` from `origin` to the first
  // triangle hit (either side; with frontOnly, only sides the renderer draws:
  // counter-clockwise fronts, and both sides of two-sided materials), or
  // nullopt when none is within maxDistance.
  std::optional<double> rayHit(const glm::dvec3& origin, const glm::dvec3& dir, double maxDistance,
                               bool frontOnly = false) const;

  std::size_t triangleCount() const { return tris_.size(); }

 private:
  struct Tri {
    glm::dvec3 a, b, c;
    bool twoSided = false;
  };
  glm::ivec3 cellOf(const glm::dvec3& p) const;
  const std::vector<std::uint32_t>* cell(const glm::ivec3& c) const;

  std::vector<Tri> tris_;
  glm::dvec3 origin_{0.0};
  glm::ivec3 dims_{0};
  double cellSize_;
  std::vector<std::vector<std::uint32_t>> cells_;
};

// Where an eye stands: the drop to the first surface straight below it
// (nullopt: nothing below, the eye is over the void) and the distance to
// the nearest triangle (capped at maxClearance; ~0: inside a wall).
struct EyeCheck {
  std::optional<double> floorDrop;
  double clearance = 0.0;
  // Above a floor within maxDrop and at least minClearance from every surface.
  bool playable(double maxDrop, double minClearance) const {
    return floorDrop && *floorDrop <= maxDrop && clearance >= minClearance;
  }
};
EyeCheck checkEye(const TriangleGrid& grid, const glm::dvec3& eye, double maxClearance = 1.0);

// The fraction of a view that sees nothing within maxDistance (sky or void):
// rays through an n × n grid of pixel centres of a camera at `eye` looking
// along `forward` (up +Y, square image, vertical field of view fovYDeg).
// frontOnly: surfaces the renderer culls (back faces) count as nothing.
double openViewFraction(const TriangleGrid& grid, const glm::dvec3& eye, const glm::dvec3& forward,
                        double fovYDeg, double maxDistance, int n = 16, bool frontOnly = false);

// Distance from p to triangle abc (Ericson, Real-Time Collision Detection §5.1.5).
double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c);

}  // namespace hw::scenes
