// The interactive viewer: GLFW window, fly-through controls, hybrid frames
// from two keyframes kept around the viewer (Zheng et al. 1999 §2), HUD.
// Everything renders in the window's own context: the geometry renderer and
// the warper draw into their FBOs, the composed frame is uploaded into a
// texture and drawn with one full-screen triangle. With --async-keyframes a
// worker thread renders and meshes keyframes in a hidden window's context
// (keyframe/gl/async_keyframes.h) and the frame only uploads what it hands over.
// This file: set-up, input (keys, scripted keys, mouse and fly controls,
// path recording and playing) and the frame loop; the keyframes and frames
// are in viewer_keyframes.cpp, the drawing on screen in viewer_draw.cpp.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include "app/gl/viewer_impl.h"
#include "core/file_io.h"
#include "core/gl/gl_api.h"
#include "keyframe/geometry_renderer.h"
#include "session/frame_budget.h"
#include "warp/cpu_warper.h"

namespace hw::app::viewer_detail {
namespace {

constexpr double kMouseRadiansPerPixel = 0.0025;
constexpr double kShiftFactor = 4.0;
constexpr double kSpeedStep = 1.5;
constexpr double kRecordStep = 0.25;  // a recorded key every this much pose distance s

void charCallback(GLFWwindow* w, unsigned codepoint) {
  auto* q = static_cast<InputQueue*>(glfwGetWindowUserPointer(w));
  if (q && q->count < static_cast<int>(q->chars.size())) q->chars[q->count++] = codepoint;
}

void keyCallback(GLFWwindow* w, int key, int, int action, int) {
  if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
}
}  // namespace

Status Viewer::setUp() {
  HW_TRY(checkViewerOptions(opt_));
  scriptedKeys_ = *parseScriptedKeys(opt_.keys);  // checked

  scenes::CameraPath path = defaultPath_;
  if (!opt_.playPath.empty()) {
    auto p = scenes::loadCameraPath(opt_.playPath);
    if (!p) return p.error();
    path = std::move(*p);
    if (opt_.keyframeEvery > 0) path.keyframeEvery = opt_.keyframeEvery;
  }
  if (opt_.play && path.keys.empty())
    return makeError("--play needs a camera path with at least one key");

  const std::string title =
      "hybridwalk view" + (opt_.sceneLabel.empty() ? std::string() : " - " + opt_.sceneLabel);
  auto ctx = gl::createWindowContext(opt_.width, opt_.height, title, opt_.visible);
  if (!ctx) return ctx.error();
  ctx_ = std::move(*ctx);
  win_ = ctx_->window();
  glfwSetWindowUserPointer(win_, &input_);
  glfwSetCharCallback(win_, charCallback);
  glfwSetKeyCallback(win_, keyCallback);
  glfwSwapInterval(0);

  // The overlay composition needs no eye z; the large-leaf mask feeds only
  // the walk's psnr_large_quads.
  session::WalkOptions engineOptions;
  engineOptions.renderHoles = opt_.renderHoles;
  engineOptions.simplifyHoles = opt_.simplifyHoles;
  engineOptions.holeRectsMax = opt_.holeRectsMax;
  engineOptions.holeTilePx = opt_.holeTilePx;
  engineOptions.warper = opt_.warper;
  engineOptions.warperThreads = opt_.warperThreads;
  auto engine = session::FrameEngine::create(scene_, engineOptions, false, false);
  if (!engine) return engine.error();
  engine_ = std::move(*engine);
  // With OpenGL's warper on a GPU the frames stay there: composed,
  // hole-filled and shown there, never read back to draw the next one.
  {
    const char* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const bool software = name && warp::isSoftwareRasteriser(name);
    using FramesOn = ViewerOptions::FramesOn;
    if (opt_.framesOn == FramesOn::Gpu || (opt_.framesOn == FramesOn::Auto && !software))
      engine_->keepFramesOnGpu(true);
  }
  renderer_ = &engine_->renderer();
  lodOptions_ = opt_.lod;

  HW_TRY(createGlResources());

  // Session camera: fov and planes of the path; home at its first camera.
  setPlayPath(path);
  if (opt_.keyframeDb) {
    playingBakedPath_ = true;
    for (int f : opt_.keyframeDb->keyframeFrames()) {
      if (f < 0 || f >= static_cast<int>(playCams_.size()))
        return makeError(opt_.keyframeDb->dir() + ": keyframe of frame " + std::to_string(f) +
                         " is outside the play path's " + std::to_string(playCams_.size()) +
                         " frames (bake the database from this path)");
      dbFrames_.push_back(f);
      dbCams_.push_back(playCams_[static_cast<std::size_t>(f)]);
    }
    if (dbFrames_.empty()) return makeError(opt_.keyframeDb->dir() + ": the database has no keyframes");
    dbSource_ = keyframe::makeKeyframeDbSource(opt_.keyframeDb, /*prefetch=*/true);
  }
  base_ = playCams_.empty() ? Camera{} : playCams_.front();
  home_ = base_;
  const glm::dvec3 diag = glm::dvec3(scene_.boundsMax) - glm::dvec3(scene_.boundsMin);
  const double diagLen = std::max(glm::length(diag), 1e-3);
  double spacing = opt_.keyframeDistance;
  if (spacing <= 0 && playCams_.size() > 1) {
    double arc = 0;
    for (std::size_t i = 1; i < playCams_.size(); ++i)
      arc += glm::length(playCams_[i].eye - playCams_[i - 1].eye);
    spacing = arc / static_cast<double>(playCams_.size() - 1) * path.keyframeEvery;
  }
  kfDistance_ = spacing > 0 ? spacing : diagLen / 30.0;
  kfAngle_ = opt_.keyframeAngleDeg * kPi / 180.0;
  moveSpeed_ = diagLen / 20.0;
  hybrid_ = opt_.mode != session::FrameMode::Geometry;
  autoMode_ = opt_.mode == session::FrameMode::Auto;
  play_ = opt_.play;
  statsLevel_ = opt_.hud ? StatsLevel::Fps : StatsLevel::Off;
  poseFromCamera(home_);

  int fw = 0, fh = 0;
  glfwGetFramebufferSize(win_, &fw, &fh);
  HW_TRY(resize(fw, fh));
  // The viewer makes a keyframe about every half of the path's keyframe
  // spacing (one 1 unit ahead each time it passes the newest by 0.25, turns
  // counting too: 22 over the 120 frames of the indoor path, keyframe_every
  // 10), so the worker's pacing starts by spreading one over that many
  // frames; without lockstep it then follows the measured interval between
  // the viewer's requests and how soon the viewer would be lost
  // (workerPacingFrames), at most keyframe_every frames.
  if (opt_.asyncKeyframes) {
    pacingFrames_ = std::max(1.0, 0.5 * path.keyframeEvery);
    requestInterval_ = pacingFrames_;
    pacingFramesMax_ = std::max(1.0, static_cast<double>(path.keyframeEvery));
    workerEarly_ = !opt_.asyncLockstep;
    HW_TRY(startWorker(pacingFrames_));
  }
  // Auto mode compares measured costs, and the first render of the scene is
  // not one: llvmpipe compiles each shader variant at its first draw and the
  // scene's textures are uploaded then (indoor:2k at 320x240: a first
  // geometry frame of 21 ms, 3.6 ms after). One untimed render at the first
  // camera, as part of loading (about 250 ms on indoor:1M), so the geometry
  // renders the chooser measures are warm.
  if (autoMode_) HW_TRY(renderer_->renderColour(sized(base_), engine_->frame().colour));
  // Per-frame records (56 bytes each) for the exit summary and --frame-stats.
  records_.reserve(static_cast<std::size_t>(std::max(opt_.exitAfterFrames, 4096)));
  cam_ = play_ ? sized(playCams_.front()) : cameraFromPose();
  playFrame_ = play_ ? 0 : -1;
  prevCam_ = cam_;
  std::printf(
      "hybridwalk view: %s, %zu triangles, %dx%d, mode %s, %s (%s planarity%s); keyframe every "
      "%.3g units or %.3g deg. Press h for help.\n",
      opt_.sceneLabel.empty() ? "scene" : opt_.sceneLabel.c_str(), scene_.triangleCount(), width_,
      height_, session::frameModeName(opt_.mode), thresholdText().c_str(),
      keyframe::planarityName(lodOptions_.planarity),
      lodOptions_.mergeStrips ? ", merged strips" : "", kfDistance_, opt_.keyframeAngleDeg);
  if (opt_.keyframeDb)
    std::printf("hybridwalk view: %zu baked keyframes from %s (used near the baked path)\n",
                dbFrames_.size(), opt_.keyframeDb->dir().c_str());
  if (worker_)
    std::printf("hybridwalk view: keyframes rendered ahead on a worker thread (%s, hidden window)\n",
                worker_->glRenderer().c_str());
  std::fflush(stdout);
  return {};
}

void Viewer::releaseGl() {
  if (!ctx_) return;
  ctx_->makeCurrent();
  for (Slot& s : slots_)
    if (s.lineVbo) glDeleteBuffers(1, &s.lineVbo);
  const unsigned vaos[] = {emptyVao_, lineVao_, hudVao_};
  for (unsigned v : vaos)
    if (v) glDeleteVertexArrays(1, &v);
  const unsigned bufs[] = {hudVbo_, hudIbo_};
  for (unsigned b : bufs)
    if (b) glDeleteBuffers(1, &b);
  const unsigned texs[] = {colourTex_, holeTex_, overlayTex_};
  for (unsigned t : texs)
    if (t) glDeleteTextures(1, &t);
  displayProg_ = {};
  lineProg_ = {};
  hudProg_ = {};
  renderer_ = nullptr;
  engine_.reset();
}

Status Viewer::resize(int w, int h) {
  width_ = w;
  height_ = h;
  glBindTexture(GL_TEXTURE_2D, colourTex_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glBindTexture(GL_TEXTURE_2D, holeTex_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, w, h, 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
  for (Slot& s : slots_) s.valid = false;
  engine_->forgetPrevious();
  overlaySerial_ = -1;
  engine_->frame().colour.resize(w, h);
  engine_->frame().holesBefore.resize(w, h);
  engine_->frame().valid.resize(w, h);
  return gl::checkGlError("viewer resize");
}

void Viewer::setPlayPath(const scenes::CameraPath& path) {
  playingBakedPath_ = false;
  playCams_.clear();
  playCams_.reserve(static_cast<std::size_t>(path.frames));
  if (!path.keys.empty())
    playCams_ = path.cameras();
  playIndex_ = 0;
}

void Viewer::poseFromCamera(const Camera& c) {
  pose_ = flyPoseFromCamera(c);
}

Camera Viewer::cameraFromPose() const {
  // Scenes are Y-up (scenes/scene.h); pitch is clamped away from the pole.
  return flyCamera(pose_, sized(base_));
}

std::string Viewer::thresholdText() const {
  char buf[64];
  if (lodOptions_.tauParallaxPx > 0)
    std::snprintf(buf, sizeof buf, "tau-px %g", lodOptions_.tauParallaxPx);
  else
    std::snprintf(buf, sizeof buf, "tau %g", lodOptions_.tau);
  return buf;
}

void Viewer::message(const std::string& text) {
  std::snprintf(messageText_, sizeof messageText_, "%s", text.c_str());
  std::printf("%s\n", messageText_);
  std::fflush(stdout);
  messageUntil_ = clock_.ms() / 1000.0 + kMessageSeconds;
}

void Viewer::handleChar(unsigned c, bool flying) {
  // While flying, W/A/S/D/Q/E are movement, not commands.
  if (flying && (c == 'w' || c == 'a' || c == 's' || c == 'd' || c == 'q' || c == 'e' || c == 'W' ||
                 c == 'A' || c == 'S' || c == 'D' || c == 'Q' || c == 'E'))
    return;
  switch (c) {
    case 's':
      statsLevel_ = nextStatsLevel(statsLevel_);
      std::printf("%s\n", statsLevelDescription(statsLevel_));
      std::fflush(stdout);
      break;
    case 'w':
      wireframe_ = !wireframe_;
      break;
    case 'f':
      toggleFullScreen();
      break;
    case 'c':
      captureRequested_ = true;
      break;
    case 'z':
      toggleRecording();
      break;
    case 'Z':
      togglePlayRecorded();
      break;
    case ' ':
      play_ = false;
      poseFromCamera(home_);
      message("home");
      break;
    case 'h':
      help_ = !help_;
      std::printf("%s", viewerKeyHelp().c_str());
      std::fflush(stdout);
      break;
    case 'g':
      autoMode_ = false;  // the user's choice from now on
      hybrid_ = !hybrid_;
      engine_->forgetPrevious();
      message(hybrid_ ? "hybrid rendering" : "geometry rendering");
      break;
    case 'o':
      overlay_ = !overlay_;
      break;
    case 'm':
      holeMask_ = !holeMask_;
      break;
    case 'p':
      psnrRequested_ = true;
      break;
    case '+':
    case '=':
      moveSpeed_ *= kSpeedStep;
      break;
    case '-':
    case '_':
      moveSpeed_ /= kSpeedStep;
      break;
    default:
      break;
  }
}

void Viewer::toggleFullScreen() {
  if (glfwGetWindowMonitor(win_)) {
    glfwSetWindowMonitor(win_, nullptr, windowedX_, windowedY_, windowedW_, windowedH_, 0);
    return;
  }
  GLFWmonitor* monitor = glfwGetPrimaryMonitor();
  const GLFWvidmode* mode = monitor ? glfwGetVideoMode(monitor) : nullptr;
  if (!mode) {
    message("full screen: no monitor");
    return;
  }
  glfwGetWindowPos(win_, &windowedX_, &windowedY_);
  glfwGetWindowSize(win_, &windowedW_, &windowedH_);
  glfwSetWindowMonitor(win_, monitor, 0, 0, mode->width, mode->height, mode->refreshRate);
}

void Viewer::toggleRecording() {
  if (!recorder_.recording()) {
    recorder_.start(base_, width_, height_, kfDistance_, kRecordStep);
    message("recording a camera path (z: stop and save)");
    return;
  }
  const scenes::CameraPath& path = recorder_.stop(cam_, metric());
  const std::string file = opt_.recordPath.empty() ? "hybridwalk_path.json" : opt_.recordPath;
  const Status s = writeFileAtomic(file, scenes::cameraPathToJson(path));
  if (!s) {
    message("cannot save the path: " + s.error().message);
    return;
  }
  message("camera path saved to " + file + " (" + std::to_string(path.keys.size()) + " keys, " +
          std::to_string(path.frames) + " frames)");
}

void Viewer::togglePlayRecorded() {
  if (play_) {
    play_ = false;
    message("playback stopped");
    return;
  }
  const std::string file = opt_.recordPath.empty() ? "hybridwalk_path.json" : opt_.recordPath;
  if (std::filesystem::exists(file)) {
    auto p = scenes::loadCameraPath(file);
    if (!p) {
      message("cannot play: " + p.error().message);
      return;
    }
    setPlayPath(*p);
    message("playing " + file);
  } else if (!recorder_.path().keys.empty()) {
    setPlayPath(recorder_.path());
    message("playing the last recording");
  } else {
    message("nothing to play: " + file + " does not exist and nothing was recorded");
    return;
  }
  play_ = !playCams_.empty();
}

void Viewer::updateCamera(double dt) {
  // Mouse look while the right button is held.
  const bool rmb = glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  double mx = 0, my = 0;
  glfwGetCursorPos(win_, &mx, &my);
  if (rmb != mouseLook_) {
    mouseLook_ = rmb;
    glfwSetInputMode(win_, GLFW_CURSOR, rmb ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
    glfwGetCursorPos(win_, &mx, &my);
    lastMouseX_ = mx;
    lastMouseY_ = my;
  }
  auto down = [&](int key) { return glfwGetKey(win_, key) == GLFW_PRESS; };
  glm::dvec3 move(0.0);  // (right, up, forward) request
  if (mouseLook_) {
    if (down(GLFW_KEY_W)) move.z += 1;
    if (down(GLFW_KEY_S)) move.z -= 1;
    if (down(GLFW_KEY_D)) move.x += 1;
    if (down(GLFW_KEY_A)) move.x -= 1;
    if (down(GLFW_KEY_E)) move.y += 1;
    if (down(GLFW_KEY_Q)) move.y -= 1;
  }
  if (down(GLFW_KEY_UP)) move.z += 1;
  if (down(GLFW_KEY_DOWN)) move.z -= 1;
  if (down(GLFW_KEY_RIGHT)) move.x += 1;
  if (down(GLFW_KEY_LEFT)) move.x -= 1;
  if (down(GLFW_KEY_PAGE_UP)) move.y += 1;
  if (down(GLFW_KEY_PAGE_DOWN)) move.y -= 1;
  const double dmx = mouseLook_ ? mx - lastMouseX_ : 0, dmy = mouseLook_ ? my - lastMouseY_ : 0;
  lastMouseX_ = mx;
  lastMouseY_ = my;

  const bool userInput = move != glm::dvec3(0.0) || dmx != 0 || dmy != 0;
  if (play_ && userInput) {
    play_ = false;  // the user takes over where the path is
    poseFromCamera(cam_);
  }
  prevCam_ = cam_;
  playFrame_ = -1;
  if (play_ && !playCams_.empty()) {
    cam_ = sized(playCams_[static_cast<std::size_t>(playIndex_)]);
    playFrame_ = playIndex_;
    playIndex_ = (playIndex_ + 1) % static_cast<int>(playCams_.size());
  } else {
    const bool fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT);
    flyUpdate(pose_, dmx * kMouseRadiansPerPixel, -dmy * kMouseRadiansPerPixel, move,
              moveSpeed_ * (fast ? kShiftFactor : 1.0) * dt);
    cam_ = cameraFromPose();
  }
  motion_.update(prevCam_, cam_, dt);  // for placing the next keyframe ahead
  moving_ = poseDistance(cam_, prevCam_) > 1e-9;

  recorder_.addFrame(cam_, metric());
}

void Viewer::typeScriptedKeys() {
  for (; nextScriptedKey_ < scriptedKeys_.size() &&
         scriptedKeys_[nextScriptedKey_].frame <= frameIndex_;
       ++nextScriptedKey_)
    charCallback(win_, scriptedKeys_[nextScriptedKey_].key);
}

FrameRecord Viewer::frameRecord(double budgetMs) const {
  FrameRecord rec;
  rec.frame = frameIndex_;
  rec.playFrame = playFrame_;
  rec.keyframeMs = stats_.keyframeMs;
  rec.built = stats_.builtKeyframe;
  rec.read = stats_.readKeyframe;
  rec.worker = stats_.workerKeyframe;
  rec.requested = stats_.requestedKeyframe;
  rec.waited = stats_.waitedForKeyframe;
  rec.stalled = stats_.stalledOnWorker;
  rec.layers = stats_.hybrid ? stats_.layers : -1;
  rec.kind = stats_.kind();
  rec.holeRects = stats_.holeRects;
  rec.holeRectsOverBudget = stats_.holeRectsOverBudget;
  rec.holesMs = stats_.holesMs;
  rec.budgetMs = budgetMs;
  return rec;
}

Status Viewer::run() {
  HW_TRY(setUp());
  Stopwatch frameClock;
  double dt = 0;
  const bool autoBudget = opt_.frameBudgetAuto;
  session::AutoFrameBudget budget(std::max(1, opt_.frameBudgetWindow),
                                opt_.frameBudgetQuantile > 0 && opt_.frameBudgetQuantile <= 1
                                    ? opt_.frameBudgetQuantile
                                    : 0.9);
  while (!ctx_->shouldClose()) {
    const auto frameStart = std::chrono::steady_clock::now();
    const double budgetMs = autoBudget ? budget.budgetMs() : opt_.frameBudgetMs;
    ctx_->pollEvents();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(win_, &fw, &fh);
    if (fw <= 0 || fh <= 0) {  // minimised
      frameClock.restart();
      glfwWaitEventsTimeout(0.1);
      continue;
    }
    if (fw != width_ || fh != height_) HW_TRY(resize(fw, fh));
    typeScriptedKeys();
    const bool flying = glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    for (int i = 0; i < input_.count; ++i)
      handleChar(input_.chars[static_cast<std::size_t>(i)], flying);
    input_.count = 0;
    if (fw != width_ || fh != height_) continue;  // full-screen toggle: resize next frame

    updateCamera(dt);
    if (worker_) worker_->frameTick();  // pacing: a new frame's share of worker time
    HW_TRY(renderFrame());
    if (psnrRequested_) {
      psnrRequested_ = false;
      HW_TRY(computePsnr());
    }
    drawWindow();
    HW_TRY(gl::checkGlError("viewer frame"));
    if (captureRequested_) {
      captureRequested_ = false;
      capture();
    }
    FrameRecord rec = frameRecord(budgetMs);
    ++frameIndex_;
    const bool last = opt_.exitAfterFrames > 0 && frameIndex_ >= opt_.exitAfterFrames;
    if (last) {
      rec.ms = frameClock.ms();
      rec.workMs = rec.ms;  // not shown (no swap) and not paced
      records_.push_back(rec);
      break;  // the back buffer still holds this frame for the exit screenshot
    }
    ctx_->swapBuffers();
    // Slice pacing: the worker's share runs now, while this frame waits.
    if (worker_) worker_->runSlice();
    // Frame pacing: shown every budgetMs. The first frame renders (or waits
    // for) the first keyframe, a load: it does not count for the budget.
    rec.workMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                           frameStart)
                     .count();
    if (budgetMs > 0)
      std::this_thread::sleep_until(
          frameStart + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double, std::milli>(budgetMs)));
    if (autoBudget && frameIndex_ > 1) budget.add(rec.workMs);
    engine_->present();
    if (engine_->frame().colour.width() != width_ || engine_->frame().colour.height() != height_) {
      engine_->frame().colour.resize(width_, height_);
      engine_->frame().holesBefore.resize(width_, height_);
      engine_->frame().valid.resize(width_, height_);
    }
    dt = frameClock.lap() / 1000.0;
    const double ms = dt * 1000.0;
    rec.ms = ms;
    records_.push_back(rec);
    frameMsSmoothed_ = frameMsSmoothed_ > 0 ? 0.9 * frameMsSmoothed_ + 0.1 * ms : ms;
  }
  return finish();
}

// After the last frame: the exit screenshot, a recording in progress saved,
// the summary and --frame-stats.
Status Viewer::finish() {
  if (frameIndex_ > 0) {
    // Closed by the user: the engine's previous frame was the last one shown;
    // presenting again swaps it back into frame().
    if (!(opt_.exitAfterFrames > 0 && frameIndex_ >= opt_.exitAfterFrames)) {
      engine_->present();
      drawWindow();
    }
    if (!opt_.screenshotPath.empty()) {
      HW_TRY(screenshot(opt_.screenshotPath));
      std::printf("screenshot saved to %s\n", opt_.screenshotPath.c_str());
    }
    if (opt_.onExit) opt_.onExit(cam_);
  }
  if (recorder_.recording()) toggleRecording();  // save what was recorded
  printSummary();
  if (!opt_.frameStatsPath.empty()) {
    HW_TRY(writeFileAtomic(opt_.frameStatsPath, frameStatsCsv(records_)));
    std::printf("frame statistics saved to %s\n", opt_.frameStatsPath.c_str());
  }
  std::fflush(stdout);
  return {};
}

// The frames, how they were drawn (with --mode auto when it chose geometry),
// their times, and the keyframe stalls and waits.
// "keyframes built" counts every keyframe rendered for this viewer, in the
// frame or taken from the worker (as the walk's summary counts them).
void Viewer::printSummary() const {
  const std::string onWorker =
      worker_ ? " (" + std::to_string(keyframesFromWorker_) + " on the worker thread)" : "";
  std::printf("hybridwalk view: %ld frames, %ld keyframes built%s, %ld read from a database; last "
              "frame: %s\n",
              frameIndex_, keyframesBuilt_ + keyframesFromWorker_, onWorker.c_str(), keyframesRead_,
              !stats_.hybrid       ? "geometry"
              : stats_.direct      ? "hybrid, a keyframe at this camera shown as is"
              : stats_.layers == 2 ? "hybrid, two keyframes warped"
                                   : "hybrid, one keyframe warped");
  std::printf("%s", modeSummary(records_, opt_.mode, auto_.firstGeometryChoice(), auto_.switches()).c_str());
  const bool budget = opt_.frameBudgetMs > 0 || opt_.frameBudgetAuto;
  std::printf("%s", frameTimeSummary(records_, !budget              ? nullptr
                                               : opt_.frameBudgetAuto ? "auto"
                                                                      : "fixed")
                        .c_str());
  if (worker_)
    std::printf("hybridwalk view: keyframes async: %ld from the worker (%ld dropped as out of "
                "reach); %ld stalls (frames that rendered one or, lost, waited for the worker's; "
                "max %.1f ms), %ld frames warped older ones while one was in flight\n",
                keyframesFromWorker_, keyframesDiscarded_, keyframeStalls_, maxStallMs_, waitFrames_);
  else
    std::printf("hybridwalk view: keyframes in the frame: %ld stalls (max %.1f ms)\n",
                keyframeStalls_, maxStallMs_);
}

}  // namespace hw::app::viewer_detail

namespace hw::app {

int runViewer(const scenes::Scene& scene, const scenes::CameraPath& defaultPath,
              const ViewerOptions& options) {
  viewer_detail::Viewer viewer(scene, defaultPath, options);
  const Status s = viewer.run();
  if (!s) {
    std::fprintf(stderr, "hybridwalk: error: %s\n", s.error().message.c_str());
    return 1;
  }
  return 0;
}

}  // namespace hw::app
