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

TEST(ModeChooser, SlowInBetweenFramesKeepTheGeometryEvenWhenTheMeanPays) {
  // 15 in-between frames: 12 at 5 ms, 3 at 14 ms (a keyframe built alongside
  // on the same cores). Mean per frame pays (well below 0.75 x 10 ms), but the
  // 90th percentile is 14 ms, slower than drawing: geometry.
  ModeChooser c;
  c.addGeometryMs(10);
  c.addKeyframeMs(5);
  for (int i = 0; i < 12; ++i) c.addInBetweenMs(5);
  for (int i = 0; i < 3; ++i) c.addInBetweenMs(14);
  EXPECT_DOUBLE_EQ(c.inBetweenMs(), 5);
  EXPECT_DOUBLE_EQ(c.inBetweenTailMs(), 14);  // 0.9 x 14 = order statistic 12.6 of 0..14
  EXPECT_LT(c.predictedWarpMs(10), 7.5);
  EXPECT_FALSE(c.warpNext(false, 10));
  EXPECT_FALSE(c.warpNext(true, 10));  // above 1.1 x 10 too
  // The same frames with a tail allowed up to 1.5x: warp.
  ModeChooserOptions loose;
  loose.tailEnterBelow = loose.tailLeaveAbove = 1.5;
  ModeChooser l(loose);
  l.addGeometryMs(10);
  l.addKeyframeMs(5);
  for (int i = 0; i < 12; ++i) l.addInBetweenMs(5);
  for (int i = 0; i < 3; ++i) l.addInBetweenMs(14);
  EXPECT_TRUE(l.warpNext(false, 10));
}

TEST(ModeChooser, TailHysteresis) {
  ModeChooser c;  // tail: enter below 1.0x, leave above 1.1x
  c.addGeometryMs(10);
  c.addKeyframeMs(2);
  for (int i = 0; i < 12; ++i) c.addInBetweenMs(2);
  for (int i = 0; i < 3; ++i) c.addInBetweenMs(10.5);  // tail between 1.0x and 1.1x
  EXPECT_GT(c.inBetweenTailMs(), 10);
  EXPECT_LT(c.inBetweenTailMs(), 11);
  EXPECT_FALSE(c.warpNext(false, 10));
  EXPECT_TRUE(c.warpNext(true, 10));
}

TEST(ModeChooser, QuantilesInterpolateBetweenOrderStatistics) {
  ModeChooser c;
  for (double v : {1.0, 2.0, 3.0, 4.0, 5.0}) c.addInBetweenMs(v);
  EXPECT_DOUBLE_EQ(c.inBetweenMs(), 3);
  EXPECT_DOUBLE_EQ(c.inBetweenTailMs(), 4.6);  // 0.9 x 4 = 3.6: 4 + 0.6 x (5 - 4)
  ModeChooser one;
  one.setWarpFloorMs(3);
  EXPECT_DOUBLE_EQ(one.inBetweenTailMs(), 3);  // the floor until one is measured
  one.addInBetweenMs(7);
  EXPECT_DOUBLE_EQ(one.inBetweenTailMs(), 7);
}

TEST(ModeChooser, AWarpedSegmentWhoseFirstFramesAllCostMoreIsGivenUp) {
  ModeChooser c;
  c.addGeometryMs(10);
  c.startSegment();
  EXPECT_FALSE(c.giveUp());  // nothing measured yet
  c.addInBetweenMs(30);
  EXPECT_FALSE(c.giveUp());  // one frame (it may carry an upload) is not enough
  c.addInBetweenMs(10.5);    // within 1.1 x the geometry frame
  EXPECT_FALSE(c.giveUp());
  c.startSegment();
  c.addInBetweenMs(30);
  c.addInBetweenMs(11.5);  // both above 11 ms
  EXPECT_TRUE(c.giveUp());
  c.addInBetweenMs(4);  // a cheap one later in the segment clears it
  EXPECT_FALSE(c.giveUp());
  // A new segment starts counting again; unknown geometry never gives up.
  c.startSegment();
  EXPECT_FALSE(c.giveUp());
  ModeChooser unknown;
  unknown.addInBetweenMs(100);
  unknown.addInBetweenMs(100);
  EXPECT_FALSE(unknown.giveUp());
  // giveUpAfter 0 turns it off.
  ModeChooserOptions off;
  off.giveUpAfter = 0;
  ModeChooser never(off);
  never.addGeometryMs(1);
  never.addInBetweenMs(100);
  never.addInBetweenMs(100);
  EXPECT_FALSE(never.giveUp());
}

TEST(ModeChooser, GeometryCostFollowsTheLastFewSamples) {
  // A view that grows heavier: ten geometry frames at 8 ms, then five at
  // 30 ms. The whole window's median is still 8 ms; the last five say 30.
  ModeChooser c;
  for (int i = 0; i < 10; ++i) c.addGeometryMs(8);
  for (int i = 0; i < 5; ++i) c.addGeometryMs(30);
  EXPECT_DOUBLE_EQ(c.geometryWindowMs(), 8);
  EXPECT_DOUBLE_EQ(c.geometryMs(), 30);
  // A warped frame at 9 ms now pays (9 < 0.75 x 30); by the window it would not.
  c.addInBetweenMs(9);
  c.addKeyframeMs(9);
  EXPECT_TRUE(c.warpNext(false, 10));
  ModeChooserOptions whole;
  whole.geometryRecent = ModeChooser::kWindow;
  ModeChooser w(whole);
  for (int i = 0; i < 10; ++i) w.addGeometryMs(8);
  for (int i = 0; i < 5; ++i) w.addGeometryMs(30);
  w.addInBetweenMs(9);
  w.addKeyframeMs(9);
  EXPECT_DOUBLE_EQ(w.geometryMs(), 8);
  EXPECT_FALSE(w.warpNext(false, 10));
  // Fewer samples than asked for: the median of those there are; the ring
  // buffer's wrap keeps the newest.
  ModeChooser few;
  few.addGeometryMs(4);
  few.addGeometryMs(6);
  EXPECT_DOUBLE_EQ(few.geometryMs(), 5);
  for (std::size_t i = 0; i < ModeChooser::kWindow + 3; ++i) few.addGeometryMs(100);
  few.addGeometryMs(1);
  few.addGeometryMs(2);
  few.addGeometryMs(3);
  EXPECT_DOUBLE_EQ(few.geometryMs(), 3);  // 100, 100, 1, 2, 3
}


TEST(ModeChooser, GeometryCostIsInterpolatedInTheViewsTriangles) {
  ModeChooser c;
  c.addGeometryMs(10, 100000);
  c.addGeometryMs(30, 200000);
  EXPECT_DOUBLE_EQ(c.geometryAtTriangles(150000), 20);  // between the two
  EXPECT_DOUBLE_EQ(c.geometryAtTriangles(100000), 10);  // on a sample
  EXPECT_DOUBLE_EQ(c.geometryAtTriangles(50000), 7.5);  // below: half fixed, half in proportion
  EXPECT_DOUBLE_EQ(c.geometryAtTriangles(0), 5);        // the fixed half
  EXPECT_DOUBLE_EQ(c.geometryAtTriangles(400000), 60);  // above: in proportion
  EXPECT_TRUE(std::isnan(c.geometryAtTriangles(-1)));
  // Samples within 2 % of each other count as one, their median: 9, 10, 50
  // at about 100k (one frame slowed by something else) give 10.
  c.addGeometryMs(9, 99000);
  c.addGeometryMs(50, 101000);
  EXPECT_DOUBLE_EQ(c.geometryAtTriangles(101000), 10);
  // Samples without a triangle count are left out of it.
  ModeChooser none;
  none.addGeometryMs(10);
  EXPECT_TRUE(std::isnan(none.geometryAtTriangles(1000)));
  none.setViewTriangles(1000);
  EXPECT_DOUBLE_EQ(none.geometryMs(), 10);  // the recent median instead
}

TEST(ModeChooser, AHeavyStretchDoesNotStandForTheLighterViewsAfterIt) {
  // The morse trees path: views of 160k triangles at 20 ms, then five of
  // 250-270k at 50-100 ms; later, one probe at 120k triangles takes 14 ms.
  // The last five samples' median is still 65 ms; the view of 125k now is
  // between the probe and the 160k views.
  auto feed = [](ModeChooser& c) {
    for (int i = 0; i < 6; ++i) c.addGeometryMs(20, 160000);
    c.addGeometryMs(30, 209000);
    c.addGeometryMs(65, 249000);
    c.addGeometryMs(93, 266000);
    c.addGeometryMs(100, 271000);
    c.addGeometryMs(14, 121000);
    c.addInBetweenMs(15);  // warped frames of this path cost about that
    c.addKeyframeMs(15);
    c.setViewTriangles(125000);
  };
  ModeChooser c;
  feed(c);
  EXPECT_DOUBLE_EQ(c.geometryRecentMs(), 65);
  EXPECT_NEAR(c.geometryMs(), 14 + 6 * (125000.0 - 121000) / (160000 - 121000), 1e-9);
  EXPECT_FALSE(c.warpNext(true, 10));  // warping stops: 15 ms is over 0.9 x 14.6
  ModeChooserOptions recentOnly;
  recentOnly.geometryByTriangles = false;
  ModeChooser r(recentOnly);
  feed(r);
  EXPECT_DOUBLE_EQ(r.geometryMs(), 65);
  EXPECT_TRUE(r.warpNext(true, 10));  // the stale estimate keeps warping
  // A view as heavy as the heavy stretch is predicted as heavy before it is drawn.
  c.setViewTriangles(266000);
  EXPECT_DOUBLE_EQ(c.geometryMs(), 93);
  EXPECT_TRUE(c.warpNext(false, 10));
}


}  // namespace
}  // namespace hw::session
