// app/keyframe_pacing.h: when the async viewer requests the keyframe after
// the newest one, how far ahead, and how many frames its worker spreads a
// keyframe over. The viewer used to request only after passing the newest
// keyframe and to pace the worker over half the path's keyframe_every
// whatever the viewer's speed, which stalled it in turns (5-7 per 120-frame
// indoor run); these pin the rules that replaced that.
#include <gtest/gtest.h>

#include <cmath>

#include "app/keyframe_pacing.h"

namespace hw::app {
namespace {

constexpr double kNone = 1e300;  // no older keyframe

TEST(EarlyAheadDistance, RequestsBeforeTheViewerReachesTheNewest) {
  // Half way rule: nearer the newest (0.4) than the older (0.8): request,
  // 1.25 beyond the newest = 1.65 from a viewer approaching it.
  EXPECT_DOUBLE_EQ(earlyAheadDistance(0.4, 0.8, false, 1.25, 0.5), 1.65);
  // Still nearer the older one: not yet at 0.5, already at 0.25 and at 0.
  EXPECT_EQ(earlyAheadDistance(0.8, 0.4, false, 1.25, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(earlyAheadDistance(0.8, 0.4, false, 1.25, 0.25), 2.05);
  EXPECT_DOUBLE_EQ(earlyAheadDistance(1.2, 0.05, false, 1.25, 0.0), 2.45);
  // The old rule requested only once the viewer was receding from the
  // newest by more than 0.25; this one requests while approaching it.
  EXPECT_GT(earlyAheadDistance(0.3, 0.9, false, 1.25, 0.5), 0.0);
}

TEST(EarlyAheadDistance, PastTheNewestTheSpacingCountsFromIt) {
  EXPECT_DOUBLE_EQ(earlyAheadDistance(0.2, 1.0, true, 1.25, 0.5), 1.05);
  // Past it, the older keyframe does not hold the request back.
  EXPECT_DOUBLE_EQ(earlyAheadDistance(0.2, 0.1, true, 1.25, 0.5), 1.05);
  // Already a spacing past it: nothing ahead to place (the synchronous rule
  // takes over).
  EXPECT_EQ(earlyAheadDistance(1.3, 2.0, true, 1.25, 0.5), 0.0);
  // Only one keyframe: any fraction of the way.
  EXPECT_DOUBLE_EQ(earlyAheadDistance(0.5, kNone, false, 1.25, 0.5), 1.75);
}

TEST(EarlyAheadDistance, BadInputRequestsNothing) {
  EXPECT_EQ(earlyAheadDistance(-0.1, 1.0, false, 1.25, 0.5), 0.0);
  EXPECT_EQ(earlyAheadDistance(0.5, 1.0, false, 0.0, 0.5), 0.0);
  EXPECT_EQ(earlyAheadDistance(0.5, 1.0, false, 1.25, std::nan("")), 0.0);
}

TEST(UpdateRequestInterval, FollowsShorterIntervalsAtOnceAndLongerOnesSlowly) {
  EXPECT_DOUBLE_EQ(updateRequestInterval(0.0, 7.0), 7.0);   // first one
  EXPECT_DOUBLE_EQ(updateRequestInterval(5.0, 2.0), 2.0);   // a turn: at once
  EXPECT_DOUBLE_EQ(updateRequestInterval(2.0, 10.0), 4.0);  // a quarter of the way up
  EXPECT_DOUBLE_EQ(updateRequestInterval(4.0, 0.0), 4.0);   // no interval: unchanged
  // A long stop does not leave the estimate far above the interval of the
  // keyframes that follow it.
  double e = 3.0;
  e = updateRequestInterval(e, 200.0);
  e = updateRequestInterval(e, 3.0);
  EXPECT_DOUBLE_EQ(e, 3.0);
}

TEST(WorkerPacingFrames, TheMeasuredIntervalNotHalfTheKeyframeEvery) {
  // Straight: lost 2 s away at 0.1 s a frame (19 frames) is later than the
  // measured interval of 8 frames: pace over 8 (the old rule: 5 for
  // keyframe_every 10, whatever the viewer did).
  EXPECT_DOUBLE_EQ(workerPacingFrames(8.0, 2.0, 0.1, 10.0), 8.0);
  // Turn: 0.75 s a frame and lost 1.5 s away: the keyframe is due before
  // the frame after next, so 1 frame, though the estimate still says 8.
  EXPECT_DOUBLE_EQ(workerPacingFrames(8.0, 1.5, 0.75, 10.0), 1.0);
  EXPECT_DOUBLE_EQ(workerPacingFrames(8.0, 2.25, 0.5, 10.0), 3.5);
  // Standing still: the estimate, capped.
  EXPECT_DOUBLE_EQ(workerPacingFrames(8.0, 1.5, 0.0, 10.0), 8.0);
  EXPECT_DOUBLE_EQ(workerPacingFrames(30.0, 1.5, 0.0, 10.0), 10.0);
  EXPECT_DOUBLE_EQ(workerPacingFrames(0.0, 1.5, 0.0, 10.0), 10.0);  // no estimate yet
  // Already lost: as fast as pacing allows, never below one frame.
  EXPECT_DOUBLE_EQ(workerPacingFrames(8.0, -0.3, 0.5, 10.0), 1.0);
  EXPECT_DOUBLE_EQ(workerPacingFrames(0.5, 5.0, 0.1, 10.0), 1.0);
}

}  // namespace
}  // namespace hw::app
