// The default walk through a model file (scenes/floor_walk.h): inside a
// roofed level it walks the floor under the roof at eye height, keeps clear
// of walls and pillars and never stands on the roof; a scene without floor
// is an error (the caller's orbit fallback).
#include <gtest/gtest.h>

#include "scenes/floor_walk.h"
#include "scenes/outdoor_scenes.h"

namespace hw::scenes {
namespace {

Scene roofedLevel() {
  Scene s;
  s.name = "level";
  s.materials.push_back(Material{});
  Mesh m;
  appendBox(m, {-20, -0.5f, -20}, {20, 0, 20});     // floor
  appendBox(m, {-20, 4, -20}, {20, 4.5f, 20});      // roof over all of it
  appendBox(m, {-20.5f, 0, -20}, {-20, 4, 20});     // walls
  appendBox(m, {20, 0, -20}, {20.5f, 4, 20});
  appendBox(m, {-20, 0, -20.5f}, {20, 4, -20});
  appendBox(m, {-20, 0, 20}, {20, 4, 20.5f});
  appendBox(m, {-1, 0, -1}, {1, 4, 1});             // a pillar
  appendBox(m, {-20, 0, 5}, {10, 4, 6});            // a wall across, with a gap at x > 10
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
    EXPECT_NEAR(cams[k].forward.y, 0.0, 1e-6);
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

}  // namespace
}  // namespace hw::scenes
