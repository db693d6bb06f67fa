// A walk under a memory budget too small for one keyframe at its
// resolution: a walk that warps is refused before anything of that size is
// drawn (the fill floor's keyframe included), naming the first keyframe; a
// geometry walk runs without the floor. Either way nothing stays charged.
#include <gtest/gtest.h>

#include "core/memory_budget.h"
#include "gl_fixture.h"
#include "scenes/procedural.h"
#include "session/walk.h"

namespace hw {
namespace {

class WalkMemoryTest : public test::GlTest {
 protected:
  void TearDown() override { setMemoryBudget(0); }
};

session::WalkOptions smallWalk(session::FrameMode mode) {
  session::WalkOptions o;
  o.mode = mode;
  o.maxFrames = 3;
  o.progress = false;
  return o;
}

TEST_F(WalkMemoryTest, AWarpingWalkIsRefusedBeforeTheFloorIsDrawn) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  const std::uint64_t before = memoryCharged();
  // Room for the scene, not for a 512x512 keyframe (4.2 MiB).
  setMemoryBudget(before + (std::uint64_t{2} << 20));
  auto res = session::runWalk(scene, "indoor", path, smallWalk(session::FrameMode::Hybrid));
  ASSERT_FALSE(res.ok());
  EXPECT_NE(res.error().message.find("keyframe of frame 0: 512x512 colour and depth"),
            std::string::npos)
      << res.error().message;
  EXPECT_EQ(memoryCharged(), before);
}

TEST_F(WalkMemoryTest, AGeometryWalkRunsWithoutTheFloor) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  const std::uint64_t before = memoryCharged();
  setMemoryBudget(before + (std::uint64_t{2} << 20));
  auto res = session::runWalk(scene, "indoor", path, smallWalk(session::FrameMode::Geometry));
  ASSERT_TRUE(res.ok()) << res.error().message;
  const auto& floor = res->report["summary"]["floor_ms"];
  EXPECT_TRUE(floor["one_layer"].is_null());
  EXPECT_TRUE(floor["two_layers"].is_null());
  EXPECT_EQ(floor["draws"].get<int>(), 0);
  EXPECT_EQ(res->report["frames"].size(), 3u);
  EXPECT_EQ(memoryCharged(), before);

  // With room for it, the same walk measures the floor.
  setMemoryBudget(0);
  auto roomy = session::runWalk(scene, "indoor", path, smallWalk(session::FrameMode::Geometry));
  ASSERT_TRUE(roomy.ok()) << roomy.error().message;
  EXPECT_GT(roomy->report["summary"]["floor_ms"]["two_layers"].get<double>(), 0.0);
  EXPECT_EQ(memoryCharged(), before);
}

}  // namespace
}  // namespace hw
