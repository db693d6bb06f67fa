// The verified planner's measurements on OSMesa: a walk of a few segments
// (WalkOptions::onlySegments, session::measureSegments) gives each of their
// frames the PSNR the whole walk gives it, bit for bit, and walks nothing
// else; segments that are not consecutive keyframes are an error.
#include <gtest/gtest.h>

#include <map>

#include "session/schedule_calibration.h"
#include "session/walk.h"
#include "gl_fixture.h"
#include "session/keyframe_planner.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class MeasureSegmentsTest : public test::GlTest {
 protected:
  static scenes::CameraPath shortPath() {
    scenes::CameraPath p = scenes::defaultIndoorPath();
    p.width = p.height = 128;
    p.frames = 40;
    return p;
  }
  static session::WalkOptions options() {
    session::WalkOptions wo;
    wo.progress = false;
    wo.strips = 0;
    wo.keyframeFrames = {0, 7, 15, 26, 39};
    return wo;
  }
};

TEST_F(MeasureSegmentsTest, SegmentsWalkedAloneGiveTheWholeWalksFrames) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = shortPath();
  auto whole = session::runWalk(scene, "indoor", path, options());
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  std::map<int, double> psnr;  // in-between frames; identical counts 99 as the walk's stats
  for (const auto& f : whole->report["frames"])
    if (!f["is_keyframe"].get<bool>())
      psnr[f["index"].get<int>()] =
          f["psnr"].is_number() ? f["psnr"].get<double>() : session::kProbePsnrCap;
  ASSERT_EQ(psnr.size(), 35u);

  // Only (7, 15) and (26, 39): their frames and keyframes, nothing else.
  session::WalkOptions wo = options();
  wo.onlySegments = {{7, 15}, {26, 39}};
  auto part = session::runWalk(scene, "indoor", path, wo);
  ASSERT_TRUE(part.ok()) << part.error().message;
  int walked = 0;
  for (const auto& f : part->report["frames"]) {
    const int i = f["index"].get<int>();
    EXPECT_TRUE((i >= 7 && i <= 15) || (i >= 26 && i <= 39)) << "frame " << i << " walked";
    ++walked;
    if (!f["is_keyframe"].get<bool>() && f["psnr"].is_number()) {
      EXPECT_EQ(f["psnr"].get<double>(), psnr[i]) << "frame " << i;
    }
  }
  EXPECT_EQ(walked, 9 + 14);

  // measureSegments: the same frames, by segment; the schedule's other
  // keyframes are not needed (it puts keyframes at the segments' ends only).
  session::MeasuredSegments m;
  ASSERT_TRUE(
      session::measureSegments(scene, "indoor", path, 40, {{7, 15}, {26, 39}, {2, 5}}, options(), m)
          .ok());
  ASSERT_EQ(m.size(), 3u);
  for (const auto& [seg, v] : m) {
    ASSERT_EQ(v.size(), static_cast<std::size_t>(seg.second - seg.first - 1));
    if (seg.first == 2) continue;  // not a segment of the whole walk
    for (std::size_t q = 0; q < v.size(); ++q)
      EXPECT_EQ(v[q], psnr[seg.first + 1 + static_cast<int>(q)]) << "frame " << seg.first + 1 + q;
  }
  // (2, 5) is measured as its own segment: its frames are better than the
  // same frames between keyframes 0 and 7.
  double mine = 0, wide = 0;
  for (int q = 0; q < 2; ++q) mine += m[{2, 5}][q], wide += psnr[3 + q];
  EXPECT_GT(mine, wide);
}

TEST_F(MeasureSegmentsTest, SegmentsThatAreNotConsecutiveKeyframesAreErrors) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = shortPath();
  session::WalkOptions wo = options();
  wo.onlySegments = {{7, 26}};  // 15 lies between
  auto r = session::runWalk(scene, "indoor", path, wo);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("consecutive keyframes"), std::string::npos)
      << r.error().message;
  wo.onlySegments = {{30, 45}};  // past the path
  EXPECT_FALSE(session::runWalk(scene, "indoor", path, wo).ok());
  // Overlapping segments cannot both be walked: one's end lies in the other.
  session::MeasuredSegments m;
  auto st = session::measureSegments(scene, "indoor", path, 40, {{7, 15}, {10, 20}}, options(), m);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("consecutive keyframes"), std::string::npos)
      << st.error().message;
  EXPECT_TRUE(m.empty());
}

}  // namespace
}  // namespace hw
