// ModeChooser (walk --mode auto): warp a segment only when its predicted cost
// per frame is clearly below the geometry frame's, with hysteresis.
#include "session/frame_mode.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hw::session {
namespace {

TEST(FrameMode, NamesRoundTrip) {
  for (FrameMode m : {FrameMode::Auto, FrameMode::Hybrid, FrameMode::Geometry}) {
    FrameMode back = FrameMode::Auto;
    ASSERT_TRUE(parseFrameMode(frameModeName(m), &back));
    EXPECT_EQ(back, m);
  }
  FrameMode m = FrameMode::Hybrid;
  EXPECT_FALSE(parseFrameMode("Auto", &m));
  EXPECT_FALSE(parseFrameMode("", &m));
  EXPECT_EQ(m, FrameMode::Hybrid);
  EXPECT_STREQ(frameKindName(FrameKind::Geometry), "geometry");
  EXPECT_STREQ(frameKindName(FrameKind::Warp), "warp");
  EXPECT_STREQ(frameKindName(FrameKind::Keyframe), "keyframe");
}

TEST(ModeChooser, UnknownCostsKeepTheCurrentChoice) {
  ModeChooser c;
  EXPECT_TRUE(std::isnan(c.predictedWarpMs(10)));
  EXPECT_TRUE(c.warpNext(true, 10));
  EXPECT_FALSE(c.warpNext(false, 10));
  c.addGeometryMs(10);  // still no in-between cost
  EXPECT_FALSE(c.warpNext(false, 10));
  EXPECT_TRUE(c.warpNext(true, 10));
}

TEST(ModeChooser, TheFloorDecidesBeforeAnyWarp) {
  ModeChooser light;
  light.addGeometryMs(2);
  light.setWarpFloorMs(3);  // a warp costs more than drawing: never warp
  EXPECT_FALSE(light.warpNext(false, 10));
  ModeChooser heavy;
  heavy.addGeometryMs(40);
  heavy.setWarpFloorMs(3);
  // (9 x 3 + 40) / 10 = 6.7 ms per frame against 40.
  EXPECT_DOUBLE_EQ(heavy.predictedWarpMs(10), 6.7);
  EXPECT_TRUE(heavy.warpNext(false, 10));
  // Measured in-between frames replace the floor.
  heavy.addInBetweenMs(50);
  EXPECT_DOUBLE_EQ(heavy.inBetweenMs(), 50);
  EXPECT_FALSE(heavy.warpNext(true, 10));
}

TEST(ModeChooser, KeyframeFramesAreAmortisedOverTheSegment) {
  ModeChooser c;
  c.addGeometryMs(10);
  c.addInBetweenMs(5);
  c.addKeyframeMs(50);
  EXPECT_DOUBLE_EQ(c.predictedWarpMs(10), (9 * 5 + 50) / 10.0);  // 9.5: not worth it
  EXPECT_FALSE(c.warpNext(false, 10));
  EXPECT_FALSE(c.warpNext(true, 10));
  EXPECT_DOUBLE_EQ(c.predictedWarpMs(100), (99 * 5 + 50) / 100.0);  // 5.45
  EXPECT_TRUE(c.warpNext(false, 100));
  EXPECT_DOUBLE_EQ(c.predictedWarpMs(1), 50);  // a one-frame segment: the keyframe alone
}

TEST(ModeChooser, HysteresisBetweenEnteringAndLeaving) {
  ModeChooserOptions o;
  o.enterBelow = 0.75;
  o.leaveAbove = 0.9;
  ModeChooser c(o);
  c.addGeometryMs(10);
  c.addInBetweenMs(8);
  c.addKeyframeMs(8);  // 8 ms per frame: 0.8 of the geometry
  EXPECT_FALSE(c.warpNext(false, 10));  // not below 0.75: stay with geometry
  EXPECT_TRUE(c.warpNext(true, 10));    // not above 0.9: keep warping
  // About even: the exact geometry wins from either side.
  ModeChooser even(o);
  even.addGeometryMs(10);
  even.addInBetweenMs(9.5);
  even.addKeyframeMs(9.5);
  EXPECT_FALSE(even.warpNext(false, 10));
  EXPECT_FALSE(even.warpNext(true, 10));
}

TEST(ModeChooser, MediansOfRecentSamplesIgnoreOutliersAndForgetOldOnes) {
  ModeChooser c;
  for (int i = 0; i < 6; ++i) c.addGeometryMs(10);
  c.addGeometryMs(500);  // one slow frame
  EXPECT_DOUBLE_EQ(c.geometryMs(), 10);
  c.addGeometryMs(std::nan(""));  // ignored
  c.addGeometryMs(-1);            // ignored
  EXPECT_DOUBLE_EQ(c.geometryMs(), 10);
  for (std::size_t i = 0; i < ModeChooser::kWindow; ++i) c.addGeometryMs(30);
  EXPECT_DOUBLE_EQ(c.geometryMs(), 30);  // the window moved on
  ModeChooser even;
  even.addInBetweenMs(4);
  even.addInBetweenMs(6);
  EXPECT_DOUBLE_EQ(even.inBetweenMs(), 5);  // even count: mean of the middle two
}

}  // namespace
}  // namespace hw::session
