// The interactive viewer: GLFW window, fly-through controls, hybrid frames
// from two keyframes kept around the viewer (Zheng et al. 1999 §2), HUD.
// Everything renders in the window's own context: the geometry renderer and
// the warper draw into their FBOs, the composed frame is uploaded into a
// texture and drawn with one full-screen triangle. With --async-keyframes a
// worker thread renders and meshes keyframes in a hidden window's context
// (keyframe/gl/async_keyframes.h) and the frame only uploads what it hands over.
#include "app/viewer.h"
#include "app/fly_pose.h"
#include "app/keyframe_pacing.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <stb_easy_font.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/gl/gl_api.h"
#include "core/gl/shader.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/gl/async_keyframes.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "session/frame_budget.h"
#include "session/frame_mode.h"
#include "session/hole_pass.h"
#include "session/frame_engine.h"
#include "session/in_between.h"
#include "session/keyframe_survey.h"
#include "warp/warper.h"

namespace hw::app {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMouseRadiansPerPixel = 0.0025;
constexpr double kShiftFactor = 4.0;
constexpr double kSpeedStep = 1.5;
constexpr double kMessageSeconds = 4.0;
// Keyframe policy, in units of the pose distance s (keyframeDistance and
// keyframeAngleDeg each count 1): session/keyframe_survey.h.
using session::kLost;
using session::kPassedNewest;
using session::kUseless;
// With the keyframe worker (not lockstep) the keyframe after the newest is
// requested once the viewer is kEarlyFraction of the way from the older
// keyframe to the newest (0: as soon as the newest has no successor in
// flight), kAheadSpacing beyond the newest (about where the synchronous
// viewer puts it: 1 ahead of a viewer that passed the newest by
// kPassedNewest), and put into a slot when the synchronous viewer would
// render it. Measured (indoor, 800x600, 120 frames of --play, 4-8 runs each):
// stalls 3-6 at 0.5, 1-4 at 0.25, 0-2 at 0.
constexpr double kAheadSpacing = 1.0 + kPassedNewest;
constexpr double kEarlyFraction = 0.0;
constexpr double kRecordStep = 0.25;  // a recorded key every this much s

constexpr const char* kHelp =
    "hybridwalk viewer keys\n"
    "  right mouse held: mouse look, W/A/S/D fly, Q/E down/up\n"
    "  arrows, PageUp/PageDown: move   Shift: x4   + / -: speed\n"
    "  s      statistics: off / fps / per-stage ms, quads, holes\n"
    "  w      wireframe (hybrid: warped quad outlines)\n"
    "  f      full screen\n"
    "  c      screenshot (PNG in the current directory)\n"
    "  z      record a camera path (again: stop and save)\n"
    "  Z      play the recorded path (again: stop)\n"
    "  space  home          Esc  quit\n"
    "  h      this help\n"
    "  g      hybrid / geometry rendering\n"
    "  o      quad overlay of the foreground keyframe\n"
    "  m      hole mask (red: no keyframe covers)\n"
    "  p      PSNR against the geometry reference\n";

const char* kDisplayVs = R"(#version 450 core
out vec2 vUv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  vUv = vec2(p.x, 1.0 - p.y);  // texture row 0 is the image's top row
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";
const char* kDisplayFs = R"(#version 450 core
in vec2 vUv;
uniform sampler2D colourTex;
uniform sampler2D holeTex;
uniform int showHoles;
out vec4 outColour;
void main() {
  vec3 c = texture(colourTex, vUv).rgb;
  if (showHoles != 0 && texture(holeTex, vUv).r > 0.5) c = mix(c, vec3(1.0, 0.0, 0.0), 0.7);
  outColour = vec4(c, 1.0);
})";
const char* kLineVs = R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 viewProj;
void main() { gl_Position = viewProj * vec4(position, 1.0); })";
const char* kLineFs = R"(#version 450 core
uniform vec4 colour;
out vec4 outColour;
void main() { outColour = colour; })";
const char* kHudVs = R"(#version 450 core
layout(location = 0) in vec2 position;  // pixels, y down
layout(location = 1) in vec4 colour;
uniform vec2 screen;
uniform float scale;
out vec4 vColour;
void main() {
  vec2 p = position * scale;
  gl_Position = vec4(p.x / screen.x * 2.0 - 1.0, 1.0 - p.y / screen.y * 2.0, 0.0, 1.0);
  vColour = colour;
})";
const char* kHudFs = R"(#version 450 core
in vec4 vColour;
out vec4 outColour;
void main() { outColour = vColour; })";

// stb_easy_font's vertex layout.
struct EasyVertex {
  float x, y, z;
  unsigned char c[4];
};
static_assert(sizeof(EasyVertex) == 16);
constexpr int kHudMaxQuads = 16384;

// Characters and Esc from GLFW callbacks, drained once per frame.
struct InputQueue {
  std::array<unsigned, 64> chars{};
  int count = 0;
};

void charCallback(GLFWwindow* w, unsigned codepoint) {
  auto* q = static_cast<InputQueue*>(glfwGetWindowUserPointer(w));
  if (q && q->count < static_cast<int>(q->chars.size())) q->chars[q->count++] = codepoint;
}

void keyCallback(GLFWwindow* w, int key, int, int action, int) {
  if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
}

void setFloatMatrix(int location, const glm::dmat4& m) {
  float f[16];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) f[c * 4 + r] = static_cast<float>(m[c][r]);
  glUniformMatrix4fv(location, 1, GL_FALSE, f);
}

// One keyframe around the viewer: its images, quad mesh, GPU copy and the
// quads' outlines (GL_LINES, world space) for the wireframe view.
struct Slot {
  bool valid = false;
  long serial = 0;    // build order; the highest is the newest
  int dbFrame = -1;   // the baked keyframe of this path frame; -1: rendered live
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  unsigned lineVbo = 0;
  int lineVertices = 0;
};

struct KeyframeStats {
  bool fromDb = false;  // read from the keyframe database (renderMs = read ms)
  bool fromWorker = false;  // built by the keyframe worker (its render and LOD ms)
  double renderMs = 0, lodMs = 0, uploadMs = 0;
  int quads = 0;
  std::size_t triangles = 0;  // built here: what its render drew
};

struct FrameStats {
  bool hybrid = true;
  bool direct = false;  // hybrid frame shown straight from a keyframe at this camera
  bool builtKeyframe = false;
  bool readKeyframe = false;  // one read from the keyframe database this frame
  bool backgroundSkipped = false;  // the foreground covered every pixel
  double geometryMs = 0;
  std::size_t trianglesDrawn = 0;
  double keyframeMs = 0;  // keyframe build, read or worker hand-over during this frame (0 if none)
  bool workerKeyframe = false;  // a keyframe from the worker was put into a slot
  bool requestedKeyframe = false;  // one was requested from the worker
  bool waitedForKeyframe = false;  // one was wanted and the worker's was not ready yet
  bool stalledOnWorker = false;  // lost: the frame waited for the worker's keyframe
  double warpAMs = 0, warpBMs = 0, composeMs = 0;
  int quadsA = 0, quadsB = 0, layers = 0;
  double holesBefore = 0, holesAfter = 0;
  // The hole pass: rectangles drawn, those left out by its budget, its ms.
  int holeRects = 0, holeRectsOverBudget = 0;
  double holesMs = 0;
  // Drawn by the geometry renderer; else hybrid: a keyframe frame when one
  // was rendered, read or taken from the worker in it (its cost is the
  // keyframe's), otherwise warped.
  session::FrameKind kind() const {
    if (!hybrid) return session::FrameKind::Geometry;
    return builtKeyframe || readKeyframe || workerKeyframe ? session::FrameKind::Keyframe
                                                           : session::FrameKind::Warp;
  }
};

// One row of ViewerOptions::frameStatsPath.
struct FrameRecord {
  long frame = 0;
  int playFrame = -1;
  double ms = 0;  // from the end of the previous frame to the end of this one
  double workMs = 0;    // from the start of this frame until it was shown (pacing wait excluded)
  double budgetMs = 0;  // this frame's budget (--frame-budget-ms; 0 = none)
  double keyframeMs = 0;
  bool built = false, read = false, worker = false, requested = false, waited = false,
       stalled = false;
  int layers = 0;
  session::FrameKind kind = session::FrameKind::Warp;
  int holeRects = 0, holeRectsOverBudget = 0;  // the hole pass (FrameStats)
  double holesMs = 0;
};

class Viewer {
 public:
  Viewer(const scenes::Scene& scene, const scenes::CameraPath& defaultPath,
         const ViewerOptions& options)
      : scene_(scene), defaultPath_(defaultPath), opt_(options) {}
  ~Viewer() {
    stopWorker();
    releaseGl();
  }
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  Status run();

 private:
  Status setUp();
  void releaseGl();
  Status resize(int w, int h);
  void setPlayPath(const scenes::CameraPath& path);
  void poseFromCamera(const Camera& c);
  Camera cameraFromPose() const;
  Camera sized(Camera c) const {
    c.width = width_;
    c.height = height_;
    return c;
  }
  double poseDistance(const Camera& a, const Camera& b) const {
    return glm::length(a.eye - b.eye) / kfDistance_ + angleBetween(a.forward, b.forward) / kfAngle_;
  }
  void handleChar(unsigned c, bool flying);
  void updateCamera(double dt);
  Status renderFrame();
  Status renderHybrid(FrameStats& st);
  Status buildKeyframe(Slot& slot, const Camera& cam);
  Status startWorker(double framesPerKeyframe);
  void stopWorker();
  void requestFromWorker(const Camera& cam);
  Status takeFromWorker(FrameStats& st, bool wait);
  Status writeFrameStats() const;
  void printFrameSummary() const;
  void printModeSummary() const;
  Status readKeyframe(Slot& slot, int frame);
  Status finishSlot(Slot& slot);
  Status liveKeyframes(FrameStats& st, int& a, int& b);
  Status bakedKeyframes(FrameStats& st, int& a, int& b, bool& used);
  Camera aheadCamera(double distance = 1.0) const;
  Camera beyondCamera(const Camera& newest, double spacing, double distance) const;
  Status computePsnr();
  void drawWindow();
  void drawHud();
  void hudBlock(float x, float y, char* text, const unsigned char colour[4]);
  void readWindow(Image<Rgba8>& out);
  Status screenshot(const std::string& path);
  void toggleRecording();
  void togglePlayRecorded();
  void toggleFullScreen();
  void message(const std::string& text);
  std::string thresholdText() const;  // "tau-px 0.125" or "tau 2048"

  const scenes::Scene& scene_;
  const scenes::CameraPath& defaultPath_;
  const ViewerOptions& opt_;

  // Declared first, destroyed last: every GL object below needs it.
  std::unique_ptr<gl::WindowContext> ctx_;
  // Keyframe worker (ViewerOptions::asyncKeyframes) and its hidden window;
  // stopWorker() joins the worker (which lets go of the window's context)
  // before the window is destroyed, on this thread.
  std::unique_ptr<gl::WindowContext> workerWindow_;
  std::unique_ptr<keyframe::AsyncKeyframes> worker_;
  std::mutex workerCamMutex_;
  std::array<Camera, 8> workerCams_;  // camera of request id, at id % 8 (≤ 2 outstanding)
  int nextRequestId_ = 0;
  int pendingId_ = -1;  // requested, not taken yet
  Camera pendingCam_;
  long pendingSinceFrame_ = 0;
  double pendingSinceMs_ = 0;
  bool workerWarm_ = false;  // its first keyframe was taken (pacing has a build time)
  // Early requests and measured pacing (not lockstep; app/keyframe_pacing.h).
  bool workerEarly_ = false;
  long aheadOfSerial_ = -1;  // newest keyframe whose successor was requested early
  long lastAheadRequestFrame_ = -1;
  double requestInterval_ = 0;  // running estimate of frames between ahead requests
  double pacingFramesMax_ = 1;  // the path's keyframe_every
  double pacingFrames_ = 0;     // what the worker was last told
  long keyframesFromWorker_ = 0, keyframesDiscarded_ = 0, keyframeStalls_ = 0, waitFrames_ = 0;
  long lastLatencyFrames_ = 0;
  double lastLatencyMs_ = 0, maxStallMs_ = 0;
  std::vector<FrameRecord> records_;
  GLFWwindow* win_ = nullptr;
  InputQueue input_;
  // Renderer, warper, keyframes on the GPU (by slot serial), in-between step,
  // hole pass and the frames: the walk's frame engine.
  std::unique_ptr<session::FrameEngine> engine_;
  keyframe::GeometryRenderer* renderer_ = nullptr;  // the engine's
  keyframe::LodBuilder lod_;
  keyframe::LodOptions lodOptions_;
  gl::Program displayProg_, lineProg_, hudProg_;
  int uShowHoles_ = -1, uViewProj_ = -1, uLineColour_ = -1, uScreen_ = -1, uScale_ = -1;
  unsigned emptyVao_ = 0, lineVao_ = 0, hudVao_ = 0, hudVbo_ = 0, hudIbo_ = 0;
  unsigned colourTex_ = 0, holeTex_ = 0, overlayTex_ = 0;

  int width_ = 0, height_ = 0;  // framebuffer size = render size
  Camera base_;                 // fov, near, far of the session
  Camera home_;
  Camera cam_, prevCam_;
  FlyPose pose_;  // fly controls (app/fly_pose.h)
  glm::dvec3 velocity_{0.0};  // smoothed, units/s
  double yawRate_ = 0, pitchRate_ = 0;
  double moveSpeed_ = 1;  // units/s
  double kfDistance_ = 1, kfAngle_ = 0.25;
  bool mouseLook_ = false;
  double lastMouseX_ = 0, lastMouseY_ = 0;

  bool hybrid_ = true, wireframe_ = false, overlay_ = false, holeMask_ = false, help_ = false;
  // ViewerOptions::mode Auto: every kAutoFrames frames, hybrid or geometry,
  // whichever the chooser predicts cheaper from this session's frames.
  static constexpr int kAutoFrames = 10, kAutoProbeEvery = 4, kAutoMinGeometrySamples = 3;
  bool autoMode_ = false;
  session::ModeChooser chooser_;
  int framesSinceChoice_ = 0, choicesSinceProbe_ = 0, geometrySamples_ = 0;
  long autoSwitches_ = 0, firstGeometryChoice_ = -1;  // frame of the first switch to geometry
  void chooseMode(bool* probe);
  void recordCost(const FrameStats& st, double workMs);
  int statsLevel_ = 1;  // 0 off, 1 fps, 2 per stage
  bool play_ = false;
  std::vector<Camera> playCams_;
  int playIndex_ = 0;
  int playFrame_ = -1;           // frame of the play path shown now; -1: not playing it
  bool playingBakedPath_ = false;  // playCams_ is the path the database was baked from
  bool recording_ = false;
  scenes::CameraPath recorded_;
  Camera lastRecordedKey_;
  int recordedFrames_ = 0;
  bool captureRequested_ = false, psnrRequested_ = false;
  int windowedX_ = 0, windowedY_ = 0, windowedW_ = 0, windowedH_ = 0;

  std::array<Slot, 2> slots_;
  long serial_ = 0;
  double newestSPrev_ = 0;
  long newestSerialPrev_ = -1;
  bool moving_ = false;
  KeyframeStats lastKeyframe_;
  FrameStats stats_;
  int foregroundSlot_ = -1;
  long overlaySerial_ = -1;
  int overlayW_ = 0, overlayH_ = 0;
  Image<Rgba8> reference_, windowImage_;
  std::vector<Rgba8> readScratch_;
  std::vector<float> lineScratch_;
  std::vector<EasyVertex> hudVerts_;
  int hudQuads_ = 0;
  char hudText_[2048] = {};
  char messageText_[512] = {};
  double messageUntil_ = 0;
  char psnrText_[128] = {};
  double psnrUntil_ = 0;
  double frameMsSmoothed_ = 0;
  char keyframeLine_[256] = {};
  long keyframesBuilt_ = 0;
  long keyframesRead_ = 0;
  long frameIndex_ = 0;
  // Baked keyframes (ViewerOptions::keyframeDb).
  std::vector<int> dbFrames_;     // their path frames, ascending
  std::vector<Camera> dbCams_;    // their cameras (the baked path's)
  keyframe::KeyframeCache::Source dbSource_;
  keyframe::CachedKeyframe dbScratch_;
  int onBakedPath_ = -1;  // last frame's state (1 baked, 0 live, -1 none yet) for messages
  Stopwatch clock_;
  Stopwatch frameWork_;  // this frame's work so far (the hole pass's budget)
};

Status Viewer::setUp() {
  if (opt_.width < 16 || opt_.height < 16 || opt_.width > 16384 || opt_.height > 16384)
    return makeError("window size must be in [16, 16384] pixels, got " +
                     std::to_string(opt_.width) + "x" + std::to_string(opt_.height));
  if (!(opt_.lod.tau >= 0) || !std::isfinite(opt_.lod.tau))
    return makeError("tau must be finite and >= 0, got " + std::to_string(opt_.lod.tau));
  if (!(opt_.lod.tauParallaxPx >= 0) || !std::isfinite(opt_.lod.tauParallaxPx))
    return makeError("tau-px must be finite and >= 0, got " +
                     std::to_string(opt_.lod.tauParallaxPx));
  if (!(opt_.lod.tauGradient >= 0) || !std::isfinite(opt_.lod.tauGradient))
    return makeError("tau gradient must be finite and >= 0, got " +
                     std::to_string(opt_.lod.tauGradient));
  if (!(opt_.keyframeAngleDeg > 0 && opt_.keyframeAngleDeg < 180) ||
      !(opt_.keyframeDistance >= 0) || !std::isfinite(opt_.keyframeDistance))
    return makeError("keyframe thresholds: distance must be >= 0 and angle in (0, 180) degrees");
  if (opt_.exitAfterFrames < 0)
    return makeError("exit-after frame count must be >= 0, got " +
                     std::to_string(opt_.exitAfterFrames));

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
  auto engine = session::FrameEngine::create(scene_, session::WalkOptions{}, false, false);
  if (!engine) return engine.error();
  engine_ = std::move(*engine);
  renderer_ = &engine_->renderer();
  lodOptions_ = opt_.lod;

  auto dp = gl::Program::build("viewer display", kDisplayVs, kDisplayFs);
  if (!dp) return dp.error();
  displayProg_ = std::move(*dp);
  auto lp = gl::Program::build("viewer lines", kLineVs, kLineFs);
  if (!lp) return lp.error();
  lineProg_ = std::move(*lp);
  auto hp = gl::Program::build("viewer HUD", kHudVs, kHudFs);
  if (!hp) return hp.error();
  hudProg_ = std::move(*hp);
  displayProg_.use();
  glUniform1i(displayProg_.uniform("colourTex"), 0);
  glUniform1i(displayProg_.uniform("holeTex"), 1);
  uShowHoles_ = displayProg_.uniform("showHoles");
  uViewProj_ = lineProg_.uniform("viewProj");
  uLineColour_ = lineProg_.uniform("colour");
  uScreen_ = hudProg_.uniform("screen");
  uScale_ = hudProg_.uniform("scale");

  glGenVertexArrays(1, &emptyVao_);
  glGenVertexArrays(1, &lineVao_);
  glGenVertexArrays(1, &hudVao_);
  glGenBuffers(1, &hudVbo_);
  glGenBuffers(1, &hudIbo_);
  hudVerts_.resize(static_cast<std::size_t>(kHudMaxQuads) * 4);
  {
    std::vector<std::uint32_t> idx(static_cast<std::size_t>(kHudMaxQuads) * 6);
    for (std::uint32_t q = 0; q < static_cast<std::uint32_t>(kHudMaxQuads); ++q) {
      const std::uint32_t v = q * 4, o = q * 6;
      idx[o] = v, idx[o + 1] = v + 1, idx[o + 2] = v + 2;
      idx[o + 3] = v, idx[o + 4] = v + 2, idx[o + 5] = v + 3;
    }
    glBindVertexArray(hudVao_);
    glBindBuffer(GL_ARRAY_BUFFER, hudVbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(hudVerts_.size() * sizeof(EasyVertex)),
                 nullptr, GL_STREAM_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(EasyVertex), nullptr);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(EasyVertex),
                          reinterpret_cast<const void*>(offsetof(EasyVertex, c)));
    glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, hudIbo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(),
                 GL_STATIC_DRAW);
    glBindVertexArray(0);
  }
  glGenTextures(1, &colourTex_);
  glGenTextures(1, &holeTex_);
  glGenTextures(1, &overlayTex_);
  for (unsigned t : {colourTex_, holeTex_, overlayTex_}) {
    glBindTexture(GL_TEXTURE_2D, t);
    const int filter = t == overlayTex_ ? GL_LINEAR : GL_NEAREST;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  for (Slot& s : slots_) glGenBuffers(1, &s.lineVbo);
  HW_TRY(gl::checkGlError("viewer set-up"));

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
  statsLevel_ = opt_.hud ? 1 : 0;
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
  for (char c : opt_.keys) charCallback(win_, static_cast<unsigned char>(c));
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

Status Viewer::startWorker(double framesPerKeyframe) {
  auto second = gl::createSecondWindowContext(*ctx_);
  if (!second)
    return makeError("keyframe worker (--async-keyframes): " + second.error().message);
  workerWindow_ = std::move(*second);
  keyframe::AsyncKeyframeOptions a;
  a.mesh = keyframe::MeshSpec{keyframe::MeshMethod::Lod, lodOptions_, 8};
  a.maxQueued = 2;  // one in flight, and a lost frame's
  a.flushEveryTriangles = opt_.keyframeFlushTriangles;
  using P = ViewerOptions::KeyframePacing;
  if (opt_.keyframePacing == P::Steps) a.stepsPerFrame = std::max(1, opt_.keyframeStepsPerFrame);
  if (opt_.keyframePacing == P::Time || opt_.keyframePacing == P::Slices) {
    a.framesPerKeyframe = framesPerKeyframe;
    a.budgetScale = opt_.keyframeBudgetScale;
    a.slices = opt_.keyframePacing == P::Slices;
  }
  gl::WindowContext* hidden = workerWindow_.get();
  a.makeContext = [hidden] { return gl::attachWindowContext(*hidden); };
  auto w = keyframe::AsyncKeyframes::create(
      scene_,
      [this](int id) {
        std::lock_guard lock(workerCamMutex_);
        return workerCams_[static_cast<std::size_t>(id) % workerCams_.size()];
      },
      a);
  if (!w) {
    workerWindow_.reset();  // the worker has exited and let go of it
    return makeError(w.error().message + " (--async-keyframes)");
  }
  worker_ = std::move(*w);
  return {};
}

void Viewer::stopWorker() {
  worker_.reset();        // joins; the worker detaches the hidden window's context
  workerWindow_.reset();  // destroyed on this (the main) thread, as GLFW requires
  if (ctx_) ctx_->makeCurrent();
}

void Viewer::requestFromWorker(const Camera& cam) {
  const int id = nextRequestId_;
  {
    std::lock_guard lock(workerCamMutex_);
    workerCams_[static_cast<std::size_t>(id) % workerCams_.size()] = cam;
  }
  if (!worker_->request(id)) return;  // full (a lost frame's is still queued): next frame
  ++nextRequestId_;
  pendingId_ = id;
  pendingCam_ = cam;
  pendingSinceFrame_ = frameIndex_;
  pendingSinceMs_ = clock_.ms();
}

// The pending keyframe into the slot it replaces: an empty one, else the one
// farther from the viewer (the synchronous viewer's choice at request time).
// Without `wait` only when it is ready; a keyframe no longer within reach
// (or of another window size) is dropped.
Status Viewer::takeFromWorker(FrameStats& st, bool wait) {
  // finished, not ready: a failed build comes back from take() as an error
  // (the viewer exits with it) instead of staying pending.
  if (pendingId_ < 0 || (!wait && !worker_->finished(pendingId_))) return {};
  Stopwatch kt;
  std::unique_ptr<keyframe::CachedKeyframe> e;
  double waitedMs = 0;
  const int id = pendingId_;
  pendingId_ = -1;
  HW_TRY(worker_->take(id, &e, &waitedMs));
  lastLatencyFrames_ = frameIndex_ - pendingSinceFrame_;
  lastLatencyMs_ = clock_.ms() - pendingSinceMs_;
  const Camera& c = e->keyframe.camera;
  if (c.width != width_ || c.height != height_ || (!wait && poseDistance(c, cam_) >= kUseless)) {
    ++keyframesDiscarded_;
    worker_->recycle(std::move(e));
    return {};
  }
  int target = 0;
  if (slots_[0].valid && slots_[1].valid)
    target = poseDistance(slots_[0].kf.camera, cam_) <= poseDistance(slots_[1].kf.camera, cam_) ? 1 : 0;
  else if (slots_[0].valid)
    target = 1;
  Slot& slot = slots_[static_cast<std::size_t>(target)];
  slot.valid = false;
  std::swap(slot.kf, e->keyframe);
  std::swap(slot.mesh, e->mesh);
  lastKeyframe_.fromDb = false;
  lastKeyframe_.fromWorker = true;
  lastKeyframe_.renderMs = e->renderMs;
  lastKeyframe_.lodMs = slot.mesh.stats.deltaMs + slot.mesh.stats.subdivideMs + slot.mesh.stats.cornersMs;
  worker_->recycle(std::move(e));  // the slot's old buffers, for a later build
  slot.dbFrame = -1;
  HW_TRY(finishSlot(slot));
  ++keyframesFromWorker_;
  workerWarm_ = true;
  st.workerKeyframe = true;
  st.keyframeMs += kt.ms();
  if (opt_.onKeyframe) opt_.onKeyframe(slot.kf, slot.mesh, true);
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
      statsLevel_ = (statsLevel_ + 1) % 3;
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
      std::printf("%s", kHelp);
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
  const glm::dvec3 look = cam_.eye + cam_.forward * kfDistance_;
  if (!recording_) {
    recorded_ = scenes::CameraPath{};
    recorded_.width = width_;
    recorded_.height = height_;
    recorded_.fovYDeg = base_.fovYRadians * 180.0 / kPi;
    recorded_.nearPlane = base_.nearPlane;
    recorded_.farPlane = base_.farPlane;
    recordedFrames_ = 0;  // keys and frames are added from this frame's camera on
    recording_ = true;
    message("recording a camera path (z: stop and save)");
    return;
  }
  recording_ = false;
  if (recorded_.keys.empty() || poseDistance(cam_, lastRecordedKey_) > 0)
    recorded_.keys.push_back({cam_.eye, look});
  recorded_.frames = std::max(recordedFrames_, 1);
  const std::string file = opt_.recordPath.empty() ? "hybridwalk_path.json" : opt_.recordPath;
  const Status s = writeFileAtomic(file, scenes::cameraPathToJson(recorded_));
  if (!s) {
    message("cannot save the path: " + s.error().message);
    return;
  }
  message("camera path saved to " + file + " (" + std::to_string(recorded_.keys.size()) +
          " keys, " + std::to_string(recorded_.frames) + " frames)");
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
  } else if (!recorded_.keys.empty()) {
    setPlayPath(recorded_);
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
  // Smoothed motion, for placing the next keyframe ahead of the viewer.
  if (dt > 1e-6) {
    constexpr double kSmooth = 0.5;
    const glm::dvec3 v = (cam_.eye - prevCam_.eye) / dt;
    const double py = std::atan2(prevCam_.forward.x, -prevCam_.forward.z);
    const double cy = std::atan2(cam_.forward.x, -cam_.forward.z);
    double dyaw = cy - py;
    if (dyaw > kPi) dyaw -= 2 * kPi;
    if (dyaw < -kPi) dyaw += 2 * kPi;
    const double dpitch = std::asin(std::clamp(cam_.forward.y, -1.0, 1.0)) -
                          std::asin(std::clamp(prevCam_.forward.y, -1.0, 1.0));
    velocity_ = glm::mix(velocity_, v, kSmooth);
    yawRate_ = yawRate_ + kSmooth * (dyaw / dt - yawRate_);
    pitchRate_ = pitchRate_ + kSmooth * (dpitch / dt - pitchRate_);
  }
  moving_ = poseDistance(cam_, prevCam_) > 1e-9;

  if (recording_) {
    ++recordedFrames_;
    if (recorded_.keys.empty() || poseDistance(cam_, lastRecordedKey_) >= kRecordStep) {
      recorded_.keys.push_back({cam_.eye, cam_.eye + cam_.forward * kfDistance_});
      lastRecordedKey_ = cam_;
    }
  }
}

// Where the viewer will be when it is `distance` pose-distance units away:
// the path's camera when playing, else the current motion extrapolated.
Camera Viewer::aheadCamera(double distance) const {
  if (play_ && playCams_.size() > 1) {
    const int n = static_cast<int>(playCams_.size());
    Camera best = cam_;
    double bestS = -1;
    for (int k = 0; k < n - 1; ++k) {
      const Camera& c = playCams_[static_cast<std::size_t>((playIndex_ + k) % n)];
      const double s = poseDistance(c, cam_);
      if (s > bestS) best = c, bestS = s;
      if (s >= distance) break;
    }
    return sized(best);
  }
  const double rate = glm::length(velocity_) / kfDistance_ +
                      std::sqrt(yawRate_ * yawRate_ + pitchRate_ * pitchRate_) / kfAngle_;
  if (!(rate > 1e-9)) return cam_;
  const double t = distance / rate;
  const glm::dvec3 eye = cam_.eye + velocity_ * t;
  const double yaw = std::atan2(cam_.forward.x, -cam_.forward.z) + yawRate_ * t;
  const double pitch = std::clamp(std::asin(std::clamp(cam_.forward.y, -1.0, 1.0)) + pitchRate_ * t,
                                  -kMaxFlyPitch, kMaxFlyPitch);
  return Camera::lookAt(eye, eye + flyForward(yaw, pitch), glm::dvec3(0, 1, 0), cam_.fovYRadians,
                        width_, height_, cam_.nearPlane, cam_.farPlane);
}

// The keyframe after `newest`, `spacing` beyond it: playing, the first
// camera of the path after the viewer that is that far from the newest and
// farther from the viewer than the newest (so past it; pose distance along a
// bending path is not additive, so the distance from the viewer would not
// do); else the motion extrapolated to `distance` from the viewer.
Camera Viewer::beyondCamera(const Camera& newest, double spacing, double distance) const {
  if (!(play_ && playCams_.size() > 1)) return aheadCamera(distance);
  const int n = static_cast<int>(playCams_.size());
  const double sNewest = poseDistance(newest, cam_);
  Camera best = cam_;
  double bestS = -1;
  for (int k = 0; k < n - 1; ++k) {
    const Camera& c = playCams_[static_cast<std::size_t>((playIndex_ + k) % n)];
    if (poseDistance(c, cam_) <= sNewest) continue;  // not past the newest yet
    const double s = poseDistance(c, newest);
    if (s > bestS) best = c, bestS = s;
    if (s >= spacing) break;
  }
  return sized(best);
}

Status Viewer::buildKeyframe(Slot& slot, const Camera& cam) {
  Stopwatch sw;
  keyframe::RenderStats rs;
  HW_TRY(renderer_->renderKeyframe(cam, slot.kf, &rs));
  lastKeyframe_.fromDb = false;
  lastKeyframe_.renderMs = sw.lap();
  lastKeyframe_.triangles = rs.trianglesDrawn;
  HW_TRY(lod_.build(slot.kf, lodOptions_, &slot.mesh));
  lastKeyframe_.lodMs = sw.lap();
  lastKeyframe_.fromWorker = false;
  slot.dbFrame = -1;
  HW_TRY(finishSlot(slot));
  ++keyframesBuilt_;
  if (opt_.onKeyframe) opt_.onKeyframe(slot.kf, slot.mesh, false);
  return {};
}

Status Viewer::readKeyframe(Slot& slot, int frame) {
  Stopwatch sw;
  slot.valid = false;
  HW_TRY(dbSource_(frame, dbScratch_));
  lastKeyframe_.fromDb = true;
  lastKeyframe_.fromWorker = false;
  lastKeyframe_.renderMs = sw.lap();  // wait + read + checksum + decode
  lastKeyframe_.lodMs = 0;
  std::swap(slot.kf, dbScratch_.keyframe);
  std::swap(slot.mesh, dbScratch_.mesh);
  slot.dbFrame = frame;
  HW_TRY(finishSlot(slot));
  ++keyframesRead_;
  return {};
}

// GPU copy and wireframe lines of a slot whose keyframe and mesh are set.
Status Viewer::finishSlot(Slot& slot) {
  Stopwatch sw;
  engine_->release(static_cast<int>(slot.serial));
  HW_TRY(engine_->upload(static_cast<int>(serial_ + 1), slot.kf, slot.mesh, slot.kf.camera.eye,
                         nullptr));
  // Quad outlines for the wireframe view: 4 edges, 8 vertices per quad.
  lineScratch_.clear();
  for (const keyframe::Quad& q : slot.mesh.quads)
    for (int e = 0; e < 4; ++e)
      for (const glm::dvec3& p :
           {q.world[static_cast<std::size_t>(e)], q.world[static_cast<std::size_t>((e + 1) % 4)]}) {
        lineScratch_.push_back(static_cast<float>(p.x));
        lineScratch_.push_back(static_cast<float>(p.y));
        lineScratch_.push_back(static_cast<float>(p.z));
      }
  glBindBuffer(GL_ARRAY_BUFFER, slot.lineVbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lineScratch_.size() * sizeof(float)),
               lineScratch_.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  slot.lineVertices = static_cast<int>(lineScratch_.size() / 3);
  lastKeyframe_.uploadMs = sw.lap();
  lastKeyframe_.quads = slot.mesh.stats.quads;
  slot.valid = true;
  slot.serial = ++serial_;
  return {};
}

// Baked keyframes for this frame: playing the baked path, the walk's pair for
// the frame (KeyframeSchedule::bracket over the database's keyframes, the
// earlier one first as in the walk); otherwise the two nearest by pose
// distance. `used` false: none is within kLost (or the window is not the
// database's size), so the caller renders keyframes live.
Status Viewer::bakedKeyframes(FrameStats& st, int& a, int& b, bool& used) {
  used = false;
  if (!opt_.keyframeDb || dbCams_.front().width != width_ || dbCams_.front().height != height_)
    return {};
  int want0 = -1, want1 = -1;
  if (play_ && playingBakedPath_ && playFrame_ >= dbFrames_.front() &&
      playFrame_ <= dbFrames_.back()) {
    const auto it = std::lower_bound(dbFrames_.begin(), dbFrames_.end(), playFrame_);
    want1 = *it;
    want0 = *it == playFrame_ ? want1 : *(it - 1);
  } else {
    double s0 = 1e300, s1 = 1e300;
    for (std::size_t i = 0; i < dbCams_.size(); ++i) {
      const double si = poseDistance(dbCams_[i], cam_);
      if (si < s0) {
        s1 = s0, want1 = want0;
        s0 = si, want0 = dbFrames_[i];
      } else if (si < s1) {
        s1 = si, want1 = dbFrames_[i];
      }
    }
    if (s0 > kLost) return {};
    if (s1 >= kUseless) want1 = -1;
  }
  if (want1 == want0) want1 = -1;
  auto slotOf = [&](int frame) {
    for (int i = 0; i < 2; ++i)
      if (slots_[static_cast<std::size_t>(i)].valid &&
          slots_[static_cast<std::size_t>(i)].dbFrame == frame)
        return i;
    return -1;
  };
  Stopwatch kt;
  a = slotOf(want0);
  b = want1 >= 0 ? slotOf(want1) : -1;
  if (a < 0) {
    a = b >= 0 ? 1 - b : 0;
    HW_TRY(readKeyframe(slots_[static_cast<std::size_t>(a)], want0));
    st.readKeyframe = true;
  }
  if (want1 >= 0 && b < 0) {
    b = 1 - a;
    HW_TRY(readKeyframe(slots_[static_cast<std::size_t>(b)], want1));
    st.readKeyframe = true;
  }
  if (st.readKeyframe) st.keyframeMs = kt.ms();
  used = true;
  return {};
}

// Keyframes rendered by the viewer itself: keep two, the last one and one
// rendered ahead along the motion once the viewer has passed the newest;
// re-render where the viewer stands when no keyframe is close (first frame,
// jumps, turns the prediction missed). With the worker the keyframe ahead is
// requested instead, and put in when it is ready (until then the two older
// ones are warped); only a lost viewer renders one in the frame. Without
// lockstep the next one is requested earlier (kEarlyFraction: as soon as the
// newest has no successor in flight), kAheadSpacing beyond the newest, and
// put in when ready and wanted (the synchronous viewer would render one
// now, the viewer is lost, or it is nearer than the keyframe it replaces);
// the worker's pacing follows the viewer (workerPacingFrames).
Status Viewer::liveKeyframes(FrameStats& st, int& a, int& b) {
  if (worker_ && !workerEarly_) HW_TRY(takeFromWorker(st, /*wait=*/false));
  int nearest = -1, newest = -1;
  double sNewest = 1e300, sOther = 1e300, sFarthest = 1e300;
  bool wanted = false, lost = true;
  auto survey = [&] {
    session::SurveySlot in[2];
    for (int i = 0; i < 2; ++i) {
      const Slot& sl = slots_[static_cast<std::size_t>(i)];
      in[i] = {sl.valid, sl.serial, sl.valid ? poseDistance(sl.kf.camera, cam_) : 0.0};
    }
    const session::KeyframeSurvey k =
        session::surveyKeyframes(in, moving_, newestSerialPrev_, newestSPrev_);
    nearest = k.nearest, newest = k.newest;
    sNewest = k.sNewest, sOther = k.sOther, sFarthest = k.sFarthest;
    lost = k.lost, wanted = k.wanted;
  };
  survey();
  // Early mode: the keyframe in hand goes in when the synchronous viewer
  // would render one, the viewer is lost, or it is nearer the viewer than
  // the keyframe it would replace; not before, so the viewer keeps the
  // keyframe behind it until it has passed the newest.
  if (workerEarly_ && pendingId_ >= 0 &&
      (wanted || lost || poseDistance(pendingCam_, cam_) < sFarthest) &&
      worker_->finished(pendingId_)) {
    HW_TRY(takeFromWorker(st, /*wait=*/false));
    survey();
  }
  Stopwatch kt;
  if (lost) {
    const int target = nearest < 0 ? 0 : 1 - nearest;
    // Loading: the first keyframe comes from the worker, waited for (the
    // walk's warm-up), so its pacing knows what a keyframe costs.
    if (worker_ && !workerWarm_ && pendingId_ < 0) requestFromWorker(cam_);
    if (worker_ && pendingId_ >= 0 && poseDistance(pendingCam_, cam_) <= kLost) {
      // The keyframe in flight is within reach: wait for the rest of it
      // (which lifts the worker's pacing) rather than render another.
      HW_TRY(takeFromWorker(st, /*wait=*/true));
      st.stalledOnWorker = st.workerKeyframe;
    }
    if (!st.workerKeyframe) {
      HW_TRY(buildKeyframe(slots_[static_cast<std::size_t>(target)], cam_));
      st.builtKeyframe = true;
    }
  } else if (wanted) {
    const Camera ahead = aheadCamera();
    if (worker_ && pendingId_ >= 0) {
      st.waitedForKeyframe = true;  // warp the two we have meanwhile
    } else if (poseDistance(ahead, cam_) > kPassedNewest) {
      if (worker_) {
        requestFromWorker(ahead);
        st.requestedKeyframe = pendingId_ >= 0;
        if (opt_.asyncLockstep) HW_TRY(takeFromWorker(st, /*wait=*/true));
      } else {
        HW_TRY(buildKeyframe(slots_[static_cast<std::size_t>(1 - nearest)], ahead));
        st.builtKeyframe = true;
      }
    }
  } else if (workerEarly_ && moving_ && pendingId_ < 0 && newest >= 0 &&
             slots_[static_cast<std::size_t>(newest)].serial != aheadOfSerial_) {
    // Past the newest or still before it: this frame's motion tells (the
    // newest may have come in this frame, so the last frame's distance to
    // it is not known).
    const Camera& nc = slots_[static_cast<std::size_t>(newest)].kf.camera;
    const double d = earlyAheadDistance(sNewest, sOther, sNewest > poseDistance(nc, prevCam_),
                                        kAheadSpacing, kEarlyFraction);
    if (d > 0) {
      const Camera ahead = beyondCamera(nc, kAheadSpacing, d);
      // Not one the viewer is already at (the path's end, a stop).
      if (poseDistance(ahead, cam_) > kPassedNewest) {
        requestFromWorker(ahead);
        st.requestedKeyframe = pendingId_ >= 0;
        if (st.requestedKeyframe) aheadOfSerial_ = slots_[static_cast<std::size_t>(newest)].serial;
      }
    }
  }
  if (workerEarly_) {
    // Pacing: the measured interval between ahead requests, or fewer frames
    // when the viewer would be lost sooner at its current pace.
    if (st.requestedKeyframe) {
      if (lastAheadRequestFrame_ >= 0)
        requestInterval_ = updateRequestInterval(
            requestInterval_, static_cast<double>(frameIndex_ - lastAheadRequestFrame_));
      lastAheadRequestFrame_ = frameIndex_;
    }
    double toLost = kLost;  // no keyframe yet: as if at the newest
    if (newest >= 0) {
      const Camera& nc = slots_[static_cast<std::size_t>(newest)].kf.camera;
      toLost = sNewest > poseDistance(nc, prevCam_) ? kLost - sNewest : kLost + sNewest;
    }
    const double frames = workerPacingFrames(requestInterval_, toLost, poseDistance(cam_, prevCam_),
                                             pacingFramesMax_);
    if (std::abs(frames - pacingFrames_) > 0.01 * pacingFrames_) {
      pacingFrames_ = frames;
      worker_->setFramesPerKeyframe(frames);
    }
  }
  if (st.builtKeyframe) st.keyframeMs = kt.ms();
  // Re-evaluate after a build.
  a = -1, b = -1;
  newest = -1;
  for (int i = 0; i < 2; ++i) {
    const Slot& sl = slots_[static_cast<std::size_t>(i)];
    if (!sl.valid) continue;
    const double si = poseDistance(sl.kf.camera, cam_);
    if (newest < 0 || sl.serial > slots_[static_cast<std::size_t>(newest)].serial) newest = i;
    if (si >= kUseless) continue;
    if (a < 0)
      a = i;
    else
      b = i;
  }
  if (newest >= 0) {
    newestSPrev_ = poseDistance(slots_[static_cast<std::size_t>(newest)].kf.camera, cam_);
    newestSerialPrev_ = slots_[static_cast<std::size_t>(newest)].serial;
  }
  HW_CHECK(a >= 0);  // a keyframe at the current camera was built if none was close
  return {};
}

Status Viewer::renderHybrid(FrameStats& st) {
  int a = -1, b = -1;
  bool baked = false;
  HW_TRY(bakedKeyframes(st, a, b, baked));
  if (opt_.keyframeDb && (baked ? 1 : 0) != onBakedPath_) {
    if (onBakedPath_ >= 0)
      message(baked ? "back on the baked path: keyframes read from the database"
                    : "off the baked path: keyframes rendered live");
    onBakedPath_ = baked ? 1 : 0;
  }
  if (!baked) HW_TRY(liveKeyframes(st, a, b));
  if (b >= 0) {
    // The nearer eye is the foreground (paper §2.2 (i)), with its tie-break.
    const int pick =
        gapfill::chooseForeground(cam_.eye, slots_[static_cast<std::size_t>(a)].kf.camera.eye,
                                  slots_[static_cast<std::size_t>(b)].kf.camera.eye);
    if (pick == 1) std::swap(a, b);
  }
  foregroundSlot_ = a;
  const Slot& fg = slots_[static_cast<std::size_t>(a)];
  // A keyframe rendered at this very camera is the frame itself.
  if (fg.kf.camera.eye == cam_.eye && fg.kf.camera.forward == cam_.forward &&
      fg.kf.camera.width == width_ && fg.kf.camera.height == height_) {
    session::showKeyframe(fg.kf.colour, engine_->frame());
    st.direct = true;
    st.layers = 0;
    st.quadsA = fg.mesh.stats.quads;
    return {};
  }
  // The walk's in-between step (session/in_between.h): both layers in one
  // pass, the background only where the foreground left pixels, then the
  // previous frame where both miss.
  session::InBetweenStats is;
  HW_TRY(engine_->warp(cam_, static_cast<int>(fg.serial),
                       b >= 0 ? static_cast<int>(slots_[static_cast<std::size_t>(b)].serial) : -1,
                       is, nullptr));
  if (opt_.renderHoles) {
    // In auto mode within the walk's budget (a fraction of a geometry frame).
    session::HoleBudget budget;
    if (autoMode_) {
      budget.fraction = opt_.renderHolesBudget;
      budget.geometryMs = chooser_.geometryMs();
      budget.frameMsSoFar = frameWork_.ms();
    }
    session::HolePassResult hr;
    HW_TRY(engine_->renderHoles(cam_, &budget, &hr));
    st.holeRects = hr.drawn;
    st.holeRectsOverBudget = hr.wanted - hr.drawn;
    st.holesMs = hr.drawMs;
  }
  st.warpAMs = is.warpAMs;
  st.warpBMs = is.warpBMs + is.readbackMs;
  st.quadsA = is.quadsForeground;
  st.quadsB = is.quadsBackground;
  st.layers = b >= 0 ? 2 : 1;
  st.backgroundSkipped = b >= 0 && is.backgroundSkipped();
  st.composeMs = is.composeMs;
  st.holesBefore = engine_->frame().holeFractionBefore;
  st.holesAfter = engine_->frame().holeFractionAfter;
  return {};
}

// Every kAutoFrames frames, whether to draw hybrid or geometry (the walk's
// rule, session/frame_mode.h, with segments of kAutoFrames frames). While
// hybrid only keyframes rendered in the frame measure the geometry: until
// kAutoMinGeometrySamples geometry renders are known (so that one slow render
// does not decide), and with keyframes from the worker or a database every
// kAutoProbeEvery choices, a choice draws one frame as geometry.
// Between choices, hybrid frames that all cost more than drawing give the
// segment up at once (ModeChooser::giveUp), as the walk does.
void Viewer::chooseMode(bool* probe) {
  *probe = false;
  if (!autoMode_) return;
  // The geometry cost compared against is this view's (ModeChooserOptions::geometryByTriangles).
  chooser_.setViewTriangles(static_cast<double>(renderer_->visibleTriangles(cam_)));
  if (++framesSinceChoice_ < kAutoFrames) {
    if (hybrid_ && chooser_.giveUp()) {
      hybrid_ = false;
      engine_->forgetPrevious();
      ++autoSwitches_;
      if (firstGeometryChoice_ < 0) firstGeometryChoice_ = frameIndex_;
      message("auto: geometry (hybrid frames cost more; from frame " +
              std::to_string(frameIndex_) + ")");
    }
    return;
  }
  framesSinceChoice_ = 0;
  chooser_.startSegment();
  const bool next = chooser_.warpNext(hybrid_, kAutoFrames);
  if (next != hybrid_) {
    hybrid_ = next;
    engine_->forgetPrevious();
    ++autoSwitches_;
    if (!hybrid_ && firstGeometryChoice_ < 0) firstGeometryChoice_ = frameIndex_;
    message(std::string(hybrid_ ? "auto: hybrid" : "auto: geometry") +
            " (cheaper now; from frame " + std::to_string(frameIndex_) + ")");
  } else if (hybrid_ &&
             (geometrySamples_ < kAutoMinGeometrySamples ||
              ((worker_ || opt_.keyframeDb) && ++choicesSinceProbe_ >= kAutoProbeEvery))) {
    choicesSinceProbe_ = 0;
    *probe = true;
  }
}

void Viewer::recordCost(const FrameStats& st, double workMs) {
  // A keyframe rendered in the frame is a geometry render too (colour and
  // depth; the walk counts it so).
  if (st.builtKeyframe) {
    chooser_.addGeometryMs(lastKeyframe_.renderMs, static_cast<double>(lastKeyframe_.triangles));
    ++geometrySamples_;
  }
  switch (st.kind()) {
    case session::FrameKind::Geometry:
      chooser_.addGeometryMs(st.geometryMs, static_cast<double>(st.trianglesDrawn));
      ++geometrySamples_;
      break;
    case session::FrameKind::Keyframe: chooser_.addKeyframeMs(workMs); break;
    case session::FrameKind::Warp: chooser_.addInBetweenMs(workMs); break;
  }
}

Status Viewer::renderFrame() {
  frameWork_.restart();
  Stopwatch& work = frameWork_;
  bool probe = false;
  chooseMode(&probe);
  FrameStats st;
  st.hybrid = hybrid_ && !probe;
  if (st.hybrid) {
    HW_TRY(renderHybrid(st));
  } else {
    keyframe::RenderStats rs;
    if (wireframe_) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    const Status s = renderer_->renderColour(cam_, engine_->frame().colour, &rs);
    if (wireframe_) glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    HW_TRY(s);
    engine_->frame().holesBefore.fill(0);
    engine_->frame().valid.fill(1);
    engine_->frame().holeFractionBefore = engine_->frame().holeFractionAfter = 0;
    st.geometryMs = rs.drawMs + rs.readbackMs;
    st.trianglesDrawn = rs.trianglesDrawn;
    if (probe) engine_->forgetPrevious();
  }
  // The first frame is the load (its keyframe the first), not a cost to predict from.
  if (autoMode_ && frameIndex_ > 0) recordCost(st, work.ms());
  stats_ = st;
  // Stalls: frames that rendered, read or waited for a keyframe; not the
  // first, the load (as in the frame-time summary).
  if (frameIndex_ > 0 && (st.builtKeyframe || st.readKeyframe || st.stalledOnWorker)) {
    ++keyframeStalls_;
    maxStallMs_ = std::max(maxStallMs_, st.keyframeMs);
  }
  waitFrames_ += st.waitedForKeyframe;
  return {};
}

Status Viewer::computePsnr() {
  Stopwatch sw;
  HW_TRY(renderer_->renderColour(cam_, reference_));
  const double p = psnr(engine_->frame().colour, reference_);
  std::snprintf(psnrText_, sizeof psnrText_, "PSNR %.2f dB vs geometry (%s, frame %ld)",
                std::isfinite(p) ? p : 99.0, hybrid_ ? "hybrid" : "geometry", frameIndex_);
  if (!std::isfinite(p))
    std::snprintf(psnrText_, sizeof psnrText_, "PSNR inf dB vs geometry (identical, %s, frame %ld)",
                  hybrid_ ? "hybrid" : "geometry", frameIndex_);
  std::printf("%s\n", psnrText_);
  std::fflush(stdout);
  psnrUntil_ = clock_.ms() / 1000.0 + 2 * kMessageSeconds;
  return {};
}

void Viewer::hudBlock(float x, float y, char* text, const unsigned char colour[4]) {
  if (hudQuads_ + 1 >= kHudMaxQuads) return;
  // Translucent backdrop, then the text.
  const float w = static_cast<float>(stb_easy_font_width(text));
  const float h = static_cast<float>(stb_easy_font_height(text));
  const float pad = 3;
  EasyVertex* v = hudVerts_.data() + static_cast<std::ptrdiff_t>(hudQuads_) * 4;
  const float xs[4] = {x - pad, x + w + pad, x + w + pad, x - pad};
  const float ys[4] = {y - pad, y - pad, y + h + pad, y + h + pad};
  for (int i = 0; i < 4; ++i) v[i] = EasyVertex{xs[i], ys[i], 0, {0, 0, 0, 150}};
  ++hudQuads_;
  unsigned char c[4] = {colour[0], colour[1], colour[2], colour[3]};
  const int room = (kHudMaxQuads - hudQuads_) * 4 * static_cast<int>(sizeof(EasyVertex));
  hudQuads_ += stb_easy_font_print(
      x, y, text, c, hudVerts_.data() + static_cast<std::ptrdiff_t>(hudQuads_) * 4, room);
}

void Viewer::drawHud() {
  hudQuads_ = 0;
  // stb_easy_font's glyphs are ~6 px: 1× up to 640 px wide, then in half steps up to 2×.
  const float scale =
      std::clamp(std::floor(static_cast<float>(width_) / 640.0f * 2.0f) / 2.0f, 1.0f, 2.0f);
  const unsigned char white[4] = {255, 255, 255, 255};
  const unsigned char yellow[4] = {255, 230, 80, 255};
  const double now = clock_.ms() / 1000.0;
  float y = 6;
  const float lineH = 12;
  if (statsLevel_ >= 1) {
    // Keyframe stalls (rendered or read in the frame, which waited for it)
    // and, with the worker, frames that warped older keyframes while the
    // next one was not ready.
    if (worker_) {
      std::snprintf(keyframeLine_, sizeof keyframeLine_,
                    "keyframes async: %ld from the worker%s, last ready after %ld frames (%.0f ms); "
                    "%ld stalls (max %.1f ms), %ld frames waited%s",
                    keyframesFromWorker_, pendingId_ >= 0 ? " (one in flight)" : "",
                    lastLatencyFrames_, lastLatencyMs_, keyframeStalls_, maxStallMs_, waitFrames_,
                    stats_.waitedForKeyframe ? " (waiting)" : "");
    } else {
      std::snprintf(keyframeLine_, sizeof keyframeLine_,
                    "keyframes in the frame: %ld stalls (max %.1f ms)", keyframeStalls_,
                    maxStallMs_);
    }
    const double fps = frameMsSmoothed_ > 0 ? 1000.0 / frameMsSmoothed_ : 0;
    int n =
        std::snprintf(hudText_, sizeof hudText_, "%s  %.1f fps (%.1f ms)  speed %.2f units/s%s%s",
                      autoMode_ ? (hybrid_ ? "auto: hybrid" : "auto: geometry")
                      : hybrid_ ? "hybrid"
                                : "geometry",
                      fps, frameMsSmoothed_, moveSpeed_,
                      play_ ? "  [playing]" : "", recording_ ? "  [recording]" : "");
    if (statsLevel_ >= 2 && n > 0 && n < static_cast<int>(sizeof hudText_)) {
      const FrameStats& s = stats_;
      char* p = hudText_ + n;
      const std::size_t room = sizeof hudText_ - static_cast<std::size_t>(n);
      if (s.hybrid) {
        std::snprintf(
            p, room,
            "\nwarp fg %.1f ms  bg + readback %.1f ms%s  compose %.1f ms%s\n"
            "quads %d + %d (%d layer%s)  holes %.2f%% -> %.2f%% after fill\n"
            "last keyframe: %s %.1f  LOD %.1f  upload %.1f ms, %d quads; %ld built, %ld read%s\n"
            "%s  keyframe every %.2f units / %.0f deg\n%s",
            s.warpAMs, s.warpBMs, s.backgroundSkipped ? " (bg skipped)" : "", s.composeMs,
            s.direct ? "  (keyframe shown as is)" : "", s.quadsA,
            s.quadsB, s.layers, s.layers == 1 ? "" : "s", 100 * s.holesBefore, 100 * s.holesAfter,
            lastKeyframe_.fromDb       ? "read from the database"
            : lastKeyframe_.fromWorker ? "worker render (wall ms, paced)"
                                       : "render",
            lastKeyframe_.renderMs,
            lastKeyframe_.lodMs, lastKeyframe_.uploadMs, lastKeyframe_.quads, keyframesBuilt_,
            keyframesRead_, s.builtKeyframe || s.readKeyframe ? " (one this frame)" : "",
            thresholdText().c_str(), kfDistance_, kfAngle_ * 180 / kPi, keyframeLine_);
      } else {
        std::snprintf(p, room, "\ngeometry %.1f ms  %zu of %zu triangles drawn", s.geometryMs,
                      s.trianglesDrawn, scene_.triangleCount());
      }
    }
    hudBlock(6, y, hudText_, white);
    y += static_cast<float>(stb_easy_font_height(hudText_)) + lineH;
  }
  if (psnrText_[0] && now < psnrUntil_) {
    hudBlock(6, y, psnrText_, yellow);
    y += lineH + 4;
  }
  if (messageText_[0] && now < messageUntil_) {
    hudBlock(6, y, messageText_, yellow);
    y += lineH + 4;
  }
  if (help_) {
    std::snprintf(hudText_, sizeof hudText_, "%s", kHelp);
    hudBlock(6, y + 4, hudText_, white);
  } else if (statsLevel_ >= 1 && frameIndex_ < 200) {
    std::snprintf(hudText_, sizeof hudText_, "h: help");
    hudBlock(6, y, hudText_, white);
  }
  if (hudQuads_ == 0) return;
  hudProg_.use();
  glUniform2f(uScreen_, static_cast<float>(width_), static_cast<float>(height_));
  glUniform1f(uScale_, scale);
  glBindVertexArray(hudVao_);
  glBindBuffer(GL_ARRAY_BUFFER, hudVbo_);
  glBufferSubData(
      GL_ARRAY_BUFFER, 0,
      static_cast<GLsizeiptr>(static_cast<std::size_t>(hudQuads_) * 4 * sizeof(EasyVertex)),
      hudVerts_.data());
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDrawElements(GL_TRIANGLES, hudQuads_ * 6, GL_UNSIGNED_INT, nullptr);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
}

void Viewer::drawWindow() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, colourTex_);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE,
                  engine_->frame().colour.data());
  const bool holes = holeMask_ && hybrid_;
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, holeTex_);
  if (holes)
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RED, GL_UNSIGNED_BYTE,
                    engine_->frame().holesBefore.data());
  displayProg_.use();
  glUniform1i(uShowHoles_, holes ? 1 : 0);
  glBindVertexArray(emptyVao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  if (wireframe_ && hybrid_) {
    lineProg_.use();
    setFloatMatrix(uViewProj_, cam_.projectionMatrix(DepthMode::Fixed24, true) * cam_.viewMatrix());
    glBindVertexArray(lineVao_);
    for (int i = 0; i < 2; ++i) {
      const Slot& s = slots_[static_cast<std::size_t>(i)];
      if (!s.valid || s.lineVertices == 0) continue;
      if (i == foregroundSlot_)
        glUniform4f(uLineColour_, 0.1f, 1.0f, 0.2f, 1.0f);
      else
        glUniform4f(uLineColour_, 1.0f, 0.6f, 0.1f, 1.0f);
      glBindBuffer(GL_ARRAY_BUFFER, s.lineVbo);
      glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
      glEnableVertexAttribArray(0);
      glDrawArrays(GL_LINES, 0, s.lineVertices);
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }

  if (overlay_ && hybrid_ && foregroundSlot_ >= 0 &&
      slots_[static_cast<std::size_t>(foregroundSlot_)].valid) {
    const Slot& s = slots_[static_cast<std::size_t>(foregroundSlot_)];
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, overlayTex_);
    if (overlaySerial_ != s.serial) {
      // Only when the foreground keyframe changes.
      const Image<Rgba8> img = keyframe::drawQuadOverlay(s.kf.colour, s.mesh);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img.width(), img.height(), 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, img.data());
      overlaySerial_ = s.serial;
      overlayW_ = img.width();
      overlayH_ = img.height();
    }
    const int w = std::max(1, width_ * 2 / 5),
              h = std::max(1, w * overlayH_ / std::max(1, overlayW_));
    displayProg_.use();
    glUniform1i(uShowHoles_, 0);
    glViewport(width_ - w - 8, 8, w, h);  // bottom right, clear of the HUD
    glBindVertexArray(emptyVao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glViewport(0, 0, width_, height_);
  }
  if (opt_.hud) drawHud();
  glActiveTexture(GL_TEXTURE0);
}

void Viewer::readWindow(Image<Rgba8>& out) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  readScratch_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, readScratch_.data());
  if (out.width() != width_ || out.height() != height_) out.resize(width_, height_);
  for (int y = 0; y < height_; ++y) {  // GL row 0 is the bottom
    const Rgba8* src = readScratch_.data() + static_cast<std::ptrdiff_t>(height_ - 1 - y) * width_;
    Rgba8* dst = out.data() + static_cast<std::ptrdiff_t>(y) * width_;
    for (int x = 0; x < width_; ++x) dst[x] = Rgba8{src[x].r, src[x].g, src[x].b, 255};
  }
}

Status Viewer::screenshot(const std::string& path) {
  readWindow(windowImage_);
  HW_TRY(gl::checkGlError("reading the window for a screenshot"));
  return writePng(path, windowImage_);
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
      std::string name;
      for (int n = 0;; ++n) {
        name = "hybridwalk_screenshot_" + std::to_string(n) + ".png";
        if (!std::filesystem::exists(name)) break;
      }
      const Status s = screenshot(name);
      if (s)
        message("screenshot saved to " + name);
      else
        message("screenshot failed: " + s.error().message);
    }
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
  if (recording_) toggleRecording();  // save what was recorded
  std::printf("hybridwalk view: %ld frames, %ld keyframes built, %ld read from a database; last frame: %s\n",
              frameIndex_, keyframesBuilt_, keyframesRead_,
              !stats_.hybrid       ? "geometry"
              : stats_.direct      ? "hybrid, a keyframe at this camera shown as is"
              : stats_.layers == 2 ? "hybrid, two keyframes warped"
                                   : "hybrid, one keyframe warped");
  printModeSummary();
  printFrameSummary();
  if (!opt_.frameStatsPath.empty()) {
    HW_TRY(writeFrameStats());
    std::printf("frame statistics saved to %s\n", opt_.frameStatsPath.c_str());
  }
  std::fflush(stdout);
  return {};
}

// How the frames were drawn, and with --mode auto when it chose geometry.
void Viewer::printModeSummary() const {
  std::array<long, 3> count{};
  for (const FrameRecord& r : records_) ++count[static_cast<std::size_t>(r.kind)];
  using K = session::FrameKind;
  std::printf("hybridwalk view: mode %s: %ld frames drawn as geometry, %ld warped, %ld with a "
              "keyframe built, read or taken",
              session::frameModeName(opt_.mode), count[static_cast<std::size_t>(K::Geometry)],
              count[static_cast<std::size_t>(K::Warp)], count[static_cast<std::size_t>(K::Keyframe)]);
  if (opt_.mode == session::FrameMode::Auto) {
    if (firstGeometryChoice_ >= 0)
      std::printf("; auto chose geometry from frame %ld (%ld switches)", firstGeometryChoice_,
                  autoSwitches_);
    else
      std::printf("; auto never chose geometry");
  }
  std::printf("\n");
}

// Frame time over the frames after the first (which renders or waits for the
// first keyframe, as a load), and the keyframe stalls and waits.
void Viewer::printFrameSummary() const {
  std::vector<double> ms;
  for (std::size_t i = 1; i < records_.size(); ++i) ms.push_back(records_[i].ms);
  if (!ms.empty())
    std::printf("hybridwalk view: frame ms over frames 1..%zu: median %.2f, p95 %.2f, max %.2f\n",
                records_.size() - 1, median(ms), percentile(ms, 95.0),
                *std::max_element(ms.begin(), ms.end()));
  if (!ms.empty() && (opt_.frameBudgetMs > 0 || opt_.frameBudgetAuto)) {
    std::vector<double> work, budgets;
    for (std::size_t i = 1; i < records_.size(); ++i) {
      work.push_back(records_[i].workMs);
      if (records_[i].budgetMs > 0) budgets.push_back(records_[i].budgetMs);
    }
    std::printf("hybridwalk view: frame budget %s: median %.2f ms (%zu frames had one); work "
                "median %.2f, p95 %.2f; frame ms p95/median %.2f\n",
                opt_.frameBudgetAuto ? "auto" : "fixed", budgets.empty() ? 0.0 : median(budgets),
                budgets.size(), median(work), percentile(work, 95.0),
                percentile(ms, 95.0) / median(ms));
  }
  if (worker_)
    std::printf("hybridwalk view: keyframes async: %ld from the worker (%ld dropped as out of "
                "reach); %ld stalls (frames that rendered one or, lost, waited for the worker's; "
                "max %.1f ms), %ld frames warped older ones while one was in flight\n",
                keyframesFromWorker_, keyframesDiscarded_, keyframeStalls_, maxStallMs_, waitFrames_);
  else
    std::printf("hybridwalk view: keyframes in the frame: %ld stalls (max %.1f ms)\n",
                keyframeStalls_, maxStallMs_);
}

Status Viewer::writeFrameStats() const {
  std::string csv =
      "frame,play_frame,ms,keyframe_ms,keyframe_rendered,keyframe_read,worker_keyframe,"
      "worker_requested,worker_waited,worker_stall,layers,work_ms,budget_ms,mode,hole_rects,"
      "hole_rects_over_budget,holes_ms\n";
  char line[260];
  for (const FrameRecord& r : records_) {
    std::snprintf(line, sizeof line, "%ld,%d,%.3f,%.3f,%d,%d,%d,%d,%d,%d,%d,%.3f,%.3f,%s,%d,%d,%.3f\n",
                  r.frame, r.playFrame, r.ms, r.keyframeMs, r.built ? 1 : 0, r.read ? 1 : 0,
                  r.worker ? 1 : 0, r.requested ? 1 : 0, r.waited ? 1 : 0, r.stalled ? 1 : 0,
                  r.layers, r.workMs, r.budgetMs, session::frameKindName(r.kind), r.holeRects,
                  r.holeRectsOverBudget, r.holesMs);
    csv += line;
  }
  return writeFileAtomic(opt_.frameStatsPath, csv);
}

}  // namespace

void applyWalkOptions(const session::WalkOptions& walk, ViewerOptions* out) {
  out->mode = walk.mode;
  out->lod = walk.lod;
  out->asyncKeyframes = walk.asyncKeyframes;
  out->renderHoles = walk.renderHoles;
  out->renderHolesBudget = walk.renderHolesBudget;
}

int runViewer(const scenes::Scene& scene, const scenes::CameraPath& defaultPath,
              const ViewerOptions& options) {
  Viewer viewer(scene, defaultPath, options);
  const Status s = viewer.run();
  if (!s) {
    std::fprintf(stderr, "hybridwalk: error: %s\n", s.error().message.c_str());
    return 1;
  }
  return 0;
}

}  // namespace hw::app
