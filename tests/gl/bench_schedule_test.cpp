// Error-driven keyframes on OSMesa: the probe's features vanish at a
// keyframe's own camera and grow away from it; an adaptive walk on a short
// indoor path uses fewer keyframes than the fixed schedule at a lax target
// and more at a strict one, and the strict plan's frames are better.
#include <gtest/gtest.h>

#include <filesystem>

#include "bench/schedule_oracle.h"
#include "session/walk.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "session/keyframe_planner.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class ScheduleTest : public test::GlTest {
 protected:
  static scenes::CameraPath shortPath() {
    scenes::CameraPath p = scenes::defaultIndoorPath();
    p.width = p.height = 128;
    p.frames = 40;
    p.keyframeEvery = 10;  // 5 keyframes: 0, 10, 20, 30, 39
    return p;
  }
};

TEST_F(ScheduleTest, ProbeFeaturesVanishAtTheKeyframeAndGrowAwayFromIt) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = shortPath();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  session::KeyframeProbe probe(
      **r, [&](int i) { return path.cameraAt(i); }, 64);
  // Frame 0 seen from keyframes 0 and 39: the first one covers it exactly.
  auto at = probe.features(0, 39, 0);
  ASSERT_TRUE(at.ok()) << at.error().message;
  EXPECT_EQ(at->holeFraction, 0.0);
  EXPECT_EQ(at->relDistance, 0.0);
  EXPECT_NEAR(at->angleDeg, 0.0, 1e-6);
  EXPECT_LT(at->stretch, 0.05);
  // Farther from both keyframes: more of the frame is uncovered.
  auto nearF = probe.features(0, 4, 2);
  auto farF = probe.features(0, 39, 20);
  ASSERT_TRUE(nearF.ok() && farF.ok());
  EXPECT_GT(farF->relDistance, nearF->relDistance);
  EXPECT_GT(farF->holeFraction, nearF->holeFraction);
  EXPECT_EQ(probe.probesRendered(), 3);  // 0, 39, 4: probes are kept
}

TEST_F(ScheduleTest, LaxTargetUsesFewerKeyframesThanFixedAndStrictMoreWithBetterFrames) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = shortPath();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto cameraOf = [&](int i) { return path.cameraAt(i); };

  session::WalkOptions wo;
  wo.progress = false;
  wo.strips = 0;
  auto fixed = session::runWalk(scene, "indoor", path, wo);
  ASSERT_TRUE(fixed.ok()) << fixed.error().message;
  const int fixedKeys = fixed->report["summary"]["keyframes"].get<int>();
  ASSERT_EQ(fixedKeys, 5);

  session::PlannerOptions po;
  po.minGap = 2;
  po.maxGap = 30;
  po.targetPsnrDb = 10;  // lax
  auto lax = session::planAdaptiveSchedule(**r, cameraOf, path.frames, po);
  ASSERT_TRUE(lax.ok()) << lax.error().message;
  po.targetPsnrDb = 40;  // strict
  auto strict = session::planAdaptiveSchedule(**r, cameraOf, path.frames, po);
  ASSERT_TRUE(strict.ok()) << strict.error().message;
  EXPECT_GT(lax->probes, 0);
  EXPECT_GT(lax->evaluations, 0);

  wo.keyframeFrames = lax->keyframes;
  auto laxWalk = session::runWalk(scene, "indoor", path, wo);
  ASSERT_TRUE(laxWalk.ok()) << laxWalk.error().message;
  wo.keyframeFrames = strict->keyframes;
  auto strictWalk = session::runWalk(scene, "indoor", path, wo);
  ASSERT_TRUE(strictWalk.ok()) << strictWalk.error().message;
  const auto& ls = laxWalk->report["summary"];
  const auto& ss = strictWalk->report["summary"];
  EXPECT_EQ(ls["keyframe_frames"].get<std::vector<int>>(), lax->keyframes);
  EXPECT_LT(ls["keyframes"].get<int>(), fixedKeys);
  EXPECT_GT(ss["keyframes"].get<int>(), fixedKeys);
  EXPECT_GT(ss["psnr"]["median"].get<double>(), ls["psnr"]["median"].get<double>() + 3.0);
  EXPECT_GT(ss["psnr"]["p5"].get<double>(), ls["psnr"]["p5"].get<double>());
}

// The oracle's table is the walk: a fixed schedule scored from the table has
// the walk's own median, and the oracle's schedule, walked, has exactly the
// median the table promised, reached with no more keyframes than fixed.
TEST_F(ScheduleTest, OracleTableScoresSchedulesExactlyAsTheWalkDoes) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  scenes::CameraPath path = shortPath();
  path.frames = 25;
  bench::ScheduleOracleOptions oo;
  oo.outDir = ::testing::TempDir() + "hw_oracle_test";
  oo.maxGap = 5;
  oo.fixedSpacings = {2, 3, 4, 5};
  oo.referenceSpacing = 4;
  oo.progress = false;
  auto doc = bench::runScheduleOracle(scene, "indoor:20k", path, oo);
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const auto& h = (*doc)["headline"];
  ASSERT_TRUE(h["reference_walk_psnr_median"].is_number());
  EXPECT_EQ(h["reference_walk_psnr_median"].get<double>(), h["reference_psnr_median"].get<double>());
  EXPECT_EQ((*doc)["walks"].get<int>(), 14);
  for (const char* f : {"oracle.json", "oracle.csv", "oracle.png", "segments.csv"})
    EXPECT_TRUE(std::filesystem::is_regular_file(oo.outDir + "/" + f)) << f;
  int checked = 0;
  for (const auto& row : (*doc)["fixed"]) {
    ASSERT_TRUE(row["oracle_keyframes"].is_number()) << row.dump();
    EXPECT_LE(row["oracle_keyframes"].get<int>(), row["fixed_keyframes"].get<int>());
    EXPECT_GE(row["oracle_psnr_median"].get<double>(), row["fixed_psnr_lower_median"].get<double>());
    session::WalkOptions wo;
    wo.progress = false;
    wo.strips = 0;
    wo.keyframeFrames = row["oracle_schedule"].get<std::vector<int>>();
    auto walked = session::runWalk(scene, "indoor", path, wo);
    ASSERT_TRUE(walked.ok()) << walked.error().message;
    EXPECT_EQ(walked->report["summary"]["psnr"]["median"].get<double>(),
              row["oracle_psnr_median"].get<double>());
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

}  // namespace
}  // namespace hw
