// The disocclusion study on a turn in the procedural indoor scene: its hole
// classes add up, every way of filling stays within the holes, exact pixels
// can only raise the PSNR, and the frames are the walk's (not blank).
#include <gtest/gtest.h>

#include <string>

#include "bench/disocclusion_study.h"
#include "gl_fixture.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class DisocclusionTest : public test::GlTest {};

scenes::CameraPath turn() {
  scenes::CameraPath p;
  p.width = p.height = 96;
  p.nearPlane = 0.1;
  p.farPlane = 100.0;
  p.frames = 21;  // keyframes 0, 10, 20
  p.keyframeEvery = 10;
  p.keys = {{{6.0, 1.7, -4.0}, {6.0, 1.6, 1.0}}, {{6.0, 1.7, -3.5}, {11.0, 1.6, -3.5}}};
  return p;
}

TEST_F(DisocclusionTest, HoleClassesAddUpAndExactPixelsOnlyHelp) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  bench::DisocclusionOptions o;
  o.frames = 0;
  o.progress = false;
  auto r = bench::runDisocclusionPath(scene, "indoor", "turn", turn(), o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const nlohmann::json& rows = (*r)["frames"];
  ASSERT_EQ(rows.size(), 18u);  // 21 frames, 3 keyframes
  long long holes = 0, prevFilled = 0, nextFilled = 0;
  for (const auto& row : rows) {
    SCOPED_TRACE("frame " + std::to_string(row["frame"].get<int>()));
    const long long h = row["holes"].get<long long>();
    EXPECT_EQ(h, row["outside"].get<long long>() + row["occluded"].get<long long>() +
                     row["sky"].get<long long>());
    EXPECT_LE(row["prev_filled"].get<long long>(), h);
    EXPECT_LE(row["next_filled"].get<long long>(), h);
    const double copy = row["psnr_copy"].get<double>();
    EXPECT_GT(copy, 15.0);  // a warped room, not a blank image
    EXPECT_GE(row["psnr_peel_bound"].get<double>(), copy - 1e-9);
    EXPECT_GE(row["psnr_exact_holes"].get<double>(), row["psnr_peel_bound"].get<double>() - 1e-9);
    EXPECT_GE(row["psnr_hole_rects"].get<double>(), copy - 1e-9);  // exact pixels replace others
    if (h == 0) {
      EXPECT_DOUBLE_EQ(row["psnr_prev"].get<double>(), copy);
      EXPECT_DOUBLE_EQ(row["psnr_next"].get<double>(), copy);
      EXPECT_DOUBLE_EQ(row["psnr_exact_holes"].get<double>(), copy);
    }
    // The first segment has no keyframe before it; the last none after it.
    if (row["k0"].get<int>() == 0) {
      EXPECT_EQ(row["prev_filled"].get<long long>(), 0);
    }
    if (row["k1"].get<int>() == 20) {
      EXPECT_EQ(row["next_filled"].get<long long>(), 0);
    }
    holes += h;
    prevFilled += row["prev_filled"].get<long long>();
    nextFilled += row["next_filled"].get<long long>();
  }
  // The turn shows what neither keyframe saw.
  const nlohmann::json& s = (*r)["summary"];
  EXPECT_GT(holes, 0);
  EXPECT_EQ(s["hole_pixels"].get<long long>(), holes);
  EXPECT_GT(s["holes_outside_share"].get<double>(), 0.0);
  EXPECT_LE(prevFilled + nextFilled, 2 * holes);
  EXPECT_GT(s["hole_rects"]["filled_share"].get<double>(), 0.5);
  EXPECT_GE(s["exact_holes"]["psnr"]["median"].get<double>(),
            s["copy"]["psnr"]["median"].get<double>());

  // One CSV row per in-between frame, after the header.
  const nlohmann::json study = {{"paths", nlohmann::json::array({*r})}};
  const std::string csv = bench::disocclusionCsv(study);
  std::size_t lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_EQ(lines, rows.size() + 1);
  EXPECT_EQ(csv.rfind("scene,path,frame,", 0), 0u);
}

}  // namespace
}  // namespace hw
