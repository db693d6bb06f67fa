#pragma once
// The viewer's state, shared by its files (not a public header): viewer.cpp
// (window, input, the frame loop), viewer_keyframes.cpp (keyframes around the
// viewer, from the renderer, a database or the worker, and each frame drawn
// through the frame engine) and viewer_draw.cpp (the frame, debug views and
// HUD on screen, screenshots).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include "app/fly_pose.h"
#include "app/path_recorder.h"
#include "app/viewer_auto_mode.h"
#include "app/viewer.h"
#include "app/viewer_frame_log.h"
#include "app/viewer_keys.h"
#include "app/viewer_motion.h"
#include "core/gl/context.h"
#include "core/gl/shader.h"
#include "core/timer.h"
#include "keyframe/gl/async_keyframes.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "session/frame_engine.h"
#include "session/frame_mode.h"
#include "session/keyframe_survey.h"

namespace hw::app::viewer_detail {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kMessageSeconds = 4.0;  // how long a HUD message stays

// stb_easy_font's vertex layout.
struct EasyVertex {
  float x, y, z;
  unsigned char c[4];
};
static_assert(sizeof(EasyVertex) == 16);
inline constexpr int kHudMaxQuads = 16384;

// Characters and Esc from GLFW callbacks, drained once per frame.
struct InputQueue {
  std::array<unsigned, 64> chars{};
  int count = 0;
};

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
  Status createGlResources();  // viewer_draw.cpp
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
  PoseMetric metric() const { return {kfDistance_, kfAngle_}; }
  double poseDistance(const Camera& a, const Camera& b) const { return metric()(a, b); }
  void handleChar(unsigned c, bool flying);
  void typeScriptedKeys();  // those due before this frame into the input queue
  void updateCamera(double dt);
  Status renderFrame();
  Status renderHybrid(FrameStats& st);
  Status buildKeyframe(Slot& slot, const Camera& cam);
  Status startWorker(double framesPerKeyframe);
  void stopWorker();
  void requestFromWorker(const Camera& cam);
  Status takeFromWorker(FrameStats& st, bool wait);
  FrameRecord frameRecord(double budgetMs) const;  // this frame's, ms and work ms unset
  void printSummary() const;
  Status finish();
  Status readKeyframe(Slot& slot, int frame);
  Status finishSlot(Slot& slot);
  Status liveKeyframes(FrameStats& st, int& a, int& b);
  Status bakedKeyframes(FrameStats& st, int& a, int& b, bool& used);
  Camera aheadCamera(double distance = 1.0) const;
  Camera beyondCamera(const Camera& newest, double spacing, double distance) const;
  Status computePsnr();
  void drawWindow();
  void drawHud();
  void hudStatsText();
  void hudBlock(float x, float y, char* text, const unsigned char colour[4]);
  void readWindow(Image<Rgba8>& out);
  Status screenshot(const std::string& path);
  void capture();  // `c`: the window into the next free hybridwalk_screenshot_N.png
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
  int uShowHoles_ = -1, uFlipColour_ = -1, uViewProj_ = -1, uLineColour_ = -1, uScreen_ = -1, uScale_ = -1;
  unsigned emptyVao_ = 0, lineVao_ = 0, hudVao_ = 0, hudVbo_ = 0, hudIbo_ = 0;
  unsigned colourTex_ = 0, holeTex_ = 0, overlayTex_ = 0;

  int width_ = 0, height_ = 0;  // framebuffer size = render size
  Camera base_;                 // fov, near, far of the session
  Camera home_;
  Camera cam_, prevCam_;
  FlyPose pose_;  // fly controls (app/fly_pose.h)
  MotionEstimate motion_;
  double moveSpeed_ = 1;  // units/s
  double kfDistance_ = 1, kfAngle_ = 0.25;
  bool mouseLook_ = false;
  double lastMouseX_ = 0, lastMouseY_ = 0;

  bool hybrid_ = true, wireframe_ = false, overlay_ = false, holeMask_ = false, help_ = false;
  bool autoMode_ = false;  // ViewerOptions::mode Auto, until `g`
  ViewerAutoMode auto_;
  void chooseMode(bool* probe);
  void recordCost(const FrameStats& st, double workMs);
  StatsLevel statsLevel_ = StatsLevel::Fps;
  std::vector<ScriptedKey> scriptedKeys_;  // ViewerOptions::keys
  std::size_t nextScriptedKey_ = 0;
  bool play_ = false;
  std::vector<Camera> playCams_;
  int playIndex_ = 0;
  int playFrame_ = -1;           // frame of the play path shown now; -1: not playing it
  bool playingBakedPath_ = false;  // playCams_ is the path the database was baked from
  PathRecorder recorder_;  // `z`
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
  Image<Rgba8> reference_, windowImage_, shownFrame_;
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
  long keyframesBuilt_ = 0;  // rendered in the frame (the worker's: keyframesFromWorker_)
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

}  // namespace hw::app::viewer_detail
