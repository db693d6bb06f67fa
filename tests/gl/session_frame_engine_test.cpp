// The frame engine (session/frame_engine.h): a keyframe warped back to its
// own camera is the keyframe; the nearer keyframe is drawn in front, ties to
// the first; the previous frame is what present() leaves; keyframes come and
// go by id; the hole pass under a budget draws what fits it; the
// fill floor is one quad whose warp is the plane's image.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/metrics.h"
#include "keyframe/lod_builder.h"
#include "session/frame_engine.h"
#include "session/presets.h"
#include "tests/gl/gl_fixture.h"
#include "tests/gl/walk_fixture.h"

namespace {

using hw::session::FrameEngine;

class FrameEngineTest : public hw::test::GlTest {};

using hw::test::Built;

Built build(FrameEngine& e, const hw::Camera& cam, const hw::session::WalkOptions& wo) {
  return hw::test::buildKeyframe(e.renderer(), cam, wo.lod);
}

TEST_F(FrameEngineTest, KeyframeWarpedToItsOwnCameraIsTheKeyframe) {
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 128, 11, 10);
  const hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
  auto e = FrameEngine::create(in.scene, wo, false);
  ASSERT_TRUE(e.ok()) << e.error().message;
  FrameEngine& engine = **e;
  const hw::Camera c0 = in.path.cameraAt(0), c10 = in.path.cameraAt(10);
  const Built k0 = build(engine, c0, wo), k10 = build(engine, c10, wo);
  ASSERT_GT(k0.mesh.stats.quads, 1);
  ASSERT_TRUE(engine.upload(0, k0.kf, k0.mesh, c0.eye, nullptr).ok());
  ASSERT_TRUE(engine.upload(10, k10.kf, k10.mesh, c10.eye, nullptr).ok());
  EXPECT_TRUE(engine.has(0) && engine.has(10) && !engine.has(5));

  // At keyframe 0's camera, keyframe 0 is nearer whichever order they are given in.
  for (bool swapped : {false, true}) {
    hw::session::InBetweenStats st;
    int fg = -1;
    ASSERT_TRUE(engine.warp(c0, swapped ? 10 : 0, swapped ? 0 : 10, st, &fg).ok());
    EXPECT_EQ(fg, 0);
    const double p = hw::psnr(engine.frame().colour, k0.kf.colour);
    EXPECT_GT(p, 40.0) << "swapped " << swapped;
    EXPECT_LT(engine.frame().holeFractionBefore, 0.01);
  }
  // A tie (one keyframe under two ids) goes to the first given.
  ASSERT_TRUE(engine.upload(11, k10.kf, k10.mesh, c10.eye, nullptr).ok());
  hw::session::InBetweenStats st;
  int fg = -1;
  ASSERT_TRUE(engine.warp(c0, 11, 10, st, &fg).ok());
  EXPECT_EQ(fg, 11);
  ASSERT_TRUE(engine.warp(c0, 10, 11, st, &fg).ok());
  EXPECT_EQ(fg, 10);
  engine.release(11);
  EXPECT_FALSE(engine.has(11));

  // present(): the frame drawn becomes the previous one; forgetPrevious() drops it.
  EXPECT_FALSE(engine.hasPrevious());
  const hw::Image<hw::Rgba8> drawn = engine.frame().colour;
  engine.present();
  ASSERT_TRUE(engine.hasPrevious());
  EXPECT_EQ(hw::psnr(engine.previous().colour, drawn), INFINITY);
  engine.forgetPrevious();
  EXPECT_FALSE(engine.hasPrevious());

  engine.releaseBefore(10);
  EXPECT_FALSE(engine.has(0));
  EXPECT_TRUE(engine.has(10));
}

TEST_F(FrameEngineTest, BudgetedHolePassDrawsNoMoreThanTheFullOne) {
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 128, 21, 20);
  hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
  auto e = FrameEngine::create(in.scene, wo, false);
  ASSERT_TRUE(e.ok()) << e.error().message;
  FrameEngine& engine = **e;
  const hw::Camera c0 = in.path.cameraAt(0), c20 = in.path.cameraAt(20),
                   mid = in.path.cameraAt(10);
  const Built k0 = build(engine, c0, wo), k20 = build(engine, c20, wo);
  ASSERT_TRUE(engine.upload(0, k0.kf, k0.mesh, c0.eye, nullptr).ok());
  ASSERT_TRUE(engine.upload(20, k20.kf, k20.mesh, c20.eye, nullptr).ok());
  hw::session::InBetweenStats st;
  ASSERT_TRUE(engine.warp(mid, 0, 20, st, nullptr).ok());
  ASSERT_GT(engine.frame().holeFractionBefore, 0.0) << "the test needs a frame with holes";
  hw::session::HolePassResult all;
  ASSERT_TRUE(engine.renderHoles(mid, nullptr, &all).ok());
  EXPECT_GT(all.drawn, 0);
  EXPECT_EQ(all.drawn, all.wanted);
  // Again, so that the cost model has a measurement (it leaves out the first).
  ASSERT_TRUE(engine.warp(mid, 0, 20, st, nullptr).ok());
  ASSERT_TRUE(engine.renderHoles(mid, nullptr, &all).ok());

  ASSERT_TRUE(engine.warp(mid, 0, 20, st, nullptr).ok());
  // A budget no rectangle fits: one drawn (the cost model keeps learning),
  // the others over it.
  hw::session::HoleBudget none{0.5, 1e-6, 0};
  hw::session::HolePassResult capped;
  double budgetMs = 0;
  ASSERT_TRUE(engine.renderHoles(mid, &none, &capped, &budgetMs).ok());
  EXPECT_EQ(capped.wanted, all.wanted);
  EXPECT_LE(capped.drawn, 1);
  EXPECT_NEAR(budgetMs, 0.5e-6, 1e-12);
  // No cap (fraction 0): as without a budget.
  ASSERT_TRUE(engine.warp(mid, 0, 20, st, nullptr).ok());
  hw::session::HoleBudget off{0, 100, 0};
  hw::session::HolePassResult uncapped;
  ASSERT_TRUE(engine.renderHoles(mid, &off, &uncapped, &budgetMs).ok());
  EXPECT_EQ(uncapped.drawn, all.drawn);
  EXPECT_TRUE(std::isnan(budgetMs));
}

TEST_F(FrameEngineTest, HoleRectsMaxCapsTheRectanglesFound) {
  // Keyframes far apart on a short path: disocclusions in many places.
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 256, 61, 20);
  const hw::Camera c0 = in.path.cameraAt(0), c10 = in.path.cameraAt(20),
                   mid = in.path.cameraAt(10);
  int found[3] = {0, 0, 0};
  const int caps[3] = {0, 12, 2};
  for (int k = 0; k < 3; ++k) {
    hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
    wo.holeRectsMax = caps[k];
    auto e = FrameEngine::create(in.scene, wo, false);
    ASSERT_TRUE(e.ok()) << e.error().message;
    FrameEngine& engine = **e;
    const Built k0 = build(engine, c0, wo), k10 = build(engine, c10, wo);
    ASSERT_TRUE(engine.upload(0, k0.kf, k0.mesh, c0.eye, nullptr).ok());
    ASSERT_TRUE(engine.upload(10, k10.kf, k10.mesh, c10.eye, nullptr).ok());
    hw::session::InBetweenStats st;
    ASSERT_TRUE(engine.warp(mid, 0, 10, st, nullptr).ok());
    hw::session::HolePassResult r;
    ASSERT_TRUE(engine.renderHoles(mid, nullptr, &r).ok());
    EXPECT_EQ(r.drawn, r.wanted);
    found[k] = r.wanted;
  }
  // The test needs a frame with more rectangles than the default cap.
  ASSERT_GT(found[0], 12) << "uncapped: " << found[0];
  EXPECT_EQ(found[1], 12);
  EXPECT_EQ(found[2], 2);
}

TEST_F(FrameEngineTest, FloorLeavesTheFramesAlone) {
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 96, 11, 10);
  const hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
  auto e = FrameEngine::create(in.scene, wo, false);
  ASSERT_TRUE(e.ok()) << e.error().message;
  FrameEngine& engine = **e;
  const hw::Camera c0 = in.path.cameraAt(0);
  ASSERT_TRUE(engine.drawGeometry(c0, nullptr).ok());
  const hw::Image<hw::Rgba8> before = engine.frame().colour;
  hw::session::FloorTimes ft;
  ASSERT_TRUE(engine.measureFloor(c0, 3, &ft).ok());
  EXPECT_EQ(ft.reps, 3);
  EXPECT_GT(ft.oneLayerMs, 0.0);
  EXPECT_GT(ft.twoLayersMs, 0.0);
  EXPECT_EQ(hw::psnr(engine.frame().colour, before), INFINITY);
  EXPECT_FALSE(engine.hasPrevious());
}

}  // namespace
