// What a person reads about a walk (report/walk_page.h), from report.json
// data alone: the summary line in the documented form, "none warped" with the
// reason instead of NaNs, counts that add up, and the page and PSNR plot.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/file_io.h"
#include "report/walk_page.h"

namespace hw::report {
namespace {

using nlohmann::json;

json stats(double median, double p5, double p95) {
  return {{"median", median}, {"p5", p5}, {"p95", p95}, {"count", 10}};
}
json nullStats() {
  return {{"median", nullptr}, {"p5", nullptr}, {"p95", nullptr}, {"count", 0}};
}

// A summary as session/walk.cpp writes it (the keys the text reads).
json indoorSummary() {
  return {{"scene", {{"name", "indoor"}, {"triangles", 20000}}},
          {"resolution", {512, 512}},
          {"frames", 120},
          {"keyframes", 13},
          {"keyframe_every", 10},
          {"keyframe_schedule", "fixed"},
          {"keyframe_frames", {0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 119}},
          {"keyframe_acquisition", "async"},
          {"keyframe_stalls", 0},
          {"keyframe_stall_ms_total", 0.0},
          {"mode", "auto"},
          {"frames_by_mode", {{"geometry", 36}, {"warp", 77}, {"keyframe", 7}}},
          {"frame_over_reference", {{"median", 0.6213}, {"p95", 0.7109}}},
          {"psnr", stats(35.71, 27.49, 40.2)},
          {"ssim", stats(0.97, 0.9, 0.99)},
          {"holes_before_fallback", stats(0.001, 0, 0.01)},
          {"holes_after_fallback", stats(0.0001, 0, 0.001)},
          {"quads_per_keyframe", stats(2294, 2000, 2600)},
          {"in_between_ms", stats(9.5, 8, 13)},
          {"reference_ms", stats(15.3, 14, 18.2)},
          {"frame_ms", stats(9.7, 8, 13.1)},
          {"tau", nullptr},
          {"tau_parallax_px", 0.125},
          {"criterion", "five-point"},
          {"planarity", "region-local"},
          {"merge_strips", true},
          {"compose_mode", "depth-merge"},
          {"depth_mode", "24-bit"},
          {"frame_budget_mode", "off"},
          {"machine", {{"cpu", "Test CPU"}, {"gl_renderer", "llvmpipe (LLVM 15.0.6, 256 bits)"}}},
          {"strips", json::array({{{"frame", 5}, {"psnr", 34.8}, {"ssim", 0.98}, {"holes_before_fallback", 0.0}}})}};
}

TEST(WalkSummary, HeadlineInTheDocumentedForm) {
  const WalkSummaryText t = walkSummaryText(indoorSummary());
  EXPECT_EQ(t.headline,
            "indoor, 120 frames: 64 % warped, in-between 35.7 dB (p5 27.5), frame 0.62x the "
            "geometry frame (median), 0.71x (p95)");
}

TEST(WalkSummary, CountsHaveOneNameAndAddUp) {
  const WalkSummaryText t = walkSummaryText(indoorSummary());
  std::string all;
  for (const auto& d : t.details) all += d + "\n";
  EXPECT_NE(all.find("frames: 120 = 77 warped + 36 drawn as geometry + 7 keyframe frames"),
            std::string::npos) << all;
  EXPECT_NE(all.find("keyframes: 13 in the schedule (a keyframe every 10 frames), 13 built"),
            std::string::npos) << all;
  // The two ratios say what they divide.
  EXPECT_NE(all.find("median frame over median geometry frame"), std::string::npos) << all;
  EXPECT_NE(all.find("not the same frames"), std::string::npos) << all;
  EXPECT_EQ(all.find("nan"), std::string::npos) << all;
}

// "keyframe stalls" is report.json's keyframe_stalls (warm-up excluded); the
// timed waits (keyframe_stall_ms, which may hold one before frame 0) are
// counted under their own name.
TEST(WalkSummary, KeyframeStallsAreTheReportsCount) {
  json s = indoorSummary();
  s["keyframe_stalls"] = 0;
  s["keyframe_stall_ms"] = {{"median", 35.3}, {"p5", 35.3}, {"p95", 35.3}, {"count", 1}};
  s["keyframe_stall_ms_total"] = 35.3;
  std::string all;
  for (const auto& d : walkSummaryText(s).details) all += d + "\n";
  EXPECT_NE(all.find("0 keyframe stalls (a frame waited for a keyframe; warm-up excluded)"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("1 wait for a keyframe, 35.3 ms in all"), std::string::npos) << all;
  s["keyframe_stalls"] = 3;
  s["keyframe_stall_ms"]["count"] = 4;
  all.clear();
  for (const auto& d : walkSummaryText(s).details) all += d + "\n";
  EXPECT_NE(all.find("3 keyframe stalls"), std::string::npos) << all;
  EXPECT_NE(all.find("4 waits for a keyframe"), std::string::npos) << all;
}

TEST(WalkSummary, FewerBuiltThanScheduledSaysWhy) {
  json s = indoorSummary();
  s["keyframes"] = 1;
  s["keyframe_frames"] = json::array();
  for (int k = 0; k < 25; ++k) s["keyframe_frames"].push_back(10 * k);
  std::string all;
  for (const auto& d : walkSummaryText(s).details) all += d + "\n";
  EXPECT_NE(all.find("25 in the schedule"), std::string::npos) << all;
  EXPECT_NE(all.find("1 built"), std::string::npos) << all;
  EXPECT_NE(all.find("segments drawn as geometry need none"), std::string::npos) << all;
}

TEST(WalkSummary, NothingWarpedInAutoSaysWhyAndNeverNan) {
  json s = indoorSummary();
  s["frames"] = 240;
  s["frames_by_mode"] = {{"geometry", 240}, {"warp", 0}, {"keyframe", 0}};
  s["psnr"] = nullStats();
  s["ssim"] = nullStats();
  s["in_between_ms"] = nullStats();
  s["mode_costs"] = {{"geometry_ms", 19.0}, {"in_between_ms", nullptr},
                     {"warp_calibration_ms", 27.6}, {"warp_floor_ms", 3.0}};
  const WalkSummaryText t = walkSummaryText(s);
  EXPECT_EQ(t.headline.rfind("indoor, 240 frames: none warped (auto: drawing was cheaper here, "
                             "19.0 ms against a warp of 27.6 ms; `--mode hybrid` warps every frame)",
                             0),
            0u)
      << t.headline;
  for (const auto& line : t.details) EXPECT_EQ(line.find("nan"), std::string::npos) << line;
  EXPECT_EQ(t.headline.find("nan"), std::string::npos);
}

TEST(WalkSummary, NothingWarpedInOtherModes) {
  json s = indoorSummary();
  s["mode"] = "geometry";
  s["frames_by_mode"] = {{"geometry", 120}, {"warp", 0}, {"keyframe", 0}};
  EXPECT_NE(walkSummaryText(s).headline.find("none warped (--mode geometry draws every frame)"),
            std::string::npos);
  s["mode"] = "hybrid";
  s["keyframe_every"] = 1;
  s["frames_by_mode"] = {{"geometry", 0}, {"warp", 0}, {"keyframe", 120}};
  EXPECT_NE(walkSummaryText(s).headline.find("every frame is a keyframe frame"), std::string::npos);
}

TEST(WalkSummary, WithoutReferenceNoRatioAndNoNan) {
  json s = indoorSummary();
  s["psnr"] = nullStats();
  s["ssim"] = nullStats();
  s["reference_ms"] = nullStats();
  s["frame_over_reference"] = nullptr;
  const WalkSummaryText t = walkSummaryText(s);
  EXPECT_NE(t.headline.find("PSNR not measured (--no-reference)"), std::string::npos) << t.headline;
  EXPECT_NE(t.headline.find("frame 9.7 ms (median), 13.1 ms (p95)"), std::string::npos) << t.headline;
  EXPECT_EQ(t.headline.find("nan"), std::string::npos);
}

TEST(WalkSummary, EmptyOrForeignSummaryDoesNotThrow) {
  EXPECT_NO_THROW(walkSummaryText(json::object()));
  EXPECT_NO_THROW(walkSummaryText(json::array()));
  EXPECT_NO_THROW(walkSummaryText(json{{"frames", "x"}, {"psnr", 3}}));
  EXPECT_EQ(walkSummaryText(json::object()).headline.find("nan"), std::string::npos);
}

TEST(WalkPage, HtmlHasSummarySettingsAndOnlyExistingImages) {
  const json report = {{"summary", indoorSummary()}, {"frames", json::array()}};
  const std::string html = walkPageHtml(report, {"frame_times.png", "strip_5.png", "report.json"});
  EXPECT_NE(html.find("64 % warped"), std::string::npos);
  EXPECT_NE(html.find("src=\"frame_times.png\""), std::string::npos);
  EXPECT_NE(html.find("src=\"strip_5.png\""), std::string::npos);
  EXPECT_EQ(html.find("psnr_along_path.png"), std::string::npos);  // not in the folder
  EXPECT_NE(html.find("<td>compose_mode</td><td>depth-merge</td>"), std::string::npos);
  EXPECT_NE(html.find("llvmpipe (LLVM 15.0.6, 256 bits)"), std::string::npos);
}

TEST(WalkPage, WritesPlotAndPageFromReportJson) {
  const std::string dir = ::testing::TempDir() + "walk_page_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // Missing report: an error naming the file.
  auto st = writeWalkPage(dir);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().message.find(dir + "/report.json"), std::string::npos);
  ASSERT_TRUE(writeFileAtomic(dir + "/report.json", "{\"summary\": "));
  st = writeWalkPage(dir);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().message.find("not valid JSON"), std::string::npos);
  ASSERT_TRUE(writeFileAtomic(dir + "/report.json", "[1, 2]"));
  st = writeWalkPage(dir);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().message.find("not a walk report"), std::string::npos);

  json frames = json::array();
  for (int i = 0; i < 21; ++i) {
    const bool key = i % 10 == 0;
    json f = {{"index", i}, {"is_keyframe", key}};
    if (key)
      f["keyframes"] = {i}, f["psnr"] = nullptr;
    else if (i > 15)  // drawn as geometry
      f["keyframes"] = json::array(), f["psnr"] = nullptr;
    else
      f["keyframes"] = {i / 10 * 10, i / 10 * 10 + 10}, f["psnr"] = 30.0 + i % 10;
    frames.push_back(f);
  }
  ASSERT_TRUE(writeFileAtomic(dir + "/report.json",
                              json{{"summary", indoorSummary()}, {"frames", frames}}.dump()));
  json summary;
  ASSERT_TRUE(writeWalkPage(dir, &summary));
  EXPECT_EQ(summary["frames"], 120);
  auto png = readPng(dir + "/psnr_along_path.png");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->width(), 1000);
  auto html = readFile(dir + "/index.html");
  ASSERT_TRUE(html);
  EXPECT_NE(html->find("src=\"psnr_along_path.png\""), std::string::npos);
  EXPECT_EQ(html->find("src=\"frame_times.png\""), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hw::report
