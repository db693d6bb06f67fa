// The viewer's keyframes and frames: two keyframes kept around the viewer
// (rendered, read from a baked database, or built ahead on the worker
// thread), the mode chooser of --mode auto, and each frame drawn through the
// frame engine (session/frame_engine.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/gl/viewer_impl.h"
#include "app/keyframe_pacing.h"
#include "core/gl/gl_api.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "session/hole_pass.h"
#include "session/in_between.h"

namespace hw::app::viewer_detail {
namespace {

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

}  // namespace

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

// Where the viewer will be when it is `distance` pose-distance units away:
// the path's camera when playing, else the current motion extrapolated.
Camera Viewer::aheadCamera(double distance) const {
  if (play_ && playCams_.size() > 1)
    return sized(pathCameraAhead(playCams_, playIndex_, cam_, distance, metric()));
  return motion_.extrapolate(cam_, distance, metric(), width_, height_);
}

// The keyframe after `newest`, `spacing` beyond it: playing, on the path
// (pathCameraBeyond); else the motion extrapolated to `distance` from the viewer.
Camera Viewer::beyondCamera(const Camera& newest, double spacing, double distance) const {
  if (!(play_ && playCams_.size() > 1)) return aheadCamera(distance);
  return sized(pathCameraBeyond(playCams_, playIndex_, cam_, newest, spacing, metric()));
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
    HW_TRY(engine_->showImage(fg.kf.colour));
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
      budget.geometryMs = auto_.geometryMs();
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

// --mode auto (app/viewer_auto_mode.h); `g` ends it.
void Viewer::chooseMode(bool* probe) {
  *probe = false;
  if (!autoMode_) return;
  const ViewerAutoMode::Step s =
      auto_.step(hybrid_, static_cast<double>(renderer_->visibleTriangles(cam_)), frameIndex_,
                 worker_ || opt_.keyframeDb);
  *probe = s.probe;
  if (!s.switched) return;
  hybrid_ = s.hybrid;
  engine_->forgetPrevious();
  if (s.gaveUp)
    message("auto: geometry (hybrid frames cost more; from frame " + std::to_string(frameIndex_) +
            ")");
  else
    message(std::string(hybrid_ ? "auto: hybrid" : "auto: geometry") +
            " (cheaper now; from frame " + std::to_string(frameIndex_) + ")");
}

void Viewer::recordCost(const FrameStats& st, double workMs) {
  auto_.record(st.kind(), workMs, st.geometryMs, static_cast<double>(st.trianglesDrawn),
               st.builtKeyframe, lastKeyframe_.renderMs,
               static_cast<double>(lastKeyframe_.triangles));
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
    const Status s = engine_->drawGeometry(cam_, &rs);
    if (wireframe_) glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    HW_TRY(s);
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

}  // namespace hw::app::viewer_detail
