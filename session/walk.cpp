// The walk's frame loop: keyframes acquired along the schedule, each frame
// drawn (a keyframe shown, or the in-between step), optionally refreshed
// within a budget and paced, measured against the geometry renderer, and
// handed to the recorder.
#include "session/walk.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/gl/render_memory.h"
#include "core/json_util.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/progress.h"
#include "core/timer.h"
#include "gapfill/age.h"
#include "keyframe/analytic_scene.h"
#include "keyframe/gl/async_keyframes.h"
#include "keyframe/keyframe_cache.h"
#include "session/frame_budget.h"
#include "session/frame_engine.h"
#include "session/hole_pass.h"
#include "session/walk_recorder.h"

namespace hw::session {

using nlohmann::json;

namespace {

std::string frameName(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d.png", i);
  return buf;
}


// One walk. The members are the state the frames share; each method is one
// stage of the loop.
class WalkLoop {
 public:
  WalkLoop(const scenes::Scene& scene, const std::string& sceneLabel,
           const scenes::CameraPath& path, const WalkOptions& opt)
      : scene_(scene),
        label_(sceneLabel),
        path_(path),
        opt_(opt),
        frames_(opt.maxFrames > 0 ? std::min(opt.maxFrames, path.frames) : path.frames),
        writing_(!opt.outDir.empty()),
        recorder_(opt.keepFrames,
                  writing_ && !opt.keepFrames
                      ? opt.outDir + "/.report-frames.tmp-" + std::to_string(::getpid())
                      : std::string(),
                  frames_) {}

  Result<WalkResult> run();

 private:
  Status setUp();
  Status setUpSchedule();
  void makeCache();
  Status startKeyframeWorker();
  Status warmUp();
  void setUpPin();
  std::string pinKey() const;
  bool pinnedWarps(int k) const;
  void writePin();
  Status calibrateRefresh();
  Status calibrateModes();
  Status calibrateWarp(int k0);
  void chooseStripFrames();
  Status chooseKind(int i, int k0, int k1, FrameKind* kind);
  bool segmentKeyframesReady(int k) const;
  Status calibrateIfUnmeasured(int k0, int frames, bool* warp);
  int segmentLength(int k) const;
  Status frame(int i);
  Status geometryFrame(int i, json& fj, json& ms);
  Status keyframeFrame(int i, int k, json& fj, json& ms);
  Status inBetweenFrame(int i, int k0, int k1, json& fj, json& ms);
  Status refresh(const Camera& cam, json& fj, json& ms, gapfill::AgeStats& as);
  Status renderHoles(const Camera& cam, json* fj, json* ms, long long* renderedHoles);
  void recordQuality(int i, json& fj, bool fused, bool bgSkipped);
  void endFrameWork(json& ms, FrameKind kind);
  void recordFreshAge(json& fj, json& ms);
  Status getSource(int k, const keyframe::CachedKeyframe** out);
  void releaseBefore(int k0);
  const gapfill::Frame* previousFrame() const {
    return engine_->hasPrevious() ? &engine_->previous() : nullptr;
  }
  json summary() const;
  void summariseLod(json& s) const;
  void summariseTiming(json& s) const;
  void summariseBudget(json& s) const;
  void summariseModes(json& s) const;

  const scenes::Scene& scene_;
  const std::string& label_;
  const scenes::CameraPath& path_;
  const WalkOptions& opt_;
  const int frames_;
  const bool writing_;

  std::unique_ptr<FrameEngine> engine_;
  keyframe::GeometryRenderer* renderer_ = nullptr;  // the engine's
  keyframe::KeyframeSchedule schedule_;
  std::vector<Camera> cams_;
  std::vector<char> walked_;  // onlySegments: the frames walked (empty = all)
  bool asyncKf_ = false;
  // Declared before the cache so that it outlives it (joined on every return).
  std::unique_ptr<keyframe::AsyncKeyframes> kfWorker_;
  std::unique_ptr<keyframe::KeyframeCache> cache_;
  double warmupMs_ = 0;
  static constexpr int kFloorReps = 15;
  FloorTimes floor_;
  // The frame mode: this segment warped or drawn as geometry, and the costs
  // the choice is made from (FrameMode::Auto).
  bool warping_ = true;
  ModeChooser chooser_{opt_.modeChooser};
  double warpFloorMs_ = -1, warpCalibrationMs_ = -1;
  int decidedAt_ = -1;  // the frame whose segment was last decided
  static constexpr int kProbeEvery = 4;
  int segmentsSinceProbe_ = 0, geometryProbes_ = 0;
  int kindCounts_[3] = {0, 0, 0};  // frames per FrameKind
  int modeSwitches_ = 0;
  int segmentsGivenUp_ = 0;  // warped segments finished as geometry (ModeChooser::giveUp)
  int warpStartsDeferred_ = 0;  // segments left as geometry while their keyframes were building
  int deferredSegment_ = -1;    // the keyframe of the segment deferred last (-1: none)
  int warmupStalls_ = 0;
  double frameWaitMs_ = 0;  // this frame's wait for keyframes not ready
  bool warmingUp_ = false;   // getSource called before the first frame
  double chooseMs_ = 0;     // this frame's share of the mode choice, done before frameSw_ starts
  // Pinned choices (WalkOptions::autoPin): the file ("" = none read or
  // written), the kinds replayed (empty: chosen in this run), how the last
  // frame was drawn, what became of the pin, and why one was not used or
  // written. The kinds a measured run pins are the recorder's.
  std::string pinFile_;
  std::vector<FrameKind> pinned_;
  std::vector<int> pinnedHoleRects_;  // per frame (-1: none ran); empty: not pinned
  std::vector<int> holeRects_;  // a measured run to pin, per frame: rectangles its hole pass drew (-1: none)
  int pinDeviations_ = 0;  // replayed warp frames drawn as geometry: their keyframes were building
  std::vector<int> nextPinnedWarp_;  // per frame: the next keyframe whose segment the pin warps (-1: none)
  FrameKind lastKind_ = FrameKind::Geometry;
  const char* pinState_ = "off";
  std::string pinNote_;
  bool builtThisFrame_ = false;

  // Frame budget and refresh.
  bool budgetOn_ = false, trackAge_ = false;
  std::unique_ptr<AutoFrameBudget> autoBudget_;
  double budgetMs_ = 0;  // this frame's budget (0 = none: no refresh, no pacing)
  RefreshCostModel refreshCost_;
  double refreshCalibrationMs_ = 0;
  Image<Rgba8> refreshColour_;
  std::vector<std::uint32_t> tileScores_;
  std::vector<int> tileOrder_;
  double workBeforeRefreshMs_ = -1;  // this frame's work when a refresh started (-1: none)

  std::map<int, warp::WarpStats> uploadStats_;  // keyframe → its upload
  Image<Rgba8> reference_;
  bool referenceCold_ = false;  // a warp source was uploaded since the last reference
  std::vector<int> stripFrames_;
  std::size_t nextStrip_ = 0;  // the first strip not taken yet
  std::size_t inBetweenCount_ = 0;

  Stopwatch frameSw_;
  std::chrono::steady_clock::time_point frameStart_;
  int currentFrame_ = 0;
  double currentRefMs_ = 0;
  long long debugErrors0_ = 0;
  WalkRecorder recorder_;
};

Status WalkLoop::setUp() {
  if (writing_) {
    HW_TRY(ensureWritableDir(opt_.outDir));
    if (opt_.saveFrames) {
      HW_TRY(ensureWritableDir(opt_.outDir + "/frames"));
      HW_TRY(ensureWritableDir(opt_.outDir + "/holes"));
    }
  }
  // The reference uses the engine's renderer: the geometry image at the same
  // camera (DESIGN.md "What is measured"). The large-leaf mask only feeds
  // psnr_large_quads: without a reference it is not made.
  auto engine = FrameEngine::create(scene_, opt_, false, opt_.reference);
  if (!engine) return engine.error();
  engine_ = std::move(*engine);
  renderer_ = &engine_->renderer();
  HW_TRY(setUpSchedule());
  makeCache();
  setUpPin();
  // A keyframe that cannot fit the memory budget is refused before anything
  // of its size is drawn: the floor's keyframe is as large.
  const bool needsKeyframes = opt_.mode != FrameMode::Geometry && !schedule_.keyframes().empty();
  if (needsKeyframes) HW_TRY(cache_->checkFits(schedule_.keyframes().front()));
  // The fill floor at this resolution, before the keyframe worker starts; a
  // geometry walk whose budget holds no keyframe goes without it.
  if (needsKeyframes || keyframe::checkKeyframeFits(cams_.front(), 0, "").ok())
    HW_TRY(engine_->measureFloor(path_.cameraAt(0), kFloorReps, &floor_));
  return startKeyframeWorker();
}

Status WalkLoop::setUpSchedule() {
  schedule_ = pathSchedule(frames_, path_.keyframeEvery, opt_.keyframeFrames);
  // Every frame's camera once (CameraPath::cameraAt rebuilds its arc-length
  // table per call); read-only, so the keyframe worker thread may use it too.
  cams_ = path_.cameras();
  if (opt_.onlySegments.empty()) return {};
  walked_.assign(static_cast<std::size_t>(frames_), 0);
  for (const auto& [a, b] : opt_.onlySegments) {
    if (a < 0 || b >= frames_ || a >= b || !schedule_.isKeyframe(a) || !schedule_.isKeyframe(b) ||
        schedule_.bracket(a + 1).second != b)
      return makeError("walk: a segment to walk (" + std::to_string(a) + ", " + std::to_string(b) +
                       ") is not two consecutive keyframes of the schedule within 0.." +
                       std::to_string(frames_ - 1));
    for (int i = a; i <= b; ++i) walked_[static_cast<std::size_t>(i)] = 1;
  }
  return {};
}

// Keyframe acquisition: a cache (memory bound), and with asyncKeyframes a
// worker that renders and meshes keyframes ahead along the schedule.
void WalkLoop::makeCache() {
  const keyframe::MeshSpec meshSpec{opt_.mesh, opt_.lod, opt_.tileSize};
  cache_ = std::make_unique<keyframe::KeyframeCache>(
      *renderer_, meshSpec, [this](int i) { return cams_[static_cast<std::size_t>(i)]; },
      keyframe::CacheOptions{opt_.keyframeCacheBytes, std::max(0, opt_.keyframePrefetch)});
  cache_->setSchedule(schedule_);
  if (opt_.keyframeSource) cache_->setSource(opt_.keyframeSource);
}

// The name of this walk's pin: a hash of what auto's choice depends on.
// The scene is known by its label, counts and bounds and every 64th vertex
// (hashing a million-triangle scene whole would cost more than its load);
// an edit that keeps all of these keeps a pin that may choose less well,
// never one that draws a wrong image.
std::string WalkLoop::pinKey() const {
  PinHasher h;
  h.text("hybridwalk walk");
  h.text(opt_.modePinContext);
  h.text(label_);
  h.text(scene_.name);
  h.number(static_cast<std::int64_t>(scene_.meshes.size()));
  for (const scenes::Mesh& m : scene_.meshes) {
    h.number(static_cast<std::int64_t>(m.vertices.size()));
    h.number(static_cast<std::int64_t>(m.indices.size()));
    h.bytes(&m.boundsMin, sizeof m.boundsMin);
    h.bytes(&m.boundsMax, sizeof m.boundsMax);
    for (std::size_t v = 0; v < m.vertices.size(); v += 64)
      h.bytes(&m.vertices[v].position, sizeof m.vertices[v].position);
  }
  for (const Camera& c : cams_) {
    for (const glm::dvec3* v : {&c.eye, &c.right, &c.up, &c.forward}) h.bytes(v, sizeof *v);
    h.number(c.fovYRadians);
    h.number(c.nearPlane);
    h.number(c.farPlane);
    h.number(static_cast<std::int64_t>(c.width));
    h.number(static_cast<std::int64_t>(c.height));
  }
  for (int k : schedule_.keyframes()) h.number(static_cast<std::int64_t>(k));
  h.text(machineInfo(opt_.glRenderer, opt_.glVersion).dump());
  return h.hex();
}

// FrameMode::Auto over the whole path: the pin of this walk, replayed when
// there is one and WalkOptions::autoPin says to use it. A pin that cannot be
// read or does not fit the schedule is not used (pinNote_ says why) and is
// replaced by this run's choices.
void WalkLoop::setUpPin() {
  if (opt_.mode != FrameMode::Auto || opt_.autoPin == AutoPin::Off || opt_.modePinDir.empty() ||
      !opt_.onlySegments.empty())
    return;
  pinFile_ = (std::filesystem::path(opt_.modePinDir) / ("walk-" + pinKey() + ".json")).string();
  pinState_ = "measured";
  if (opt_.autoPin != AutoPin::Use) return;
  bool found = false;
  auto pin = readModePin(pinFile_, frames_, &found);
  if (!pin) {
    pinNote_ = pin.error().message;
    return;
  }
  if (!found) return;
  for (int i = 0; i < frames_; ++i) {
    const FrameKind k = pin->kinds[static_cast<std::size_t>(i)];
    const bool keyframe = schedule_.isKeyframe(i);
    if ((k == FrameKind::Keyframe && !keyframe) || (k == FrameKind::Warp && keyframe)) {
      pinNote_ = "mode pin " + pinFile_ + ": frame " + std::to_string(i) + " is " +
                 (keyframe ? "a keyframe" : "an in-between frame") + " of the schedule, the pin has " +
                 frameKindName(k);
      return;
    }
  }
  pinned_ = std::move(pin->kinds);
  pinnedHoleRects_ = std::move(pin->holeRects);
  pinState_ = "replayed";
  nextPinnedWarp_.assign(static_cast<std::size_t>(frames_), -1);
  for (int i = frames_ - 2, next = -1; i >= 0; --i) {
    if (schedule_.isKeyframe(i + 1) && pinnedWarps(i + 1)) next = i + 1;
    nextPinnedWarp_[static_cast<std::size_t>(i)] = next;
  }
}

// A pinned segment (from keyframe k to the next) draws some frame from keyframes.
bool WalkLoop::pinnedWarps(int k) const {
  const int end = std::min(frames_, k + segmentLength(k));
  for (int i = k; i < end; ++i)
    if (pinned_[static_cast<std::size_t>(i)] != FrameKind::Geometry) return true;
  return false;
}

// The choices of a measured walk become its pin; a pin that cannot be
// written leaves the walk as it is (pinNote_ says why).
void WalkLoop::writePin() {
  if (pinFile_.empty() || !pinned_.empty()) return;
  if (auto st = writeModePin(pinFile_, ModePin{recorder_.frameTimes.kind.values(), holeRects_}, label_);
      !st) {
    pinNote_ = st.error().message;
    pinState_ = "measured, not pinned";
  }
}

Status WalkLoop::startKeyframeWorker() {
  asyncKf_ = opt_.asyncKeyframes && !opt_.keyframeSource;
  if (!asyncKf_) return {};
  keyframe::AsyncKeyframeOptions aopt;
  aopt.render = renderer_->options();
  aopt.render.simplifiedRects = false;  // the worker draws keyframes, never rectangles
  aopt.mesh = keyframe::MeshSpec{opt_.mesh, opt_.lod, opt_.tileSize};
  aopt.maxQueued = std::max(1, opt_.keyframePrefetch) + 2;  // the bracket + those ahead
  aopt.flushEveryTriangles = opt_.keyframeFlushTriangles;
  aopt.workerNice = opt_.keyframeWorkerNice;
  using P = WalkOptions::KeyframePacing;
  if (opt_.keyframePacing == P::Steps) aopt.stepsPerFrame = opt_.keyframeStepsPerFrame;
  if (opt_.keyframePacing == P::Time || opt_.keyframePacing == P::Slices) {
    aopt.slices = opt_.keyframePacing == P::Slices;
    const std::size_t nk = schedule_.keyframes().size();
    aopt.framesPerKeyframe =
        nk > 1 ? static_cast<double>(frames_ - 1) / static_cast<double>(nk - 1) : 1.0;
    aopt.budgetScale = opt_.keyframeBudgetScale;
  }
  auto w = keyframe::AsyncKeyframes::create(
      scene_, [this](int i) { return cams_[static_cast<std::size_t>(i)]; }, aopt);
  if (!w) return w.error();
  kfWorker_ = std::move(*w);
  cache_->setProducer(kfWorker_.get());
  return {};
}

// Warm-up, as a viewer loads before its first frame: the first two keyframes
// are built (or, async, waited for) before the walk starts.
Status WalkLoop::warmUp() {
  Stopwatch warmupSw;
  warping_ = opt_.mode != FrameMode::Geometry;
  if (opt_.mode == FrameMode::Auto && !pinned_.empty()) {
    // Replayed: the geometry cost still sets the hole pass's budget.
    HW_TRY(calibrateModes());
    warping_ = pinnedWarps(0);
    decidedAt_ = 0;
  } else if (opt_.mode == FrameMode::Auto) {
    HW_TRY(calibrateModes());
    warping_ = chooser_.warpNext(false, segmentLength(0));
    if (warping_ && frames_ > 1) {
      warmingUp_ = true;
      const Status cal = calibrateWarp(schedule_.bracket(0).first);
      warmingUp_ = false;
      HW_TRY(cal);
      warping_ = chooser_.warpNext(false, segmentLength(0));
    }
    decidedAt_ = 0;
    chooser_.startSegment();
  }
  if (warping_) {
    if (asyncKf_) HW_TRY(cache_->prefetch(frames_ > 1 ? 1 : 0));
    for (int k : {schedule_.bracket(0).first, schedule_.bracket(frames_ > 1 ? 1 : 0).second}) {
      auto kf = cache_->get(k);
      if (!kf) return kf.error();
    }
  }
  warmupMs_ = warmupSw.ms();
  warmupStalls_ = cache_->stalls();
  budgetOn_ = opt_.frameBudgetMs > 0 || opt_.frameBudgetAuto;
  if (opt_.frameBudgetAuto &&
      (opt_.frameBudgetWindow < 1 ||
       !(opt_.frameBudgetQuantile > 0 && opt_.frameBudgetQuantile <= 1)))
    return makeError(
        "walk: automatic frame budget: expected window >= 1 and 0 < quantile <= 1, got window " +
        std::to_string(opt_.frameBudgetWindow) + ", quantile " +
        std::to_string(opt_.frameBudgetQuantile));
  autoBudget_ = std::make_unique<AutoFrameBudget>(
      std::max(1, opt_.frameBudgetWindow),
      opt_.frameBudgetQuantile > 0 && opt_.frameBudgetQuantile <= 1 ? opt_.frameBudgetQuantile
                                                                     : 0.9);
  budgetMs_ = opt_.frameBudgetAuto ? 0.0 : opt_.frameBudgetMs;
  trackAge_ = budgetOn_ || opt_.pixelAge;
  if (!budgetOn_) return {};
  if (opt_.staleAfter < 1)
    return makeError("walk: staleAfter " + std::to_string(opt_.staleAfter) +
                     ": expected at least 1 frame");
  return calibrateRefresh();
}

// FrameMode::Auto starts from two costs measured before the first frame: a
// geometry frame at the first camera (its second render), and a floor under
// any in-between frame, the warp of a keyframe of a plain box room around that
// camera (a few quads, nothing of the scene), also timed on its second run.
// The floor stands for the in-between cost until one is measured, so a scene
// that draws faster than the floor never builds a keyframe.
Status WalkLoop::calibrateModes() {
  const Camera& cam = cams_[0];
  keyframe::RenderStats rs;
  for (int rep = 0; rep < 2; ++rep) HW_TRY(renderer_->renderColour(cam, reference_, &rs));
  chooser_.addGeometryMs(rs.drawMs + rs.readbackMs, static_cast<double>(rs.trianglesDrawn));
  chooser_.setViewTriangles(static_cast<double>(rs.trianglesDrawn));
  keyframe::AnalyticScene room;
  const double r = std::clamp(cam.nearPlane * 50, cam.nearPlane * 2, cam.farPlane * 0.5);
  room.boxes.push_back({cam.eye - glm::dvec3(r), cam.eye + glm::dvec3(r), Rgba8{128, 128, 128, 255}});
  const keyframe::Keyframe kf = keyframe::renderAnalyticKeyframe(room, cam);
  keyframe::QuadMesh mesh;
  keyframe::LodBuilder builder;
  HW_TRY(builder.build(kf, opt_.lod, &mesh));
  auto src = engine_->warper().upload(kf, mesh, nullptr);
  if (!src) return src.error();
  InBetweenStats st;
  for (int rep = 0; rep < 2; ++rep) {
    Stopwatch sw;
    HW_TRY(engine_->step().draw(engine_->warper(), **src, nullptr, cam, nullptr, nullptr,
                                engine_->frame(), st));
    warpFloorMs_ = sw.ms();
  }
  chooser_.setWarpFloorMs(warpFloorMs_);
  return {};
}

// The floor says warping may pay: keyframe k0 (which the walk then warps,
// the first, or the first of a later segment when no in-between frame has
// been measured yet) is built (or taken from the worker) and warped, as both
// layers (an in-between frame draws two), to the camera half-way through its
// segment; that frame's cost (with its hole pass, WalkOptions::renderHoles),
// not the floor (which leaves out the scene's mesh: 1.3x below the real cost
// indoors, 3-6x on dense outdoor meshes), decides the segment.
Status WalkLoop::calibrateWarp(int k0) {
  // Only k0 (get() requests it from the worker and waits): the keyframes after
  // it are requested once warping is chosen (warmUp), so that a walk drawn
  // as geometry does not build them beside its first frames.
  const keyframe::CachedKeyframe* kf = nullptr;
  HW_TRY(getSource(k0, &kf));
  const warp::WarpSource& src = engine_->source(k0);
  InBetweenOptions both = opt_.inBetween;
  both.skipBackground = false;
  InBetweenStep step(both);
  const int mid = std::clamp(k0 + segmentLength(k0) / 2, 1, frames_ - 1);
  InBetweenStats st;
  double ms = 0;
  for (int rep = 0; rep < 2; ++rep) {
    Stopwatch sw;
    frameSw_.restart();
    const Camera& cam = cams_[static_cast<std::size_t>(mid)];
    HW_TRY(step.draw(engine_->warper(), src, &src, cam, nullptr, nullptr, engine_->frame(), st));
    long long drawn = 0;  // the hole pass too (its first, cold draw is this one's to pay)
    if (opt_.renderHoles) HW_TRY(renderHoles(cam, nullptr, nullptr, &drawn));
    ms = sw.ms();
  }
  warpCalibrationMs_ = ms;
  chooser_.addInBetweenMs(ms);
  return {};
}

// Whether the keyframes of the segment starting at keyframe k are built
// (cached, or done by the worker).
bool WalkLoop::segmentKeyframesReady(int k) const {
  const int k1 = k + 1 < frames_ ? schedule_.bracket(k + 1).second : k;
  for (int f : {k, k1})
    if (!cache_->contains(f) && !(kfWorker_ && kfWorker_->ready(f))) return false;
  return true;
}

// No in-between frame measured yet (the floor, which leaves out the scene's
// mesh, said warping may pay only now): keyframe k0 is warped as before the
// walk (calibrateWarp), in this frame's time, and that cost decides *warp
// for the `frames` frames to come.
Status WalkLoop::calibrateIfUnmeasured(int k0, int frames, bool* warp) {
  if (chooser_.inBetweenMeasured()) return {};
  Stopwatch sw;
  HW_TRY(calibrateWarp(k0));
  *warp = chooser_.warpNext(false, frames);
  chooseMs_ += sw.ms();
  return {};
}

// Frames from keyframe k to the next keyframe (1 for the last frame).
int WalkLoop::segmentLength(int k) const {
  return k + 1 < frames_ ? schedule_.bracket(k + 1).second - k : 1;
}

// How frame i is drawn. FrameMode::Auto decides at each keyframe of the
// schedule, for the segment that starts there, whether to warp it.
Status WalkLoop::chooseKind(int i, int k0, int k1, FrameKind* kind) {
  bool probe = false;
  chooseMs_ = 0;
  if (!pinned_.empty()) {  // replayed: as the pin says
    const bool warp = pinnedWarps(k0);
    modeSwitches_ += i != decidedAt_ && warp != warping_;
    warping_ = warp;
    decidedAt_ = i;
    *kind = pinned_[static_cast<std::size_t>(i)];
    // A warp start waits for no build, as in the measured run (whose starts
    // found their keyframes built): while they are building, the frame is
    // drawn as geometry and the next one tries again.
    if (*kind != FrameKind::Geometry && asyncKf_ && i > 0 && lastKind_ == FrameKind::Geometry &&
        !segmentKeyframesReady(k0)) {
      *kind = FrameKind::Geometry;
      ++pinDeviations_;
    }
    return {};
  }
  if (opt_.mode == FrameMode::Auto) {
    // The geometry cost the choice compares against is this view's
    // (ModeChooserOptions::geometryByTriangles); counting is frame work.
    Stopwatch sw;
    chooser_.setViewTriangles(
        static_cast<double>(renderer_->visibleTriangles(cams_[static_cast<std::size_t>(i)])));
    chooseMs_ = sw.ms();
  }
  if (opt_.mode == FrameMode::Auto && k0 == k1 && i != decidedAt_) {
    bool warp = chooser_.warpNext(warping_, segmentLength(i));
    // Warping starts only on keyframes built ahead: a keyframe frame that
    // waits for its build costs a geometry render and the LOD build in one
    // frame. The geometry frames before asked for them; until they are
    // done, this segment is drawn as geometry; warping starts at the first
    // of its frames that finds them done (below).
    deferredSegment_ = -1;
    if (warp && !warping_ && asyncKf_ && !segmentKeyframesReady(i)) {
      warp = false;
      deferredSegment_ = i;
      ++warpStartsDeferred_;
    }
    if (warp && !warping_) HW_TRY(calibrateIfUnmeasured(i, segmentLength(i), &warp));
    modeSwitches_ += warp != warping_;
    // Warping with keyframes from elsewhere, no frame measures the geometry:
    // every kProbeEvery warped segments one starts with a geometry frame.
    probe = warp && warping_ && (asyncKf_ || opt_.keyframeSource) &&
            ++segmentsSinceProbe_ >= kProbeEvery;
    if (probe) {
      segmentsSinceProbe_ = 0;
      ++geometryProbes_;
    }
    warping_ = warp;
    decidedAt_ = i;
    chooser_.startSegment();
  } else if (opt_.mode == FrameMode::Auto && k0 != k1 && warping_ && chooser_.giveUp()) {
    warping_ = false;  // the rest of this segment as geometry
    ++modeSwitches_;
    ++segmentsGivenUp_;
  } else if (opt_.mode == FrameMode::Auto && k0 != k1 && !warping_ && deferredSegment_ == k0 &&
             segmentKeyframesReady(k0)) {
    // The deferred segment's keyframes are done: its other frames are warped.
    bool warp = chooser_.warpNext(false, k1 - i);
    if (warp) HW_TRY(calibrateIfUnmeasured(k0, k1 - i, &warp));
    if (warp) {
      warping_ = true;
      ++modeSwitches_;
      chooser_.startSegment();
    }
    deferredSegment_ = -1;  // one try: the next decision is the next keyframe's
  }
  *kind = !warping_ || probe ? FrameKind::Geometry
          : k0 == k1         ? FrameKind::Keyframe
                             : FrameKind::Warp;
  return {};
}

// The refresh render's cost model, calibrated before the first frame: two
// scissored renders, each timed on its second run (a tile at the centre and
// the whole image).
Status WalkLoop::calibrateRefresh() {
  constexpr int kTile = WalkOptions::kRefreshTilePx;
  Stopwatch cal;
  const Camera cam0 = path_.cameraAt(0);
  const int tw = std::min(kTile, cam0.width), th = std::min(kTile, cam0.height);
  const keyframe::PixelRect small{(cam0.width - tw) / 2, (cam0.height - th) / 2,
                                  (cam0.width - tw) / 2 + tw, (cam0.height - th) / 2 + th};
  const keyframe::PixelRect full{0, 0, cam0.width, cam0.height};
  double t[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const keyframe::PixelRect& r = k == 0 ? small : full;
    for (int rep = 0; rep < 2; ++rep) {
      Stopwatch sw;
      HW_TRY(renderer_->renderColourRect(cam0, r, refreshColour_));
      t[k] = sw.ms();
    }
  }
  refreshCost_.calibrate(small.area(), t[0], full.area(), t[1]);
  refreshCalibrationMs_ = cal.ms();
  return {};
}

// Strip frames: spread over the in-between frames.
void WalkLoop::chooseStripFrames() {
  std::vector<int> inBetween;
  for (int i = 0; i < frames_; ++i)
    if (!schedule_.isKeyframe(i)) inBetween.push_back(i);
  inBetweenCount_ = inBetween.size();
  for (int s = 0; s < opt_.strips && !inBetween.empty(); ++s) {
    const std::size_t k =
        (2 * s + 1) * inBetween.size() / (2 * static_cast<std::size_t>(opt_.strips));
    if (stripFrames_.empty() || stripFrames_.back() != inBetween[k])
      stripFrames_.push_back(inBetween[k]);
  }
}

Status WalkLoop::getSource(int k, const keyframe::CachedKeyframe** kfOut) {
  auto kf = cache_->get(k);
  if (!kf) return kf.error();
  *kfOut = *kf;
  auto& s = recorder_.series;
  // Waits before the first frame (warm-up) are warmup_ms's, not stalls.
  if (cache_->lastWaitMs() > 0 && !warmingUp_) {
    frameWaitMs_ += cache_->lastWaitMs();
    s.stallMs.push_back(cache_->lastWaitMs());
  }
  if (engine_->has(k)) return {};
  builtThisFrame_ = true;
  warp::WarpStats ws;
  HW_TRY(engine_->upload(k, (*kf)->keyframe, (*kf)->mesh, cams_[static_cast<std::size_t>(k)].eye,
                         &ws));
  uploadStats_[k] = ws;
  referenceCold_ = true;
  const auto& ms = (*kf)->mesh.stats;
  // A keyframe rendered here is a geometry frame's cost (plus its depth
  // readback); one from the worker or a database is not.
  if (!asyncKf_ && !opt_.keyframeSource)
    chooser_.addGeometryMs((*kf)->renderMs,
                           static_cast<double>(renderer_->visibleTriangles((*kf)->keyframe.camera)));
  s.keyframeMs.push_back((*kf)->renderMs + ms.deltaMs + ms.subdivideMs + ms.cornersMs +
                         ws.uploadMs);
  s.quadsPerKeyframe.push_back(static_cast<double>(ms.quads));
  s.drawnQuads.push_back(ws.drawnQuads);
  s.pointsPerKeyframe.push_back(ws.points);
  s.subdividedQuads.push_back(ws.subdividedQuads);
  s.lodBuildMs.push_back(ms.deltaMs + ms.subdivideMs + ms.cornersMs);
  s.onePixelLeaves.push_back(static_cast<double>(ms.onePixelLeaves));
  return {};
}

// The end of a frame's work: ms["frame"] (work), then with a budget and
// pacing a sleep until the budget has passed since the frame started, and
// ms["interval"], the presented frame interval (work + that wait; the
// reference render and the metrics stay outside both).
void WalkLoop::endFrameWork(json& ms, FrameKind kind) {
  auto& s = recorder_.series;
  auto& c = recorder_.counts;
  if (kfWorker_ && opt_.keyframePacing == WalkOptions::KeyframePacing::Slices) {
    const double slice = kfWorker_->runSlice();  // part of the frame: the CPUs are the worker's now
    ms["keyframe_slice"] = slice;
    s.sliceMs.push_back(slice);
  }
  const double work = frameSw_.ms() + chooseMs_;
  ms["frame"] = work;
  if (kfWorker_) ms["keyframe_worker"] = kfWorker_->workerMsSinceTick();
  const bool budgeted = budgetOn_ && budgetMs_ > 0;
  if (budgeted) {
    if (work > budgetMs_) {
      ++c.budgetOverruns;
      c.budgetOverrunsInBetween += kind == FrameKind::Warp;
      // Within the budget before a refresh, over it after: the estimate missed.
      c.budgetOverrunsByRefresh += workBeforeRefreshMs_ >= 0 && workBeforeRefreshMs_ <= budgetMs_;
    }
    if (opt_.paceFrames)
      std::this_thread::sleep_until(
          frameStart_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double, std::milli>(budgetMs_)));
  }
  const double interval =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart_)
          .count();
  ms["pacing_wait"] = std::max(0.0, interval - work);
  ms["interval"] = interval;
  s.frameIntervalMs.push_back(interval);
  recorder_.frameTimes.push(currentFrame_, kind, builtThisFrame_, work, interval,
                            budgeted ? budgetMs_ : 0.0, currentRefMs_);
  if (kind == FrameKind::Warp) s.inBetweenIntervalMs.push_back(interval);
  // The keyframe worker runs only beside frames, as it would in a viewer:
  // held from here to the next frame's start, it takes no time from the
  // reference render, the metrics or the output, and no frame is spared the
  // sharing of the CPUs that building keyframes ahead costs.
  if (kfWorker_) kfWorker_->hold();
}

// A frame drawn whole (geometry, or a keyframe shown): with pixel ages, their
// update; without, no pixel is stale.
void WalkLoop::recordFreshAge(json& fj, json& ms) {
  if (!trackAge_) {
    fj["stale_pixels"] = 0;  // drawn now: nothing from an earlier frame
    return;
  }
  Stopwatch sa;
  const gapfill::AgeStats as = gapfill::updateAge(previousFrame(), engine_->frame());
  ms["age"] = sa.ms();
  fj["stale_pixels"] = as.stale;
  fj["max_age"] = as.maxAge;
}

// A frame drawn by the geometry renderer: exact, so it is its own reference
// (one render; psnr null as for identical images, ssim 1).
Status WalkLoop::geometryFrame(int i, json& fj, json& ms) {
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  keyframe::RenderStats rs;
  HW_TRY(engine_->drawGeometry(cam, &rs));
  const double renderMs = rs.drawMs + rs.readbackMs;
  chooser_.addGeometryMs(renderMs, static_cast<double>(rs.trianglesDrawn));
  ms["geometry"] = renderMs;
  ms["total"] = renderMs;
  if (opt_.reference) {
    currentRefMs_ = renderMs;
    recorder_.series.referenceMs.push_back(renderMs);
  }
  recordFreshAge(fj, ms);
  // Warping the next segment predicted to pay: its keyframes are built ahead.
  // Replayed, the pin says which segment warps next, however far ahead: its
  // keyframes are asked for from here, so that they are built when it
  // starts (the measured run started warping only on keyframes found built).
  const int next = pinned_.empty() ? schedule_.bracket(i).second
                                   : nextPinnedWarp_[static_cast<std::size_t>(i)];
  // (A replayed segment that warps later in it asked for its own in frame().)
  if (asyncKf_ && opt_.mode == FrameMode::Auto && next > i &&
      (pinned_.empty() ? chooser_.warpNext(false, segmentLength(next)) : !warping_))
    HW_TRY(cache_->prefetch(next));
  endFrameWork(ms, FrameKind::Geometry);
  fj["is_keyframe"] = false;
  fj["keyframes"] = json::array();
  fj["quads"] = 0;
  fj["holes_before_fallback"] = 0.0;
  fj["holes_after_fallback"] = 0.0;
  fj["psnr"] = nullptr;
  fj["ssim"] = opt_.reference ? json(1.0) : json(nullptr);
  return {};
}

Status WalkLoop::keyframeFrame(int i, int k0, json& fj, json& ms) {
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  const keyframe::CachedKeyframe* kf = nullptr;
  HW_TRY(getSource(k0, &kf));
  fj["is_keyframe"] = true;
  fj["keyframes"] = {k0};
  fj["quads"] = kf->mesh.stats.quads;
  const auto& st = kf->mesh.stats;
  const double upload = uploadStats_[k0].uploadMs;
  ms = {{"keyframe_render", kf->renderMs}, {"delta", st.deltaMs}, {"subdivide", st.subdivideMs},
        {"corners", st.cornersMs},         {"upload", upload}};
  ms["total"] = kf->renderMs + st.deltaMs + st.subdivideMs + st.cornersMs + upload;
  InBetweenStats ns;
  HW_TRY(engine_->showKeyframe(cam, k0, kf->keyframe, &ns));
  if (opt_.inBetween.nearDistance > 0) {
    ms["near_geometry"] = ns.nearMs;
    ms["near_geometry_draw"] = ns.nearDrawMs;
    recorder_.series.nearMs.push_back(ns.nearMs);
    ms["total"] = ms["total"].get<double>() + ns.nearMs;
  }
  // The displayed keyframe costs no warp: upload the next keyframe now if it
  // is already built, instead of on the next frame.
  if (i + 1 < frames_) {
    const int next = schedule_.bracket(i + 1).second;
    if (next != k0 && !engine_->has(next) && cache_->contains(next)) {
      const keyframe::CachedKeyframe* kn = nullptr;
      HW_TRY(getSource(next, &kn));
      // No warm-up draw from it here: measured without a reference render
      // (as a viewer runs), one made the keyframe frame 1.4-3 ms and the
      // next frame 1.4-5 ms slower on indoor, oa_dm5 and outdoor:1M.
    }
  }
  recordFreshAge(fj, ms);
  endFrameWork(ms, FrameKind::Keyframe);
  chooser_.addKeyframeMs(ms["frame"].get<double>());
  fj["holes_before_fallback"] = 0.0;
  fj["holes_after_fallback"] = 0.0;
  if (opt_.reference) {
    fj["psnr"] = finiteOrNull(psnr(engine_->frame().colour, reference_));  // identical: +inf → null
    fj["ssim"] = ssim(engine_->frame().colour, reference_);
  } else {
    fj["psnr"] = nullptr;
    fj["ssim"] = nullptr;
  }
  return {};
}

// With a budget: the region whose pixels are oldest re-rendered while its
// estimated cost fits in the time left (WalkOptions::frameBudgetMs).
Status WalkLoop::refresh(const Camera& cam, json& fj, json& ms, gapfill::AgeStats& as) {
  constexpr int kTile = WalkOptions::kRefreshTilePx;
  auto& s = recorder_.series;
  Stopwatch sr;
  int cols = 0, rows = 0;
  gapfill::scoreStaleTiles(engine_->frame().age, opt_.staleAfter, kTile, tileScores_, &cols, &rows);
  long long refreshed = 0;
  json rects = json::array();
  for (int n = 0; n < WalkOptions::kMaxRefreshRects; ++n) {
    if (budgetMs_ <= 0) break;
    const long long maxPx = refreshCost_.maxPixels(budgetMs_ - frameSw_.ms());
    keyframe::PixelRect r;
    if (maxPx < 1 || !gapfill::chooseRefreshRect(tileScores_, cols, rows, kTile, cam.width,
                                                cam.height, maxPx, tileOrder_, &r))
      break;
    const double predicted = refreshCost_.predict(r.area());
    if (workBeforeRefreshMs_ < 0) workBeforeRefreshMs_ = frameSw_.ms();
    Stopwatch one;
    HW_TRY(renderer_->renderColourRect(cam, r, refreshColour_));
    applyRendered(r, refreshColour_, engine_->frame(), engine_->step());
    const double t = one.ms();
    refreshCost_.update(r.area(), t);
    s.refreshPredictedOverMeasured.push_back(t > 0 ? predicted / t : std::nan(""));
    gapfill::clearTileScores(r, cols, kTile, tileScores_);
    refreshed += r.area();
    rects.push_back({{"rect", {r.x0, r.y0, r.width(), r.height()}},
                     {"ms", t},
                     {"predicted_ms", predicted}});
  }
  if (refreshed > 0) {
    as = gapfill::ageStats(engine_->frame().age);
    ++recorder_.counts.framesRefreshed;
    recorder_.counts.refreshRects += static_cast<long long>(rects.size());
  }
  const double rt = sr.ms();
  ms["refresh"] = rt;
  s.refreshMs.push_back(rt);
  s.refreshedPixels.push_back(static_cast<double>(refreshed));
  fj["refreshed_pixels"] = refreshed;
  fj["refresh_rects"] = std::move(rects);
  return {};
}

// WalkOptions::renderHoles (session/hole_pass.h), as many rectangles as
// renderHolesBudget allows. *renderedHoles: the hole pixels (holesBefore)
// they drew. With `fj` null (the calibration frame) nothing is reported.
Status WalkLoop::renderHoles(const Camera& cam, json* fj, json* ms, long long* renderedHoles) {
  Stopwatch sw;
  HoleBudget budget;
  if (opt_.mode == FrameMode::Auto) {
    const double predicted = chooser_.geometryMs();
    budget.fraction = opt_.renderHolesBudget;
    budget.geometryMs = predicted > 0 ? predicted : currentRefMs_;
    budget.frameMsSoFar = frameSw_.ms();
    // Replayed: as many rectangles as the pinned run drew (its budget
    // followed its own timings), so that the frame is the pinned run's.
    const auto f = static_cast<std::size_t>(currentFrame_);
    if (fj && f < pinnedHoleRects_.size() && pinnedHoleRects_[f] >= 0)
      budget.rects = pinnedHoleRects_[f];
  }
  HolePassResult hr;
  double budgetMs = std::nan("");
  HW_TRY(engine_->renderHoles(cam, &budget, &hr, &budgetMs));
  *renderedHoles = hr.holes;
  if (!fj) return {};
  if (!holeRects_.empty()) holeRects_.back() = hr.drawn;
  (*ms)["render_holes"] = sw.ms();
  (*fj)["hole_rects"] = hr.drawn;
  (*fj)["hole_rects_over_budget"] = hr.wanted - hr.drawn;
  (*fj)["holes_budget_ms"] = finiteOrNull(budgetMs);
  (*fj)["hole_rect_pixels"] = hr.area;
  (*fj)["hole_triangles"] = hr.triangles;
  (*fj)["holes_rendered"] = hr.holes;
  recorder_.series.holesRenderedPixels.push_back(static_cast<double>(hr.holes));
  return {};
}

Status WalkLoop::inBetweenFrame(int i, int k0, int k1, json& fj, json& ms) {
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  auto& s = recorder_.series;
  const keyframe::CachedKeyframe* kfa = nullptr;
  const keyframe::CachedKeyframe* kfb = nullptr;
  HW_TRY(getSource(k0, &kfa));
  HW_TRY(getSource(k1, &kfb));
  Stopwatch total;
  InBetweenStats st;
  int fgFrame = k0;  // the keyframe whose eye is nearer (paper §2.2 (i))
  HW_TRY(engine_->warp(cam, k0, k1, st, &fgFrame));
  if (st.fused) {
    if (st.backgroundDrawn) s.backgroundCulled.push_back(st.backgroundCulled);
    ms = {{"warp_a", st.warpAMs}, {"warp_b", st.warpBMs},
          {"readback", st.readbackMs}, {"compose", st.composeMs}};
    if (st.cullMs > 0) ms["cull"] = st.cullMs;
  } else {
    ms = {{"warp_a", st.warpAMs},          {"warp_b", st.warpBMs},
          {"warp_a_draw", st.warpADrawMs}, {"warp_b_draw", st.warpBDrawMs},
          {"readback", st.readbackMs},     {"compose", st.composeMs}};
  }
  s.warpMs.push_back(st.warpMs());
  if (st.nearMs >= 0) {
    ms["near_geometry"] = st.nearMs;
    ms["near_geometry_draw"] = st.nearDrawMs;
    s.nearMs.push_back(st.nearMs);
  }
  const double totalMs = total.ms();  // the hole render has its own ms
  ms["total"] = totalMs;
  long long renderedHoles = 0;
  if (!trackAge_ && opt_.renderHoles) HW_TRY(renderHoles(cam, &fj, &ms, &renderedHoles));
  if (trackAge_) {
    Stopwatch sa;
    gapfill::AgeStats as = gapfill::updateAge(previousFrame(), engine_->frame());
    ms["age"] = sa.ms();
    if (opt_.renderHoles) {  // after the ages, which go by holesBefore: its pixels get age 0
      HW_TRY(renderHoles(cam, &fj, &ms, &renderedHoles));
      if (renderedHoles > 0) as = gapfill::ageStats(engine_->frame().age);
    }
    fj["stale_pixels_before_refresh"] = as.stale;
    if (budgetOn_) HW_TRY(refresh(cam, fj, ms, as));
    fj["stale_pixels"] = as.stale;
    fj["max_age"] = as.maxAge;
    s.stalePixels.push_back(as.stale);
    s.maxAges.push_back(as.maxAge);
  } else {
    // Without ages: the pixels no keyframe layer (nor near geometry) gave,
    // the same count as the ages' (age >= 1 exactly there).
    long long stale = -renderedHoles;
    for (std::size_t p = 0; p < engine_->frame().holesBefore.size(); ++p) stale += engine_->frame().holesBefore.data()[p];
    fj["stale_pixels"] = stale;
    s.stalePixels.push_back(static_cast<double>(stale));
  }
  fj["reprojected_pixels"] = opt_.inBetween.reprojects() ? json(st.reprojectedPixels) : json(nullptr);
  if (opt_.inBetween.reprojects()) s.reprojectedPixels.push_back(st.reprojectedPixels);
  if (st.fallbackMs >= 0) {
    ms["fallback"] = st.fallbackMs;
    s.fallbackMs.push_back(st.fallbackMs);
  }
  const bool blend = opt_.inBetween.compose.mode == gapfill::ComposeMode::Blend;
  fj["blended_pixels"] = blend ? json(engine_->frame().blended) : json(nullptr);
  if (blend) s.blendedPixels.push_back(engine_->frame().blended);
  recorder_.counts.backgroundSkips += st.backgroundSkipped();
  recorder_.counts.previousSkips += st.previousSkipped;
  fj["is_keyframe"] = false;
  fj["keyframes"] = {k0, k1};
  fj["foreground"] = fgFrame;
  fj["quads"] = st.quads();
  fj["skipped"] = {{"background", st.backgroundSkipped()}, {"previous_frame", st.previousSkipped}};
  fj["foreground_uncovered_pixels"] = st.foregroundUncovered;
  s.foregroundUncovered.push_back(st.foregroundUncovered);
  endFrameWork(ms, FrameKind::Warp);
  s.inBetweenFrameMs.push_back(ms["frame"].get<double>());
  chooser_.addInBetweenMs(ms["frame"].get<double>());
  if (opt_.frameBudgetAuto)  // the next frames' budget: this frame's work without its refresh
    autoBudget_->add(ms["frame"].get<double>() -
                     (ms.contains("refresh") ? ms["refresh"].get<double>() : 0.0));
  fj["holes_before_fallback"] = engine_->frame().holeFractionBefore;
  fj["holes_after_fallback"] = engine_->frame().holeFractionAfter;
  s.holesBefore.push_back(engine_->frame().holeFractionBefore);
  s.holesAfter.push_back(engine_->frame().holeFractionAfter);
  s.inBetweenMs.push_back(totalMs);
  s.composeMs.push_back(st.composeMs);
  recordQuality(i, fj, st.fused, st.backgroundSkipped());
  return {};
}

// PSNR, SSIM and per-channel MSE against the reference; the large-leaf pixels'
// PSNR; the strip when this frame is one of them.
void WalkLoop::recordQuality(int i, json& fj, bool fused, bool bgSkipped) {
  auto& s = recorder_.series;
  if (opt_.reference) {
    const ChannelMse m = channelMse(engine_->frame().colour, reference_);
    const double p = psnrFromMse(m.mean());  // psnr(), from the same sums
    const double q = ssim(engine_->frame().colour, reference_);
    fj["psnr"] = finiteOrNull(p);
    fj["ssim"] = q;
    fj["mse"] = {{"r", m.r}, {"g", m.g}, {"b", m.b}};
    s.psnr.push_back(std::isfinite(p) ? p : 99.0);
    s.ssim.push_back(q);
    // How much of the error the holes (holesBefore: no keyframe layer of this
    // pair nor near geometry drew them; filled by the fallback, the refresh or
    // --render-holes) carry, and the PSNR of the other pixels.
    const std::size_t n = engine_->frame().colour.size();
    if (engine_->frame().holesBefore.size() == n && reference_.size() == n) {
      const auto staleCount = static_cast<std::size_t>(
          std::count_if(engine_->frame().holesBefore.data(), engine_->frame().holesBefore.data() + n,
                        [](std::uint8_t h) { return h != 0; }));
      const std::size_t drawn = n - staleCount;
      // Summed squared errors over R, G, B: integers (channelMse sums exactly),
      // so the rounding below recovers them.
      const double total = std::round(3.0 * m.mean() * static_cast<double>(n));
      const double staleErr =
          staleCount > 0
              ? std::round(3.0 * channelMse(engine_->frame().colour, reference_, engine_->frame().holesBefore).mean() *
                           static_cast<double>(staleCount))
              : 0.0;
      const double pd =
          drawn > 0 ? psnrFromMse((total - staleErr) / (3.0 * static_cast<double>(drawn)))
                    : std::nan("");
      const double share = total > 0 ? staleErr / total : 0.0;
      fj["psnr_drawn"] = finiteOrNull(pd);
      fj["stale_error_share"] = share;
      if (!std::isnan(pd)) s.psnrDrawn.push_back(std::isfinite(pd) ? pd : 99.0);
      s.staleErrorShare.push_back(share);
    }
  } else {
    fj["psnr"] = nullptr;
    fj["ssim"] = nullptr;
  }
  // Pixels whose colour came from a large leaf of either layer (the ones
  // subdivision changes; previous-frame fill, near objects, refresh: not).
  // Unknown with the depth merge, which does not say which layer won.
  if (engine_->warpOptions().markLargeQuads &&
      (fused || opt_.inBetween.compose.mode == gapfill::ComposeMode::Overlay)) {
    warp::Layer& layerA = engine_->step().layerA();
    const warp::Layer& layerB = engine_->step().layerB();
    Image<std::uint8_t>& large = layerA.largeQuad;
    if (!fused && !bgSkipped)
      for (std::size_t p = 0; p < large.size(); ++p)
        if (!layerA.coverage.data()[p])
          large.data()[p] = layerB.coverage.data()[p] ? layerB.largeQuad.data()[p] : 0;
    long long count = 0;
    for (std::size_t p = 0; p < large.size(); ++p) count += large.data()[p];
    fj["large_quad_pixels"] = count;
    s.largeQuadPixels.push_back(static_cast<double>(count));
    const double pl =
        opt_.reference ? psnrCapped(engine_->frame().colour, reference_, large) : std::nan("");
    fj["psnr_large_quads"] = finiteOrNull(pl);  // NaN: no such pixel or no reference
    if (std::isfinite(pl)) s.psnrLargeQuads.push_back(pl);
  } else {
    fj["large_quad_pixels"] = nullptr;
    fj["psnr_large_quads"] = nullptr;
  }
  // A strip frame drawn as geometry (FrameMode::Auto) passes its strip to
  // the next warped frame.
  bool strip = false;
  while (nextStrip_ < stripFrames_.size() && stripFrames_[nextStrip_] <= i) {
    strip = true;
    ++nextStrip_;
  }
  if (writing_ && opt_.reference && strip) {
    const Image<Rgba8> diff = diffImage(engine_->frame().colour, reference_, 4);
    const Image<Rgba8> holes =
        maskToImage(engine_->frame().holesBefore, Rgba8{255, 40, 40, 255}, Rgba8{30, 30, 30, 255});
    recorder_.strips.push_back(
        hstack({&reference_, &engine_->frame().colour, &diff, &holes}, 4, Rgba8{255, 255, 255, 255}));
    recorder_.stripInfo.push_back({{"frame", i},
                                   {"psnr", fj["psnr"]},
                                   {"ssim", fj["ssim"]},
                                   {"holes_before_fallback", engine_->frame().holeFractionBefore}});
  }
}

// Drop GPU copies of keyframes no later frame can use.
void WalkLoop::releaseBefore(int k0) {
  engine_->releaseBefore(k0);
  for (auto it = uploadStats_.begin(); it != uploadStats_.end();)
    it = it->first < k0 ? uploadStats_.erase(it) : std::next(it);
  cache_->releaseBefore(k0);
}

Status WalkLoop::frame(int i) {
  currentFrame_ = i;
  builtThisFrame_ = false;
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  json fj;
  fj["index"] = i;
  const auto [k0, k1] = schedule_.bracket(i);
  FrameKind kind = FrameKind::Geometry;
  HW_TRY(chooseKind(i, k0, k1, &kind));
  if (!pinFile_.empty() && pinned_.empty()) holeRects_.push_back(-1);
  json ms = json::object();
  currentRefMs_ = std::nan("");
  if (opt_.reference && kind != FrameKind::Geometry) {  // a geometry frame is its own
    keyframe::RenderStats rs;
    // The keyframe worker is held here (see endFrameWork), so the reference
    // is timed alone. The first whole-scene draw after a new warp source
    // was drawn from costs llvmpipe a one-time stall (about 100 ms on
    // indoor:1M, measured; the draw after it does not): a cost of
    // switching, not of drawing the view, so that draw is not the one timed.
    Status refStatus;
    if (referenceCold_) refStatus = renderer_->renderColour(cam, reference_, nullptr);
    referenceCold_ = false;
    if (refStatus.ok()) refStatus = renderer_->renderColour(cam, reference_, &rs);
    HW_TRY(refStatus);
    currentRefMs_ = rs.drawMs + rs.readbackMs;
    recorder_.series.referenceMs.push_back(currentRefMs_);
  }
  // What a viewer waits for: keyframe acquisition (build or wait), upload,
  // warp, compose; not the reference or the metrics.
  if (opt_.frameBudgetAuto) {
    budgetMs_ = autoBudget_->budgetMs();
    fj["budget_ms"] = budgetMs_ > 0 ? json(budgetMs_) : json(nullptr);
  }
  frameSw_.restart();
  frameStart_ = std::chrono::steady_clock::now();
  workBeforeRefreshMs_ = -1;
  frameWaitMs_ = 0;
  if (asyncKf_) {
    kfWorker_->release();
    kfWorker_->frameTick();
    if (warping_) HW_TRY(cache_->prefetch(i));
  }
  if (kind == FrameKind::Geometry)
    HW_TRY(geometryFrame(i, fj, ms));
  else if (kind == FrameKind::Keyframe)
    HW_TRY(keyframeFrame(i, k0, fj, ms));
  else
    HW_TRY(inBetweenFrame(i, k0, k1, fj, ms));
  ++kindCounts_[static_cast<int>(kind)];
  lastKind_ = kind;
  fj["mode"] = frameKindName(kind);
  ms["keyframe_wait"] = frameWaitMs_;
  recorder_.series.frameMs.push_back(ms["frame"].get<double>());
  fj["reference_ms"] = opt_.reference ? json(currentRefMs_) : json(nullptr);
  fj["ms"] = ms;
  if (writing_ && opt_.saveFrames) {
    HW_TRY(writePng(opt_.outDir + "/frames/" + frameName(i), engine_->frame().colour));
    HW_TRY(writePng(opt_.outDir + "/holes/" + frameName(i),
                    maskToImage(engine_->frame().holesBefore, Rgba8{255, 40, 40, 255},
                                Rgba8{0, 0, 0, 255})));
  }
  if (kind == FrameKind::Warp && fj["reference_ms"].is_number())
    recorder_.series.speedup.push_back(fj["reference_ms"].get<double>() /
                                       fj["ms"]["total"].get<double>());
  HW_TRY(recorder_.addFrame(std::move(fj)));
  engine_->present();
  releaseBefore(k0);
  recorder_.counts.glErrors += gl::drainGlErrors();
  // The soak's sample (scripts/soak.sh), every 500th frame, at a quiet point:
  // llvmpipe's binned triangles released and free heap pages returned, so
  // that what is read is what the walk keeps (docs/notes/soak-sample.md).
  if ((i + 1) % 500 == 0) {
    gl::releaseFinishedRenderMemory();
    returnFreeHeapPages();
    recorder_.residentKiB.push_back({i + 1, residentKiB()});
  }
  return {};
}

Result<WalkResult> WalkLoop::run() {
  HW_TRY(setUp());
  HW_TRY(warmUp());
  HW_TRY(recorder_.open());
  debugErrors0_ = gl::debugCallbackErrors();
  chooseStripFrames();
  Progress progress(opt_.progress, frames_, "walk");
  for (int i = 0; i < frames_; ++i) {
    if (!walked_.empty() && !walked_[static_cast<std::size_t>(i)]) continue;
    HW_TRY(frame(i));
    progress.update(i + 1);
  }
  writePin();
  WalkResult result;
  HW_TRY(recorder_.finish(summary(), writing_ ? opt_.outDir + "/report.json" : std::string(),
                          &result.report));
  result.strips = std::move(recorder_.strips);
  result.frameTimes = recorder_.frameTimes.take();
  result.frameTimes.floorMs = floor_.twoLayersMs;
  return result;
}

json WalkLoop::summary() const {
  const auto& r = recorder_.series;
  json s;
  s["scene"] = {{"name", label_}, {"triangles", scene_.triangleCount()}};
  s["resolution"] = {path_.width, path_.height};
  s["frames"] = frames_;
  s["keyframes"] = static_cast<int>(cache_->builds());
  s["in_between_frames"] = static_cast<int>(inBetweenCount_);
  s["keyframe_every"] = path_.keyframeEvery;
  s["keyframe_schedule"] = opt_.keyframeFrames.empty() ? "fixed" : "explicit";
  s["keyframe_frames"] = schedule_.keyframes();
  summariseLod(s);
  s["psnr"] = seriesStats(r.psnr);
  s["psnr_large_quads"] = seriesStats(r.psnrLargeQuads);
  s["large_quad_pixels"] = seriesStats(r.largeQuadPixels);
  s["ssim"] = seriesStats(r.ssim);
  s["holes_before_fallback"] = seriesStats(r.holesBefore);
  s["holes_after_fallback"] = seriesStats(r.holesAfter);
  s["quads_per_keyframe"] = seriesStats(r.quadsPerKeyframe);
  s["in_between_ms"] = seriesStats(r.inBetweenMs);
  s["warp_ms"] = seriesStats(r.warpMs);
  s["compose_ms"] = seriesStats(r.composeMs);
  s["reference_ms"] = seriesStats(r.referenceMs);
  s["keyframe_build_ms"] = seriesStats(r.keyframeMs);
  s["lod_build_ms"] = seriesStats(r.lodBuildMs);
  s["one_pixel_leaves_per_keyframe"] = seriesStats(r.onePixelLeaves);
  s["speedup_reference_over_in_between"] = seriesStats(r.speedup);
  s["gl_errors"] = std::max(recorder_.counts.glErrors,
                            debugErrors0_ < 0 ? 0LL : gl::debugCallbackErrors() - debugErrors0_);
  s["resident_kib_every_500_frames"] = recorder_.residentKiB;
  summariseTiming(s);
  summariseBudget(s);
  summariseModes(s);
  s["machine"] = machineInfo(opt_.glRenderer, opt_.glVersion);
  s["strips"] = recorder_.stripInfo;
  return s;
}

void WalkLoop::summariseLod(json& s) const {
  const auto& r = recorder_.series;
  const auto& c = recorder_.counts;
  const auto& ib = opt_.inBetween;
  s["tau"] = opt_.lod.tauParallaxPx > 0 ? json(nullptr) : json(opt_.lod.tau);
  s["tau_parallax_px"] = opt_.lod.tauParallaxPx;
  s["criterion"] = keyframe::deltaCriterionName(opt_.lod.criterion);
  s["mesh"] = keyframe::meshMethodName(opt_.mesh);
  s["planarity"] = keyframe::planarityName(opt_.lod.planarity);
  s["merge_strips"] = opt_.lod.mergeStrips;
  s["tau_gradient"] = opt_.lod.tauGradient;
  s["tile_size"] =
      opt_.mesh == keyframe::MeshMethod::UniformTiles ? json(opt_.tileSize) : json(nullptr);
  s["depth_mode"] = depthModeName(opt_.depthMode);
  s["compose_mode"] = gapfill::composeModeName(ib.compose.mode);
  s["texcoords"] = warp::texcoordModeName(opt_.warp.texcoords);
  s["sky_backdrop"] = opt_.warp.skyBackdrop;
  s["layers"] = ib.fused() ? "fused" : "separate";
  s["warper_option"] = warp::warperChoiceName(opt_.warper);
  s["warper"] = engine_->cpuWarper() ? "cpu" : "gl";
  s["warper_threads"] = engine_->cpuWarper() ? json(opt_.warperThreads) : json(nullptr);
  s["near_distance"] = ib.nearDistance;
  s["fallback"] = gapfill::fallbackName(ib.fallback);
  s["render_holes"] = opt_.renderHoles;
  s["render_holes_budget"] = opt_.renderHoles ? json(opt_.renderHolesBudget) : json(nullptr);
  s["simplify_holes"] = opt_.renderHoles ? json(opt_.simplifyHoles) : json(nullptr);
  s["hole_rects_max"] = opt_.renderHoles ? json(opt_.holeRectsMax) : json(nullptr);
  s["hole_tile_px"] = opt_.renderHoles ? json(opt_.holeTilePx) : json(nullptr);
  s["holes_rendered"] = seriesStats(r.holesRenderedPixels);
  s["reprojected_pixels"] = seriesStats(r.reprojectedPixels);
  s["fallback_ms"] = seriesStats(r.fallbackMs);
  s["blend_softness"] = ib.compose.mode == gapfill::ComposeMode::Blend
                            ? json(ib.compose.blendSoftness)
                            : json(nullptr);
  s["blended_pixels"] = seriesStats(r.blendedPixels);
  s["subdivision"] = warp::subdivisionName(opt_.warp.subdivision);
  s["primitives"] = warp::primitivesName(opt_.warp.primitives);
  s["points_per_keyframe"] = seriesStats(r.pointsPerKeyframe);  // 1×1 leaves as points
  s["cull_background"] =
      opt_.warp.cullBackground && opt_.warp.primitives != warp::Primitives::Independent;
  s["background_quads_culled"] = seriesStats(r.backgroundCulled);
  s["subdivide_cell_px"] = opt_.warp.subdivideCellPx;
  s["drawn_quads_per_keyframe"] = seriesStats(r.drawnQuads);
  s["subdivided_quads_per_keyframe"] = seriesStats(r.subdividedQuads);
  s["near_geometry_ms"] = seriesStats(r.nearMs);
  s["skip_background"] = ib.skipBackground;
  s["skip_previous_frame"] = ib.skipPrevious;
  s["background_layer_skipped_frames"] = c.backgroundSkips;
  s["foreground_uncovered_pixels"] = seriesStats(r.foregroundUncovered);
  s["previous_frame_pass_skipped_frames"] = c.previousSkips;
}

// Frame-time stability: wall time per frame as a viewer sees it, keyframe
// frames included, and the in-between frames alone; keyframe acquisition.
void WalkLoop::summariseTiming(json& s) const {
  const auto& r = recorder_.series;
  auto ratio = [](const WalkRecorder::Column& c) {
    const std::vector<double> v = c.values();
    const double m = median(v);
    return m > 0 ? finiteOrNull(percentile(v, 95) / m) : json(nullptr);
  };
  using P = WalkOptions::KeyframePacing;
  const bool timed = opt_.keyframePacing == P::Time || opt_.keyframePacing == P::Slices;
  s["keyframe_acquisition"] = opt_.keyframeSource ? "source" : asyncKf_ ? "async" : "sync";
  s["async_keyframes"] = asyncKf_;
  s["keyframe_prefetch"] = asyncKf_ ? json(opt_.keyframePrefetch) : json(nullptr);
  s["keyframe_cache_mb"] = static_cast<double>(opt_.keyframeCacheBytes) / (1 << 20);
  s["keyframe_cache_peak_mb"] = static_cast<double>(cache_->peakBytes()) / (1 << 20);
  s["keyframe_cache_evictions"] = cache_->evictions();
  s["keyframe_cache_released"] = cache_->released();
  s["frame_ms"] = seriesStats(r.frameMs);
  s["frame_ms_p95_over_median"] = ratio(r.frameMs);
  s["in_between_frame_ms"] = seriesStats(r.inBetweenFrameMs);
  s["in_between_frame_ms_p95_over_median"] = ratio(r.inBetweenFrameMs);
  s["floor_ms"] = {{"one_layer", floor_.oneLayerMs >= 0 ? json(floor_.oneLayerMs) : json(nullptr)},
                   {"two_layers", floor_.twoLayersMs >= 0 ? json(floor_.twoLayersMs) : json(nullptr)},
                   {"draws", floor_.reps}};
  {
    const std::vector<double> ib = r.inBetweenFrameMs.values();
    const double fl = floor_.twoLayersMs;
    s["in_between_frame_over_floor"] =
        ib.empty() || !(fl > 0) ? json(nullptr)
                                : json{{"median", finiteOrNull(median(ib) / fl)},
                                       {"p95", finiteOrNull(percentile(ib, 95) / fl)}};
  }
  s["keyframe_stalls"] = cache_->stalls() - warmupStalls_;
  s["keyframe_warmup_ms"] = warmupMs_;
  s["keyframe_stall_ms"] = seriesStats(r.stallMs);
  double stallTotal = 0;
  for (double t : r.stallMs.values()) stallTotal += t;
  s["keyframe_stall_ms_total"] = stallTotal;
  s["keyframe_flush_triangles"] = asyncKf_ ? json(opt_.keyframeFlushTriangles) : json(nullptr);
  s["keyframe_worker_nice"] = asyncKf_ ? json(opt_.keyframeWorkerNice) : json(nullptr);
  s["keyframe_pacing"] = asyncKf_ ? json(keyframePacingName(opt_.keyframePacing)) : json(nullptr);
  s["keyframe_budget_scale"] = asyncKf_ && timed ? json(opt_.keyframeBudgetScale) : json(nullptr);
  s["keyframe_slice_ms"] = r.sliceMs.empty() ? json(nullptr) : seriesStats(r.sliceMs);
  s["keyframe_steps_per_frame"] = asyncKf_ && opt_.keyframePacing == P::Steps
                                      ? json(opt_.keyframeStepsPerFrame)
                                      : json(nullptr);
  s["keyframe_worker_busy_ms"] = kfWorker_ ? json(kfWorker_->workerBusyMs()) : json(nullptr);
  s["frame_interval_ms"] = seriesStats(r.frameIntervalMs);
  s["frame_interval_ms_p95_over_median"] = ratio(r.frameIntervalMs);
  s["in_between_frame_interval_ms"] = seriesStats(r.inBetweenIntervalMs);
  s["in_between_frame_interval_ms_p95_over_median"] = ratio(r.inBetweenIntervalMs);
}

// Frame budget and pixel age (WalkOptions::frameBudgetMs). With the automatic
// budget: the median of the per-frame budgets.
void WalkLoop::summariseBudget(json& s) const {
  const auto& r = recorder_.series;
  const auto& c = recorder_.counts;
  std::vector<double> budgets;  // the frames that had one
  for (double b : recorder_.frameTimes.budgetMs.values())
    if (b > 0) budgets.push_back(b);
  s["frame_budget_ms"] = opt_.frameBudgetAuto ? finiteOrNull(median(budgets))
                                              : json(opt_.frameBudgetMs);
  s["frame_budget_mode"] = opt_.frameBudgetAuto ? "auto" : budgetOn_ ? "fixed" : "off";
  s["frame_budget_auto"] =
      opt_.frameBudgetAuto
          ? json{{"quantile", opt_.frameBudgetQuantile},
                 {"window_frames", opt_.frameBudgetWindow},
                 {"budget_ms", seriesStats(budgets)},
                 {"frames_without_budget", frames_ - static_cast<int>(budgets.size())}}
          : json(nullptr);
  s["frame_pacing"] = budgetOn_ && opt_.paceFrames;
  s["pixel_age"] = trackAge_;
  s["stale_after"] = budgetOn_ ? json(opt_.staleAfter) : json(nullptr);
  s["refresh_tile_px"] = budgetOn_ ? json(WalkOptions::kRefreshTilePx) : json(nullptr);
  s["stale_pixels"] = seriesStats(r.stalePixels);
  s["psnr_drawn"] = seriesStats(r.psnrDrawn);
  s["stale_error_share"] = seriesStats(r.staleErrorShare);
  s["max_age"] = seriesStats(r.maxAges);
  s["refreshed_pixels"] = seriesStats(r.refreshedPixels);
  s["refresh_ms"] = seriesStats(r.refreshMs);
  s["frames_refreshed"] = c.framesRefreshed;
  s["refresh_rects"] = c.refreshRects;
  s["refresh_cost_model"] = budgetOn_ ? json{{"fixed_ms", refreshCost_.fixedMs},
                                             {"per_megapixel_ms", refreshCost_.perPixelMs * 1e6},
                                             {"scale_at_end", refreshCost_.scale},
                                             {"margin", RefreshCostModel::kMargin},
                                             {"calibration_ms", refreshCalibrationMs_}}
                                       : json(nullptr);
  s["budget_overruns"] = budgetOn_ ? json(c.budgetOverruns) : json(nullptr);
  s["budget_overruns_in_between"] = budgetOn_ ? json(c.budgetOverrunsInBetween) : json(nullptr);
  s["budget_overruns_by_refresh"] = budgetOn_ ? json(c.budgetOverrunsByRefresh) : json(nullptr);
  s["refresh_predicted_over_measured"] = seriesStats(r.refreshPredictedOverMeasured);
}

// The frame mode: how many frames each way, the costs the choice ended
// with, and the headline ratio of frame time to geometry time.
void WalkLoop::summariseModes(json& s) const {
  const auto& r = recorder_.series;
  s["mode"] = frameModeName(opt_.mode);
  s["frames_by_mode"] = {{"geometry", kindCounts_[0]},
                         {"warp", kindCounts_[1]},
                         {"keyframe", kindCounts_[2]}};
  s["mode_switches"] = modeSwitches_;
  s["segments_given_up"] = segmentsGivenUp_;
  s["warp_starts_deferred"] = warpStartsDeferred_;
  s["geometry_probes"] = geometryProbes_;
  s["auto_pin"] = opt_.mode == FrameMode::Auto
                      ? json{{"setting", autoPinName(opt_.autoPin)},
                             {"state", pinState_},
                             {"file", pinFile_.empty() ? json(nullptr) : json(pinFile_)},
                             {"deviations", pinDeviations_},
                             {"note", pinNote_.empty() ? json(nullptr) : json(pinNote_)}}
                      : json(nullptr);
  s["mode_costs"] =
      opt_.mode == FrameMode::Auto
          ? json{{"geometry_ms", finiteOrNull(chooser_.geometryWindowMs())},
                 {"geometry_recent_ms", finiteOrNull(chooser_.geometryRecentMs())},
                 {"geometry_by_triangles", opt_.modeChooser.geometryByTriangles},
                 {"view_triangles", chooser_.viewTriangles() >= 0
                                        ? json(chooser_.viewTriangles())
                                        : json(nullptr)},
                 {"geometry_view_ms", finiteOrNull(chooser_.geometryMs())},
                 {"geometry_recent", opt_.modeChooser.geometryRecent},
                 {"in_between_ms", finiteOrNull(chooser_.inBetweenMs())},
                 {"in_between_tail_ms", finiteOrNull(chooser_.inBetweenTailMs())},
                 {"warp_floor_ms", warpFloorMs_ >= 0 ? json(warpFloorMs_) : json(nullptr)},
                 {"warp_calibration_ms",
                  warpCalibrationMs_ >= 0 ? json(warpCalibrationMs_) : json(nullptr)},
                 {"enter_below", opt_.modeChooser.enterBelow},
                 {"leave_above", opt_.modeChooser.leaveAbove},
                 {"tail_quantile", opt_.modeChooser.tailQuantile},
                 {"tail_enter_below", opt_.modeChooser.tailEnterBelow},
                 {"tail_leave_above", opt_.modeChooser.tailLeaveAbove}}
          : json(nullptr);
  auto over = [](double a, double b) { return b > 0 ? finiteOrNull(a / b) : json(nullptr); };
  const std::vector<double> frameMs = r.frameMs.values(), referenceMs = r.referenceMs.values();
  s["frame_over_reference"] =
      referenceMs.empty()
          ? json(nullptr)
          : json{{"median", over(median(frameMs), median(referenceMs))},
                 {"p95", over(percentile(frameMs, 95), percentile(referenceMs, 95))}};
}

}  // namespace

const char* keyframePacingName(KeyframePacing p) {
  switch (p) {
    case KeyframePacing::Time: return "time";
    case KeyframePacing::Slices: return "slices";
    case KeyframePacing::Steps: return "steps";
    case KeyframePacing::None: break;
  }
  return "none";
}

Result<WalkResult> runWalk(const scenes::Scene& scene, const std::string& sceneLabel,
                           const scenes::CameraPath& path, const WalkOptions& options) {
  WalkLoop loop(scene, sceneLabel, path, options);
  return loop.run();
}

}  // namespace hw::session
