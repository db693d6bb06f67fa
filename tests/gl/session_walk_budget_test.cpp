// Per-frame time budget (WalkOptions::frameBudgetMs): the scissored
// colour render gives the full render's pixels; with a budget large enough
// every stale pixel is re-rendered and equals the geometry render there; with
// the budget off (and pixel ages tracked or not) the frames are those of the
// default walk, byte for byte.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "session/walk.h"
#include "core/file_io.h"
#include "gl_fixture.h"
#include "walk_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/loader.h"

namespace hw {
namespace {

using test::Indoor;
using test::readBytes;

// indoor:20k at 128², a short walk with keyframes far enough apart to leave holes.
Indoor smallIndoor(int frames, int keyframeEvery) {
  return test::smallIndoor("indoor:20k", 128, frames, keyframeEvery);
}

std::string frameFile(const std::string& dir, int i) {
  char name[32];
  std::snprintf(name, sizeof name, "/frames/%04d.png", i);
  return dir + name;
}

class WalkBudgetTest : public test::GlTest {};

TEST_F(WalkBudgetTest, ScissoredRenderGivesTheFullRendersPixels) {
  const Indoor in = smallIndoor(2, 1);
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Camera cam = in.path.cameraAt(0);
  Image<Rgba8> full, part;
  ASSERT_TRUE((*r)->renderColour(cam, full).ok());
  const keyframe::PixelRect rects[] = {{0, 0, 128, 128}, {0, 0, 32, 32},  {96, 96, 128, 128},
                                       {5, 70, 61, 101}, {127, 0, 128, 1}, {40, 0, 41, 128}};
  for (const auto& rect : rects) {
    ASSERT_TRUE((*r)->renderColourRect(cam, rect, part).ok());
    ASSERT_EQ(part.width(), rect.width());
    ASSERT_EQ(part.height(), rect.height());
    int diff = 0;
    for (int y = rect.y0; y < rect.y1; ++y)
      for (int x = rect.x0; x < rect.x1; ++x) diff += part(x - rect.x0, y - rect.y0) != full(x, y);
    EXPECT_EQ(diff, 0) << "rect " << rect.x0 << "," << rect.y0 << " " << rect.width() << "x"
                       << rect.height();
  }
  // A scissored render leaves the scissor test off: the next full render is whole.
  Image<Rgba8> again;
  ASSERT_TRUE((*r)->renderColour(cam, again).ok());
  int changed = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) changed += again(x, y) != full(x, y);
  EXPECT_EQ(changed, 0);
  // Bad rectangles are errors, not crashes.
  EXPECT_FALSE((*r)->renderColourRect(cam, keyframe::PixelRect{0, 0, 0, 5}, part).ok());
  EXPECT_FALSE((*r)->renderColourRect(cam, keyframe::PixelRect{100, 100, 129, 120}, part).ok());
}

TEST_F(WalkBudgetTest, BudgetOffGivesTheDefaultFramesWithOrWithoutPixelAge) {
  const Indoor in = smallIndoor(16, 8);
  const std::string dir = ::testing::TempDir() + "walk_budget_off";
  std::filesystem::remove_all(dir);
  nlohmann::json reports[2];
  for (int v = 0; v < 2; ++v) {
    session::WalkOptions o;
    o.progress = false;
    o.strips = 0;
    o.saveFrames = true;
    o.reference = false;
    o.outDir = dir + (v ? "/age" : "/default");
    o.frameBudgetMs = 0;
    o.pixelAge = v == 1;
    auto r = session::runWalk(in.scene, "indoor:20k", in.path, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    reports[v] = r->report;
  }
  long long stale = 0;
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(readBytes(frameFile(dir + "/default", i)), readBytes(frameFile(dir + "/age", i)))
        << "frame " << i;
    const auto& f = reports[1]["frames"][i];
    ASSERT_TRUE(f["stale_pixels"].is_number()) << "frame " << i;
    stale += f["stale_pixels"].get<long long>();
    EXPECT_FALSE(f.contains("refreshed_pixels"));
    // Without ages: stale_pixels still counted (pixels from an earlier
    // frame), but no ages.
    EXPECT_TRUE(reports[0]["frames"][i]["stale_pixels"].is_number());
    EXPECT_FALSE(reports[0]["frames"][i].contains("max_age"));
  }
  EXPECT_GT(stale, 0) << "the path should leave holes filled from earlier frames";
  EXPECT_EQ(reports[1]["summary"]["frame_budget_ms"], 0.0);
  EXPECT_EQ(reports[1]["summary"]["frames_refreshed"], 0);
  EXPECT_TRUE(reports[1]["summary"]["budget_overruns"].is_null());
}

TEST_F(WalkBudgetTest, LargeBudgetReRendersEveryStalePixelFromGeometry) {
  const Indoor in = smallIndoor(16, 8);
  const std::string dir = ::testing::TempDir() + "walk_budget_large";
  std::filesystem::remove_all(dir);
  session::WalkOptions o;
  o.progress = false;
  o.strips = 0;
  o.saveFrames = true;
  o.outDir = dir;
  o.frameBudgetMs = 60000;  // always time left; no pacing, so no waiting
  o.paceFrames = false;
  o.staleAfter = 1;
  auto res = session::runWalk(in.scene, "indoor:20k", in.path, o);
  ASSERT_TRUE(res.ok()) << res.error().message;
  const auto& report = res->report;
  auto renderer = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  Image<Rgba8> reference;
  int framesWithRefresh = 0;
  long long refreshedChecked = 0;
  for (int i = 0; i < 16; ++i) {
    const auto& f = report["frames"][i];
    if (f["is_keyframe"].get<bool>()) continue;
    // Every pixel that was carried over is re-rendered: none stays stale.
    ASSERT_TRUE(f["stale_pixels_before_refresh"].is_number()) << "frame " << i;
    EXPECT_EQ(f["stale_pixels"], 0) << "frame " << i;
    EXPECT_EQ(f["max_age"], 0) << "frame " << i;
    if (f["refreshed_pixels"].get<long long>() == 0) {
      EXPECT_EQ(f["stale_pixels_before_refresh"], 0) << "frame " << i;
      continue;
    }
    ++framesWithRefresh;
    auto shown = readPng(frameFile(dir, i));
    ASSERT_TRUE(shown.ok()) << shown.error().message;
    ASSERT_TRUE((*renderer)->renderColour(in.path.cameraAt(i), reference).ok());
    long long area = 0;
    for (const auto& rj : f["refresh_rects"]) {
      const int x0 = rj["rect"][0], y0 = rj["rect"][1], w = rj["rect"][2], h = rj["rect"][3];
      area += static_cast<long long>(w) * h;
      int diff = 0;
      for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) diff += (*shown)(x, y) != reference(x, y);
      EXPECT_EQ(diff, 0) << "frame " << i << " rect " << x0 << "," << y0 << " " << w << "x" << h;
    }
    EXPECT_EQ(area, f["refreshed_pixels"].get<long long>()) << "frame " << i;
    refreshedChecked += area;
  }
  EXPECT_GT(framesWithRefresh, 0);
  EXPECT_GT(refreshedChecked, 0);
  const auto& s = report["summary"];
  EXPECT_EQ(s["frames_refreshed"], framesWithRefresh);
  EXPECT_EQ(s["stale_after"], 1);
  EXPECT_EQ(s["stale_pixels"]["max"], 0.0);
  EXPECT_EQ(s["budget_overruns"], 0);
  EXPECT_TRUE(s["refresh_cost_model"]["fixed_ms"].is_number());
}

TEST_F(WalkBudgetTest, PacedWalkPresentsNoFasterThanTheBudget) {
  const Indoor in = smallIndoor(6, 5);
  session::WalkOptions o;
  o.progress = false;
  o.strips = 0;
  o.reference = false;
  o.frameBudgetMs = 30;
  auto res = session::runWalk(in.scene, "indoor:20k", in.path, o);
  ASSERT_TRUE(res.ok()) << res.error().message;
  // Sleeping until the budget has passed: every interval is at least the
  // budget (a property of the pacing, not a timing bound on the machine).
  for (const auto& f : res->report["frames"]) {
    EXPECT_GE(f["ms"]["interval"].get<double>(), 30.0);
    EXPECT_GE(f["ms"]["interval"].get<double>(), f["ms"]["frame"].get<double>());
  }
  EXPECT_EQ(res->report["summary"]["frame_pacing"], true);
}

}  // namespace
}  // namespace hw
