// The walk's frame mode (session/frame_mode.h): geometry frames are exact and
// build no keyframes; an automatic choice that flips per segment warps exactly
// the segments it chose, with keyframes built only for them, and its warped
// segments are the hybrid walk's frames bit for bit. The choice's thresholds are forced (a timed outcome would
// not be a test): ModeChooser's decisions are tested in
// tests/cpu/session_frame_mode_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/file_io.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "session/walk.h"
#include "walk_fixture.h"

namespace hw {
namespace {

class WalkModeTest : public test::GlTest {};

std::string tempDir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() /
                 ("hw_walk_mode_" + name + "_" +
                  std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::remove_all(d);
  return d.string();
}

session::WalkOptions options(session::FrameMode mode, const std::string& out) {
  session::WalkOptions wo;
  wo.mode = mode;
  wo.saveFrames = true;
  wo.strips = 2;
  wo.progress = false;
  wo.outDir = out;
  return wo;
}

std::string frameFile(const std::string& out, int i) {
  char name[32];
  std::snprintf(name, sizeof name, "/frames/%04d.png", i);
  return out + name;
}

TEST_F(WalkModeTest, GeometryModeDrawsEveryFrameExactlyAndBuildsNoKeyframe) {
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 12, 5);
  const std::string out = tempDir("geometry");
  auto walk = session::runWalk(in.scene, "indoor:20k", in.path,
                               options(session::FrameMode::Geometry, out));
  ASSERT_TRUE(walk.ok()) << walk.error().message;
  const auto& s = walk->report["summary"];
  EXPECT_EQ(s["mode"], "geometry");
  EXPECT_EQ(s["keyframes"], 0);
  EXPECT_EQ(s["frames_by_mode"]["geometry"], 12);
  EXPECT_EQ(s["frames_by_mode"]["warp"], 0);
  EXPECT_EQ(s["frames_by_mode"]["keyframe"], 0);
  EXPECT_EQ(s["psnr"]["count"], 0);  // PSNR covers warped frames only
  EXPECT_EQ(s["reference_ms"]["count"], 12);
  ASSERT_EQ(walk->report["frames"].size(), 12u);
  for (const auto& f : walk->report["frames"]) {
    EXPECT_EQ(f["mode"], "geometry");
    EXPECT_EQ(f["ssim"], 1.0);
    EXPECT_EQ(f["ms"]["frame"].get<double>() >= f["ms"]["geometry"].get<double>(), true);
  }
  // Each saved frame is the geometry renderer's image at that camera.
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (int i : {0, 7, 11}) {
    Image<Rgba8> ref;
    ASSERT_TRUE((*r)->renderColour(in.path.cameraAt(i), ref).ok());
    auto saved = readPng(frameFile(out, i));
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_EQ(saved->pixels(), ref.pixels()) << "frame " << i;
  }
  for (auto kind : walk->frameTimes.kind) EXPECT_EQ(kind, session::FrameKind::Geometry);
  std::filesystem::remove_all(out);
}

TEST_F(WalkModeTest, AutoWarpsOnlyTheSegmentsItChoosesAndBuildsOnlyTheirKeyframes) {
  // Enter below a huge ratio, leave above 0: warp, geometry, warp, ... per
  // segment of 5 frames (keyframes 0, 5, 10, 15; the last frame 15 alone).
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 16, 5);
  const std::string autoOut = tempDir("auto"), hybridOut = tempDir("hybrid");
  session::WalkOptions wo = options(session::FrameMode::Auto, autoOut);
  wo.modeChooser.enterBelow = wo.modeChooser.tailEnterBelow = 1e30;
  wo.modeChooser.leaveAbove = 0;
  wo.modeChooser.giveUpAfter = 0;  // forced: no segment given up by its timing
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  auto h = session::runWalk(in.scene, "indoor:20k", in.path,
                            options(session::FrameMode::Hybrid, hybridOut));
  ASSERT_TRUE(h.ok()) << h.error().message;

  const char* expected[16] = {"keyframe", "warp",     "warp",     "warp",     "warp",     "geometry",
                              "geometry", "geometry", "geometry", "geometry", "keyframe", "warp",
                              "warp",     "warp",     "warp",     "geometry"};
  const auto& frames = a->report["frames"];
  ASSERT_EQ(frames.size(), 16u);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(frames[i]["mode"], expected[i]) << "frame " << i;
  const auto& s = a->report["summary"];
  EXPECT_EQ(s["mode"], "auto");
  EXPECT_EQ(s["frames_by_mode"]["geometry"], 6);
  EXPECT_EQ(s["frames_by_mode"]["warp"], 8);
  EXPECT_EQ(s["frames_by_mode"]["keyframe"], 2);
  EXPECT_EQ(s["mode_switches"], 3);
  // Keyframes 0, 5 (bracketing the first segment), 10 and 15: never one for
  // a geometry segment alone.
  EXPECT_EQ(s["keyframes"], 4);
  EXPECT_EQ(s["psnr"]["count"], 8);
  EXPECT_TRUE(s["mode_costs"]["warp_floor_ms"].is_number());
  EXPECT_TRUE(s["frame_over_reference"]["median"].is_number());
  // The warped segments are the hybrid walk's, bit for bit: each starts at
  // its keyframe frame, so its previous-frame chain is the hybrid walk's.
  for (int i : {0, 1, 2, 3, 4, 10, 11, 12, 13, 14})
    EXPECT_EQ(test::readBytes(frameFile(autoOut, i)), test::readBytes(frameFile(hybridOut, i)))
        << "frame " << i;
  // The hybrid walk warps every frame.
  EXPECT_EQ(h->report["summary"]["frames_by_mode"]["geometry"], 0);
  EXPECT_EQ(h->report["summary"]["mode"], "hybrid");
  // Strips only of warped frames.
  ASSERT_FALSE(s["strips"].empty());
  for (const auto& st : s["strips"]) EXPECT_EQ(frames[st["frame"].get<int>()]["mode"], "warp");
  std::filesystem::remove_all(autoOut);
  std::filesystem::remove_all(hybridOut);
}

TEST_F(WalkModeTest, ReprojectedFallbackAfterAGeometryFrameCopiesInsteadOfReprojecting) {
  // A geometry frame reads back no depth: the warped frames after it must not
  // reproject it with a stale depth or camera (they copy its pixels).
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 16, 5);
  session::WalkOptions wo = options(session::FrameMode::Auto, "");
  wo.saveFrames = false;
  wo.inBetween.fallback = gapfill::Fallback::Reproject;
  wo.modeChooser.enterBelow = wo.modeChooser.tailEnterBelow = 1e30;
  wo.modeChooser.leaveAbove = 0;
  wo.modeChooser.giveUpAfter = 0;  // forced: no segment given up by its timing
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  EXPECT_EQ(a->report["summary"]["frames_by_mode"]["geometry"], 6);
  EXPECT_EQ(a->report["summary"]["frames_by_mode"]["warp"], 8);
}

TEST_F(WalkModeTest, AutoThatNeverWarpsBuildsNoKeyframe) {
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 12, 5);
  session::WalkOptions wo = options(session::FrameMode::Auto, "");
  wo.saveFrames = false;
  wo.modeChooser.enterBelow = 0;  // nothing is cheaper than 0 x the geometry
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  const auto& s = a->report["summary"];
  EXPECT_EQ(s["keyframes"], 0);
  EXPECT_EQ(s["frames_by_mode"]["geometry"], 12);
  EXPECT_EQ(s["mode_switches"], 0);
  EXPECT_GT(s["mode_costs"]["geometry_ms"].get<double>(), 0);
  // The cost compared against is the view's, from the triangles it draws.
  EXPECT_EQ(s["mode_costs"]["geometry_by_triangles"], true);
  EXPECT_GT(s["mode_costs"]["view_triangles"].get<double>(), 0);
  EXPECT_GT(s["mode_costs"]["geometry_view_ms"].get<double>(), 0);
  EXPECT_EQ(s["warp_starts_deferred"], 0);  // keyframes built in the frame: nothing to wait for
}

TEST_F(WalkModeTest, AutoStartsWarpingOnlyOnKeyframesBuiltAhead) {
  // Keyframes from the worker, and a choice forced to flip every segment:
  // each warped stretch after a geometry one starts on keyframes the worker
  // has finished (the segment's frames are drawn as geometry until then,
  // and warping starts at the first that finds them done), so none of its
  // frames waits for a build.
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 41, 5);
  session::WalkOptions wo = options(session::FrameMode::Auto, "");
  wo.saveFrames = false;
  wo.strips = 0;
  wo.asyncKeyframes = true;
  wo.modeChooser.enterBelow = wo.modeChooser.tailEnterBelow = 1e30;
  wo.modeChooser.leaveAbove = 0;
  wo.modeChooser.giveUpAfter = 0;  // forced: no segment given up by its timing
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  const auto& frames = a->report["frames"];
  ASSERT_EQ(frames.size(), 41u);
  int starts = 0;
  for (int i = 1; i < 41; ++i) {
    if (frames[i]["mode"] == "geometry" || frames[i - 1]["mode"] != "geometry") continue;
    ++starts;
    for (int j = i; j < 41 && (j == i || j % 5 != 0); ++j)  // to the next keyframe
      EXPECT_EQ(frames[j]["ms"]["keyframe_wait"].get<double>(), 0.0) << "frame " << j;
  }
  // Segments 10-15, 20-25, ...: every one after a geometry segment either
  // started warping at its keyframe or was deferred (and may have started
  // later in the segment).
  const auto& s = a->report["summary"];
  EXPECT_GE(starts + s["warp_starts_deferred"].get<int>(), 3);
}

std::string modesOf(const nlohmann::json& report) {
  std::string m;
  for (const auto& f : report["frames"]) m += f["mode"].get<std::string>()[0];
  return m;
}

TEST_F(WalkModeTest, APinnedWalkDrawsEachFrameAsTheMeasuredRunDid) {
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 16, 5);
  const std::string pins = tempDir("pins"), out1 = tempDir("pin1"), out2 = tempDir("pin2");
  // Measured: forced to flip per segment (as above).
  session::WalkOptions wo = options(session::FrameMode::Auto, out1);
  wo.modePinDir = pins;
  wo.modePinContext = "test";
  wo.modeChooser.enterBelow = wo.modeChooser.tailEnterBelow = 1e30;
  wo.modeChooser.leaveAbove = 0;
  wo.modeChooser.giveUpAfter = 0;
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  const auto& pa = a->report["summary"]["auto_pin"];
  EXPECT_EQ(pa["state"], "measured");
  EXPECT_EQ(pa["setting"], "use");
  ASSERT_TRUE(pa["file"].is_string());
  const std::string file = pa["file"];
  EXPECT_EQ(std::filesystem::path(file).parent_path(), std::filesystem::path(pins));
  EXPECT_EQ(modesOf(a->report), "kwwwwgggggkwwwwg");
  bool found = false;
  auto pinned = session::readModePin(file, 16, &found);
  ASSERT_TRUE(pinned.ok()) << pinned.error().message;
  EXPECT_TRUE(found);
  EXPECT_EQ(pinned->holeRects.size(), 16u);

  // Replayed: thresholds that would draw every frame as geometry are not
  // consulted; the frames are the measured run's, bit for bit.
  wo.outDir = out2;
  wo.modeChooser.enterBelow = wo.modeChooser.tailEnterBelow = 0;
  auto b = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(b->report["summary"]["auto_pin"]["state"], "replayed");
  EXPECT_EQ(b->report["summary"]["auto_pin"]["file"], file);
  EXPECT_EQ(modesOf(b->report), "kwwwwgggggkwwwwg");
  EXPECT_EQ(b->report["summary"]["keyframes"], 4);  // only the warped segments' keyframes
  for (int i = 0; i < 16; ++i)
    EXPECT_EQ(test::readBytes(frameFile(out1, i)), test::readBytes(frameFile(out2, i)))
        << "frame " << i;

  // Measure: chosen again (now all geometry) and pinned over the old pin.
  wo.outDir = "";
  wo.saveFrames = false;
  wo.autoPin = session::AutoPin::Measure;
  auto c = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->report["summary"]["auto_pin"]["state"], "measured");
  EXPECT_EQ(modesOf(c->report), std::string(16, 'g'));
  pinned = session::readModePin(file, 16, &found);
  ASSERT_TRUE(pinned.ok()) << pinned.error().message;
  EXPECT_EQ(pinned->kinds, std::vector<session::FrameKind>(16, session::FrameKind::Geometry));
  EXPECT_EQ(pinned->holeRects, std::vector<int>(16, -1));  // no frame ran a hole pass

  // Another context is another pin; hybrid and geometry walks pin nothing.
  wo.autoPin = session::AutoPin::Use;
  wo.modePinContext = "other";
  auto d = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_NE(d->report["summary"]["auto_pin"]["file"], file);
  EXPECT_EQ(d->report["summary"]["auto_pin"]["state"], "measured");
  wo.mode = session::FrameMode::Hybrid;
  auto e = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(e.ok()) << e.error().message;
  EXPECT_TRUE(e->report["summary"]["auto_pin"].is_null());
  int files = 0;
  for ([[maybe_unused]] const auto& f : std::filesystem::directory_iterator(pins)) ++files;
  EXPECT_EQ(files, 2);
  for (const auto& dir : {pins, out1, out2}) std::filesystem::remove_all(dir);
}

TEST_F(WalkModeTest, APinThatDoesNotFitTheWalkIsChosenAgainAndReplaced) {
  test::Indoor in = test::smallIndoor("indoor:20k", 64, 11, 5);
  const std::string pins = tempDir("badpin");
  session::WalkOptions wo = options(session::FrameMode::Auto, "");
  wo.saveFrames = false;
  wo.modePinDir = pins;
  wo.modeChooser.enterBelow = 0;  // chosen: every frame as geometry
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  const std::string file = a->report["summary"]["auto_pin"]["file"];
  // Frame 1 is an in-between frame, not a keyframe.
  using K = session::FrameKind;
  ASSERT_TRUE(session::writeModePin(file,
                                    session::ModePin{{K::Keyframe, K::Keyframe, K::Warp, K::Warp,
                                                      K::Warp, K::Keyframe, K::Warp, K::Warp,
                                                      K::Warp, K::Warp, K::Keyframe},
                                                     {}},
                                    "x")
                  .ok());
  auto b = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(b.ok()) << b.error().message;
  const auto& p = b->report["summary"]["auto_pin"];
  EXPECT_EQ(p["state"], "measured");
  ASSERT_TRUE(p["note"].is_string());
  EXPECT_NE(p["note"].get<std::string>().find("frame 1 is an in-between frame of the schedule, "
                                               "the pin has keyframe"),
            std::string::npos)
      << p["note"];
  EXPECT_EQ(modesOf(b->report), std::string(11, 'g'));
  bool found = false;
  auto pinned = session::readModePin(file, 11, &found);
  ASSERT_TRUE(pinned.ok()) << pinned.error().message;
  EXPECT_EQ(pinned->kinds, std::vector<session::FrameKind>(11, session::FrameKind::Geometry));
  std::filesystem::remove_all(pins);
}

TEST_F(WalkModeTest, APinnedWalkDrawsTheHoleRectanglesTheMeasuredRunDid) {
  // The hole pass's budget follows the run's own timings: measured with a
  // budget that admits one rectangle a frame, replayed with none (every
  // rectangle would be drawn). The replay draws what the pin says, so its
  // frames are the measured run's, bit for bit.
  test::Indoor in = test::smallIndoor("indoor:20k", 96, 16, 5);
  const std::string pins = tempDir("holepins"), out1 = tempDir("holes1"), out2 = tempDir("holes2");
  session::WalkOptions wo = options(session::FrameMode::Auto, out1);
  wo.modePinDir = pins;
  wo.modeChooser.enterBelow = wo.modeChooser.tailEnterBelow = 1e30;  // warp every segment
  wo.modeChooser.leaveAbove = wo.modeChooser.tailLeaveAbove = 1e30;
  wo.modeChooser.giveUpAfter = 0;
  wo.renderHoles = true;
  wo.renderHolesBudget = 1e-9;
  auto a = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(a.ok()) << a.error().message;
  ASSERT_EQ(a->report["summary"]["auto_pin"]["state"], "measured");
  wo.outDir = out2;
  wo.renderHolesBudget = 0;
  auto b = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(b.ok()) << b.error().message;
  ASSERT_EQ(b->report["summary"]["auto_pin"]["state"], "replayed");
  int warped = 0, heldBack = 0;
  for (int i = 0; i < 16; ++i) {
    const auto& fa = a->report["frames"][i];
    const auto& fb = b->report["frames"][i];
    ASSERT_EQ(fa["mode"], fb["mode"]) << "frame " << i;
    if (fa["mode"] == "warp") {
      ++warped;
      EXPECT_EQ(fa["hole_rects"], fb["hole_rects"]) << "frame " << i;
      heldBack += fb["hole_rects_over_budget"].get<int>();
    }
    EXPECT_EQ(test::readBytes(frameFile(out1, i)), test::readBytes(frameFile(out2, i)))
        << "frame " << i;
  }
  EXPECT_GT(warped, 8);
  // Without the pin the replay would have drawn these rectangles too.
  EXPECT_GT(heldBack, 0);
  for (const auto& dir : {pins, out1, out2}) std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hw
