// The viewer's per-frame records (app/viewer_frame_log.h): the --frame-stats
// CSV has one row per frame with the documented columns, and the exit
// summary counts frames by how they were drawn and leaves frame 0 (the load)
// out of the frame times.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "app/viewer_frame_log.h"

namespace hw::app {
namespace {

std::vector<FrameRecord> records() {
  std::vector<FrameRecord> r(5);
  const double ms[] = {500, 10, 20, 30, 40};
  const session::FrameKind kinds[] = {session::FrameKind::Keyframe, session::FrameKind::Warp,
                                      session::FrameKind::Warp, session::FrameKind::Geometry,
                                      session::FrameKind::Warp};
  for (int i = 0; i < 5; ++i) {
    r[i].frame = i;
    r[i].playFrame = i + 7;
    r[i].ms = ms[i];
    r[i].workMs = ms[i] / 2;
    r[i].kind = kinds[i];
    r[i].layers = kinds[i] == session::FrameKind::Geometry ? -1 : 2;
  }
  r[0].built = true;
  r[0].keyframeMs = 123.4567;
  r[2].holeRects = 3;
  r[2].holeRectsOverBudget = 1;
  r[2].holesMs = 0.25;
  return r;
}

TEST(ViewerFrameLog, CsvHasAHeaderAndOneRowPerFrame) {
  const std::string csv = frameStatsCsv(records());
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0],
            "frame,play_frame,ms,keyframe_ms,keyframe_rendered,keyframe_read,worker_keyframe,"
            "worker_requested,worker_waited,worker_stall,layers,work_ms,budget_ms,mode,hole_rects,"
            "hole_rects_over_budget,holes_ms");
  EXPECT_EQ(lines[1], "0,7,500.000,123.457,1,0,0,0,0,0,2,250.000,0.000,keyframe,0,0,0.000");
  EXPECT_EQ(lines[3], "2,9,20.000,0.000,0,0,0,0,0,0,2,10.000,0.000,warp,3,1,0.250");
  EXPECT_EQ(lines[4], "3,10,30.000,0.000,0,0,0,0,0,0,-1,15.000,0.000,geometry,0,0,0.000");
}

TEST(ViewerFrameLog, ModeSummaryCountsFramesByHowTheyWereDrawn) {
  EXPECT_EQ(modeSummary(records(), session::FrameMode::Hybrid, -1, 0),
            "hybridwalk view: mode hybrid: 1 frames drawn as geometry, 3 warped, 1 with a keyframe "
            "built, read or taken\n");
  EXPECT_NE(modeSummary(records(), session::FrameMode::Auto, 3, 2)
                .find("; auto chose geometry from frame 3 (2 switches)\n"),
            std::string::npos);
  EXPECT_NE(
      modeSummary(records(), session::FrameMode::Auto, -1, 0).find("; auto never chose geometry\n"),
      std::string::npos);
}

TEST(ViewerFrameLog, FrameTimesLeaveTheLoadOut) {
  // Frames 1..4: 10, 20, 30, 40 ms; frame 0's 500 ms is not among them.
  const std::string s = frameTimeSummary(records(), nullptr);
  EXPECT_NE(s.find("frame ms over frames 1..4: median "), std::string::npos) << s;
  EXPECT_NE(s.find("max 40.00\n"), std::string::npos) << s;
  EXPECT_EQ(s.find("frame budget"), std::string::npos) << s;
  EXPECT_NE(frameTimeSummary(records(), "fixed")
                .find("frame budget fixed: median 0.00 ms (0 frames had one)"),
            std::string::npos);
  EXPECT_TRUE(frameTimeSummary(std::vector<FrameRecord>(1), nullptr).empty());
}

}  // namespace
}  // namespace hw::app
