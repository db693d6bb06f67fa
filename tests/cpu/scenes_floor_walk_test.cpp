// The default walk through a model file (scenes/floor_walk.h): inside a
// roofed level it walks the floor under the roof at eye height, keeps clear
// of walls and pillars and never stands on the roof; a scene without floor
// is an error (the caller's orbit fallback).
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "scenes/floor_walk.h"
#include "scenes/outdoor_scenes.h"
#include "scenes/q3bsp.h"

namespace hw::scenes {
namespace {

Scene roofedLevel() {
  Scene s;
  s.name = "level";
  s.materials.push_back(Material{});
  Mesh m;
  appendBox(m, {-20, -0.5f, -20}, {20, 0, 20});  // floor
  appendBox(m, {-20, 4, -20}, {20, 4.5f, 20});   // roof over all of it
  appendBox(m, {-20.5f, 0, -20}, {-20, 4, 20});  // walls
  appendBox(m, {20, 0, -20}, {20.5f, 4, 20});
  appendBox(m, {-20, 0, -20.5f}, {20, 4, -20});
  appendBox(m, {-20, 0, 20}, {20, 4, 20.5f});
  appendBox(m, {-1, 0, -1}, {1, 4, 1});   // a pillar
  appendBox(m, {-20, 0, 5}, {10, 4, 6});  // a wall across, with a gap at x > 10
  m.computeBounds();
  s.meshes.push_back(std::move(m));
  s.computeBounds();
  return s;
}

TEST(FloorWalk, WalksTheFloorUnderTheRoofAtEyeHeight) {
  const Scene s = roofedLevel();
  FloorWalkOptions o;
  o.eyeHeight = 1.7;
  auto p = floorWalkPath(s, o);
  ASSERT_TRUE(p.ok()) << p.error().message;
  const TriangleGrid grid(s, 1.0);
  const auto cams = p->cameras();
  double travelled = 0;
  for (std::size_t k = 0; k < cams.size(); ++k) {
    const glm::dvec3 e = cams[k].eye;
    EXPECT_NEAR(e.y, 1.7, 0.05) << "frame " << k;  // on the floor, not on the roof (6.2)
    EXPECT_GT(e.x, -20);
    EXPECT_LT(e.x, 20);
    EXPECT_GT(e.z, -20);
    EXPECT_LT(e.z, 20);
    const EyeCheck c = checkEye(grid, e, 1.0);
    ASSERT_TRUE(c.floorDrop.has_value());
    EXPECT_NEAR(*c.floorDrop, 1.7, 0.05);
    EXPECT_GT(c.clearance, 0.2) << "frame " << k << " at " << e.x << "," << e.z;
    // Looking along the way, level.
    EXPECT_NEAR(cams[k].forward.y, 0.0, 1e-6);  // under a roof: never needs to look down
    if (k) travelled += glm::length(e - cams[k - 1].eye);
  }
  // The route crosses the level (its longest shortest path): through the
  // gap in the cross wall, so well over the 40 m of one side.
  EXPECT_GT(travelled, 40.0);
}

TEST(FloorWalk, EyeHeightFromTheSceneSize) {
  Scene s = roofedLevel();
  auto p = floorWalkPath(s);  // 41 m across: min(0.05 × 41, 1.7) = 1.7
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_NEAR(p->cameraAt(0).eye.y, 1.7, 0.05);
}

TEST(FloorWalk, NoFloorIsAnError) {
  Scene s;
  s.name = "wall";
  s.materials.push_back(Material{});
  Mesh m;
  m.vertices = {{{0, 0, 0}}, {{1, 0, 0}}, {{1, 1, 0}}, {{0, 1, 0}}};  // a vertical quad
  m.indices = {0, 1, 2, 0, 2, 3};
  m.computeBounds();
  s.meshes.push_back(std::move(m));
  s.computeBounds();
  auto p = floorWalkPath(s);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().message.find("wall: no"), std::string::npos) << p.error().message;
}

// TriangleGrid::rayHit against testing every triangle, on the level from
// random eyes in random directions; and the open view fraction of a camera
// inside the roofed level (0) and one above it looking up (1).
TEST(FloorWalk, RayHitMatchesBruteForceAndOpenViews) {
  const Scene s = roofedLevel();
  const TriangleGrid grid(s, 1.5);
  std::vector<std::array<glm::dvec3, 3>> tris;
  for (const Mesh& m : s.meshes)
    for (std::size_t i = 0; i < m.indices.size(); i += 3)
      tris.push_back({glm::dvec3(m.vertices[m.indices[i]].position),
                      glm::dvec3(m.vertices[m.indices[i + 1]].position),
                      glm::dvec3(m.vertices[m.indices[i + 2]].position)});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-25, 25), d(-1, 1);
  for (int k = 0; k < 300; ++k) {
    const glm::dvec3 o(u(rng), 0.5 * u(rng) + 2, u(rng));
    glm::dvec3 dir(d(rng), d(rng), d(rng));
    if (glm::length(dir) < 0.1) continue;
    dir = glm::normalize(dir);
    double best = 1e300;
    for (const auto& t : tris) {  // Möller–Trumbore, both sides
      const glm::dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0], p = glm::cross(dir, e2);
      const double det = glm::dot(e1, p);
      if (std::abs(det) < 1e-14) continue;
      const glm::dvec3 sv = o - t[0];
      const double a = glm::dot(sv, p) / det;
      const glm::dvec3 q = glm::cross(sv, e1);
      const double b = glm::dot(dir, q) / det;
      const double tt = glm::dot(e2, q) / det;
      if (a >= 0 && b >= 0 && a + b <= 1 && tt > 1e-9) best = std::min(best, tt);
    }
    const auto hit = grid.rayHit(o, dir, 100.0);
    if (best <= 100.0) {
      ASSERT_TRUE(hit.has_value()) << k;
      EXPECT_NEAR(*hit, best, 1e-6) << k;
    } else {
      EXPECT_FALSE(hit.has_value()) << k << " " << *hit;
    }
  }
  EXPECT_EQ(openViewFraction(grid, {10, 1.7, -10}, {1, 0, 0}, 60, 1000), 0.0);
  EXPECT_EQ(openViewFraction(grid, {0, 10, 0}, {0, 1, 0.01}, 60, 1000), 1.0);
}

// A spawn exactly over the floor's edge (Quake units → metres in double,
// the floor's vertices in float) is above the floor: from oa_pvomit, where
// it fell through by rounding, 1e-7 m outside the float edge.
TEST(FloorWalk, HitsBelowOnTheFloorsEdge) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh m;
  m.vertices = {{{-1.2192f, -4.064f, -34.9504f}},
                {{-1.2192f, -4.064f, -39.8272f}},
                {{-2.6416f, -4.064f, -34.9504f}},
                {{-2.6416f, -4.064f, -39.8272f}},
                // the lower floor beyond the step, further out
                {{-9.0f, -5.0f, -30.0f}},
                {{-9.0f, -5.0f, -45.0f}},
                {{-8.0f, -5.0f, -30.0f}}};
  m.indices = {0, 1, 2, 1, 3, 2, 4, 5, 6};
  m.computeBounds();
  s.meshes.push_back(std::move(m));
  s.computeBounds();
  const TriangleGrid grid(s, 2.0);
  const glm::dvec3 spawn(-104 * kQ3MetresPerUnit, 0.0, -1544 * kQ3MetresPerUnit);
  ASSERT_FALSE(grid.hitsBelow(spawn).empty());
  EXPECT_NEAR(grid.hitsBelow(spawn)[0], -4.064, 1e-6);
  // Well outside the edge (1 mm) is not.
  EXPECT_TRUE(grid.hitsBelow(spawn - glm::dvec3(0.001, 0, 0)).empty());
}

}  // namespace
}  // namespace hw::scenes
