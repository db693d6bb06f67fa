// The interactive viewer under Xvfb (scripts/test.sh): a scripted session
// plays a short path, exits after a fixed number of frames and writes a
// screenshot of the window. The screenshot must not be blank and must match
// the geometry renderer's image of the same camera, rendered in the same
// window context at the window's size. Without a display this FAILS: CI must
// exercise the windowed path.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

#include "app/viewer.h"
#include "core/file_io.h"
#include "core/metrics.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/camera_path.h"
#include "scenes/procedural.h"
#include "session/presets.h"

namespace hw {
namespace {

const scenes::Scene& indoorScene() {
  static const scenes::Scene scene = scenes::makeIndoorScene(20000);
  return scene;
}

// The first three keys of the indoor walk: through the SW room to its doorway.
scenes::CameraPath shortIndoorPath() {
  scenes::CameraPath p = scenes::defaultIndoorPath();
  p.keys.resize(3);
  p.frames = 30;
  p.keyframeEvery = 5;
  return p;
}

struct Session {
  int exitCode = -1;
  Image<Rgba8> screenshot;
  Image<Rgba8> reference;
  Camera lastCamera;
  std::string referenceError;
};

Session runScripted(bool hybrid, const std::string& tag, bool hud = false,
                    const std::string& keys = "", const std::string& recordPath = "",
                    const std::function<void(app::ViewerOptions&)>& configure = {}) {
  Session out;
  const std::string dir = ::testing::TempDir();
  const std::string pathFile = dir + "viewer_path_" + tag + ".json";
  const std::string shot = dir + "viewer_shot_" + tag + ".png";
  std::filesystem::remove(shot);
  const Status w = writeFileAtomic(pathFile, scenes::cameraPathToJson(shortIndoorPath()));
  EXPECT_TRUE(w.ok()) << w.error().message;

  app::ViewerOptions opt;
  opt.sceneLabel = "indoor:20k";
  opt.width = 400;
  opt.height = 300;
  opt.playPath = pathFile;
  opt.play = true;
  opt.exitAfterFrames = 15;
  opt.screenshotPath = shot;
  // Pinned: these sessions test each way of drawing, not the auto choice.
  opt.mode = hybrid ? session::FrameMode::Hybrid : session::FrameMode::Geometry;
  opt.hud = hud;
  opt.keys = keys;
  opt.recordPath = recordPath;
  if (configure) configure(opt);
  // Reference: the geometry renderer in the viewer's own window context, at
  // the final camera and the window's size.
  opt.onExit = [&](const Camera& cam) {
    out.lastCamera = cam;
    auto r = keyframe::GeometryRenderer::create(indoorScene());
    if (!r) {
      out.referenceError = r.error().message;
      return;
    }
    const Status s = (*r)->renderColour(cam, out.reference);
    if (!s) out.referenceError = s.error().message;
  };
  out.exitCode = app::runViewer(indoorScene(), scenes::defaultIndoorPath(), opt);
  if (std::filesystem::exists(shot)) {
    auto img = readPng(shot);
    EXPECT_TRUE(img.ok()) << (img.ok() ? "" : img.error().message);
    if (img) out.screenshot = std::move(*img);
  }
  return out;
}

std::size_t distinctColours(const Image<Rgba8>& img) {
  std::set<std::uint32_t> c;
  for (const Rgba8& p : img.pixels())
    c.insert(static_cast<std::uint32_t>(p.r) << 16 | static_cast<std::uint32_t>(p.g) << 8 | p.b);
  return c.size();
}

void writeFailureImages(const Session& s, const std::string& tag) {
  const std::string dir = ::testing::TempDir();
  (void)writePng(dir + "viewer_" + tag + "_actual.png", s.screenshot);
  (void)writePng(dir + "viewer_" + tag + "_expected.png", s.reference);
  (void)writePng(dir + "viewer_" + tag + "_diff.png", diffImage(s.screenshot, s.reference, 4));
  ADD_FAILURE() << "actual/expected/diff PNGs written to " << dir << "viewer_" << tag << "_*.png";
}

void checkSession(bool hybrid, const std::string& tag, double psnrFloorDb) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  const Session s = runScripted(hybrid, tag);
  ASSERT_EQ(s.exitCode, 0);
  ASSERT_TRUE(s.referenceError.empty()) << s.referenceError;
  ASSERT_FALSE(s.screenshot.empty()) << "no screenshot written";
  // The window is 400×300 under Xvfb; the camera takes the framebuffer size.
  EXPECT_EQ(s.screenshot.width(), s.lastCamera.width);
  EXPECT_EQ(s.screenshot.height(), s.lastCamera.height);
  ASSERT_EQ(s.screenshot.width(), s.reference.width());
  ASSERT_EQ(s.screenshot.height(), s.reference.height());
  // The 15th frame of the played path (one path frame per displayed frame).
  const Camera expected = shortIndoorPath().cameraAt(14);
  EXPECT_NEAR(glm::length(s.lastCamera.eye - expected.eye), 0.0, 1e-9);

  // Not blank: a textured interior has thousands of colours.
  const std::size_t colours = distinctColours(s.screenshot);
  EXPECT_GT(colours, 500u);
  const Rgba8 first = s.screenshot.pixels().front();
  std::size_t same = 0;
  for (const Rgba8& p : s.screenshot.pixels()) same += (p == first);
  EXPECT_LT(same, s.screenshot.size() / 2);

  const double p = psnrCapped(s.screenshot, s.reference);
  std::printf("viewer %s: %zu colours, PSNR %.2f dB against the geometry reference\n", tag.c_str(),
              colours, p);
  EXPECT_GE(p, psnrFloorDb);
  if (::testing::Test::HasFailure()) writeFailureImages(s, tag);
}

TEST(Viewer, GeometryModeScreenshotMatchesReference) { checkSession(false, "geometry", 25.0); }

TEST(Viewer, HybridModeScreenshotMatchesReference) { checkSession(true, "hybrid", 20.0); }

// With OpenGL's warper the frames stay on the GPU (composed, hole-filled and
// shown from a texture); read back and composed on the CPU instead, the
// window shows the same pixels.
TEST(Viewer, FramesKeptOnTheGpuAreTheFramesComposedOnTheCpu) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  Session sessions[2];
  for (int onGpu = 0; onGpu < 2; ++onGpu)
    sessions[onGpu] = runScripted(true, onGpu ? "frames_gpu" : "frames_cpu", false, "", "",
                                  [onGpu](app::ViewerOptions& o) {
                                    o.warper = warp::WarperChoice::Gl;
                                    o.renderHoles = true;
                                    o.framesOn = onGpu ? app::ViewerOptions::FramesOn::Gpu
                                                       : app::ViewerOptions::FramesOn::Cpu;
                                  });
  for (const Session& s : sessions) {
    ASSERT_EQ(s.exitCode, 0);
    ASSERT_FALSE(s.screenshot.empty()) << "no screenshot written";
  }
  const Image<Rgba8>& cpu = sessions[0].screenshot;
  const Image<Rgba8>& gpu = sessions[1].screenshot;
  EXPECT_GT(distinctColours(gpu), 500u);
  ASSERT_EQ(cpu.width(), gpu.width());
  ASSERT_EQ(cpu.height(), gpu.height());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) differ += !(cpu.pixels()[i] == gpu.pixels()[i]);
  EXPECT_EQ(differ, 0u);
  EXPECT_GE(psnrCapped(gpu, sessions[1].reference), 20.0);
  if (::testing::Test::HasFailure()) writeFailureImages(sessions[1], "frames_gpu");
}

TEST(Viewer, HudIsDrawnOverTheFrame) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  const Session s = runScripted(false, "hud", /*hud=*/true);
  ASSERT_EQ(s.exitCode, 0);
  ASSERT_FALSE(s.screenshot.empty());
  ASSERT_EQ(s.screenshot.width(), s.reference.width());
  // The statistics line sits in the top-left corner: white text pixels there,
  // none of which the geometry frame has at exactly those places.
  int white = 0, differing = 0;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < s.screenshot.width() / 2; ++x) {
      const Rgba8 a = s.screenshot(x, y);
      white += (a.r == 255 && a.g == 255 && a.b == 255);
      differing += (a != s.reference(x, y));
    }
  EXPECT_GT(white, 50);
  EXPECT_GT(differing, 200);
  // Elsewhere the frame is untouched.
  Image<std::uint8_t> lowerHalf(s.screenshot.width(), s.screenshot.height(), 0);
  for (int y = s.screenshot.height() / 2; y < s.screenshot.height(); ++y)
    for (int x = 0; x < s.screenshot.width(); ++x) lowerHalf(x, y) = 1;
  EXPECT_GE(psnrCapped(s.screenshot, s.reference, lowerHalf), 40.0);
}

// The lowest row of the frame's left half holding HUD text: white pixels
// the geometry frame does not have there; -1: none.
int hudTextBottom(const Session& s) {
  int bottom = -1;
  for (int y = 0; y < s.screenshot.height(); ++y) {
    int white = 0;
    for (int x = 0; x < s.screenshot.width() / 2; ++x) {
      const Rgba8 a = s.screenshot(x, y);
      white += a.r == 255 && a.g == 255 && a.b == 255 && a != s.reference(x, y);
    }
    if (white >= 2) bottom = y;
  }
  return bottom;
}

// `s` cycles the statistics as docs/viewer.md says: from fps, a first `s`
// adds per-stage lines, a second the keyframe stalls (not HUD off), a third
// turns them off.
TEST(Viewer, SCyclesStatisticsThroughStallsToOff) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  int bottom[4] = {};
  const char* keys[4] = {"", "s", "ss", "sss"};
  for (int i = 0; i < 4; ++i) {
    const Session s = runScripted(false, std::string("stats") + std::to_string(i), true, keys[i]);
    ASSERT_EQ(s.exitCode, 0);
    ASSERT_FALSE(s.screenshot.empty());
    ASSERT_EQ(s.screenshot.width(), s.reference.width());
    bottom[i] = hudTextBottom(s);
  }
  std::printf("HUD text bottom row: fps %d, s %d, ss %d, sss %d\n", bottom[0], bottom[1],
              bottom[2], bottom[3]);
  EXPECT_GT(bottom[0], 0);
  EXPECT_GE(bottom[1], bottom[0] + 8);  // one more line (glyphs ~7 px, lines 10 px apart)
  EXPECT_GE(bottom[2], bottom[1] + 8);  // and the keyframe stalls line
  EXPECT_EQ(bottom[3], -1);             // off: no text at all
}

TEST(Viewer, DebugViewsAreDrawnInHybridMode) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  // s: per-stage statistics (fps is the default); w: quad outlines; o: keyframe
  // overlay; m: hole mask.
  const Session s = runScripted(true, "debug", /*hud=*/true, "swom");
  ASSERT_EQ(s.exitCode, 0);
  ASSERT_FALSE(s.screenshot.empty());
  ASSERT_EQ(s.screenshot.width(), s.reference.width());
  // Outlines (pure green / orange lines) cover a good part of the frame.
  long outline = 0;
  for (const Rgba8& p : s.screenshot.pixels())
    outline +=
        (p.g > 200 && p.r < 60 && p.b < 100) || (p.r > 230 && p.g > 120 && p.g < 180 && p.b < 60);
  EXPECT_GT(outline, 500);
  EXPECT_LT(psnrCapped(s.screenshot, s.reference), 20.0);
}

TEST(Viewer, RecordsThePathItWalks) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  const std::string rec = ::testing::TempDir() + "viewer_recorded.json";
  std::filesystem::remove(rec);
  // z starts recording on the first frame; the exit saves it.
  const Session s = runScripted(true, "record", false, "z", rec);
  ASSERT_EQ(s.exitCode, 0);
  auto path = scenes::loadCameraPath(rec);
  ASSERT_TRUE(path.ok()) << path.error().message;
  ASSERT_GE(path->keys.size(), 2u);
  EXPECT_EQ(path->frames, 15);
  const scenes::CameraPath played = shortIndoorPath();
  EXPECT_NEAR(glm::length(path->keys.front().eye - played.cameraAt(0).eye), 0.0, 1e-6);
  EXPECT_NEAR(glm::length(path->keys.back().eye - played.cameraAt(14).eye), 0.0, 1e-6);
}

// `view` takes its mode, LOD and keyframe worker from a preset
// (applyWalkOptions); whatever else a preset sets, the viewer does as the
// paper does, so no preset may set it otherwise.
TEST(ViewerPresets, PresetsDepartFromThePaperOnlyInWhatTheViewerCarries) {
  const session::WalkOptions paper = session::presetOptions(session::Preset::Paper);
  for (session::Preset p : {session::Preset::Default, session::Preset::Paper}) {
    session::WalkOptions rest = session::presetOptions(p);
    rest.mode = paper.mode;
    rest.lod = paper.lod;
    rest.asyncKeyframes = paper.asyncKeyframes;
    rest.renderHoles = paper.renderHoles;
    const session::PresetConflict c = session::differenceFromPaper(rest);
    EXPECT_TRUE(c.option.empty()) << session::presetName(p) << " sets " << c.option
                                  << ", which the viewer does not carry";
  }
}

TEST(ViewerPresets, TheViewerTakesThePresetsModeLodAndWorker) {
  for (session::Preset p : {session::Preset::Default, session::Preset::Paper}) {
    const session::WalkOptions w = session::presetOptions(p);
    app::ViewerOptions v;
    v.width = 123;  // not the preset's business: kept
    app::applyWalkOptions(w, &v);
    EXPECT_EQ(v.width, 123);
    EXPECT_EQ(v.mode, w.mode) << session::presetName(p);
    EXPECT_EQ(v.asyncKeyframes, w.asyncKeyframes) << session::presetName(p);
    EXPECT_EQ(v.renderHoles, w.renderHoles) << session::presetName(p);
    EXPECT_EQ(v.lod.tau, w.lod.tau);
    EXPECT_EQ(v.lod.tauParallaxPx, w.lod.tauParallaxPx);
    EXPECT_EQ(v.lod.planarity, w.lod.planarity);
    EXPECT_EQ(v.lod.mergeStrips, w.lod.mergeStrips);
    EXPECT_EQ(v.lod.criterion, w.lod.criterion);
    EXPECT_EQ(v.lod.tauGradient, w.lod.tauGradient);
  }
  // ViewerOptions{} is the paper's pipeline, as WalkOptions{} is.
  app::ViewerOptions plain, paper;
  app::applyWalkOptions(session::presetOptions(session::Preset::Paper), &paper);
  EXPECT_EQ(plain.mode, paper.mode);
  EXPECT_EQ(plain.asyncKeyframes, paper.asyncKeyframes);
  EXPECT_EQ(plain.renderHoles, paper.renderHoles);
  EXPECT_EQ(plain.lod.tau, paper.lod.tau);
  EXPECT_EQ(plain.lod.tauParallaxPx, paper.lod.tauParallaxPx);
}

// `view --warper` and `--warper-threads` reach the viewer's engine.
TEST(ViewerPresets, TheViewerTakesTheWarperOptions) {
  session::WalkOptions w = session::presetOptions(session::Preset::Default);
  w.warper = warp::WarperChoice::Gl;
  w.warperThreads = 3;
  app::ViewerOptions v;
  app::applyWalkOptions(w, &v);
  EXPECT_EQ(v.warper, warp::WarperChoice::Gl);
  EXPECT_EQ(v.warperThreads, 3);
  EXPECT_EQ(app::ViewerOptions{}.warperThreads, session::WalkOptions{}.warperThreads);
}

TEST(Viewer, BadPlayPathIsAnErrorExit) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr)
      << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  const std::string bad = ::testing::TempDir() + "viewer_bad_path.json";
  ASSERT_TRUE(writeFileAtomic(bad, "{\"keys\": [], \"bogus\": 1}").ok());
  app::ViewerOptions opt;
  opt.playPath = bad;
  opt.play = true;
  opt.exitAfterFrames = 2;
  ::testing::internal::CaptureStderr();
  const int code = app::runViewer(indoorScene(), scenes::defaultIndoorPath(), opt);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("hybridwalk: error:"), std::string::npos) << err;
  EXPECT_NE(err.find("viewer_bad_path.json"), std::string::npos) << err;
}

}  // namespace
}  // namespace hw
