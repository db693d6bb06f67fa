#include "keyframe/gl/async_keyframes.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/check.h"
#include "core/gl/context.h"
#include "core/gl/gl_api.h"
#include "core/timer.h"
#include "keyframe/lod_builder.h"

namespace hw::keyframe {

Result<std::unique_ptr<AsyncKeyframes>> AsyncKeyframes::create(
    const scenes::Scene& scene, std::function<Camera(int)> cameraOf,
    const AsyncKeyframeOptions& options) {
  HW_CHECK_GE(options.maxQueued, 1);
  std::unique_ptr<AsyncKeyframes> a(new AsyncKeyframes());
  a->cameraOf_ = std::move(cameraOf);
  a->options_ = options;
  a->framesPerKeyframe_.store(options.framesPerKeyframe, std::memory_order_relaxed);
  Status init;
  a->thread_ = std::thread(&AsyncKeyframes::run, a.get(), &scene, &init);
  {
    std::unique_lock lock(a->mutex_);
    a->doneCv_.wait(lock, [&] { return a->initDone_; });
  }
  if (!init.ok()) return init.error();  // the worker has exited; ~AsyncKeyframes joins
  return a;
}

AsyncKeyframes::~AsyncKeyframes() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    queue_.clear();
  }
  workCv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void AsyncKeyframes::endStep() {
  const double now = clock_.ms();
  lastStepMs_ = now - stepStartMs_;
  tickBusyMs_.fetch_add(now - stepStartMs_, std::memory_order_relaxed);
  debtMs_ += now - stepStartMs_;
  buildStepMs_ += now - stepStartMs_;
  stepStartMs_ = now;
}

void AsyncKeyframes::pace() {
  if (options_.slices && options_.framesPerKeyframe > 0) {
    endStep();
    std::unique_lock lock(mutex_);
    if (sliceOpen_) sliceUsedMs_ += lastStepMs_;
    auto canRun = [&] {
      return stop_ || waiting_ > 0 || (sliceOpen_ && sliceUsedMs_ < sliceBudgetMs_);
    };
    if (!canRun()) {
      parked_ = true;
      doneCv_.notify_all();  // the slice is used up
      workCv_.wait(lock, canRun);
      parked_ = false;
    }
    stepStartMs_ = clock_.ms();
    return;
  }
  if (options_.framesPerKeyframe > 0) {
    endStep();
    std::unique_lock lock(mutex_);
    // Read in every check: setFramesPerKeyframe() applies at once.
    auto settle = [&] {  // each new frame pays back one budget
      const double budget = std::max(0.5, options_.budgetScale * lastBuildMs_ /
                                              framesPerKeyframe_.load(std::memory_order_relaxed));
      if (ticks_ > paidTicks_) {
        debtMs_ = std::max(0.0, debtMs_ - budget * static_cast<double>(ticks_ - paidTicks_));
        paidTicks_ = ticks_;
      }
      // Unpaced while waited for, and before the first build is measured
      // (paced by the 0.5 ms floor, a first build asked for well ahead took
      // more frames to finish than the walk had before its need).
      if (stop_ || waiting_ > 0 || lastBuildMs_ <= 0) {
        debtMs_ = 0;  // nothing to pay back
        return true;
      }
      return debtMs_ < budget;
    };
    boundaryWait(lock, settle);
    stepStartMs_ = clock_.ms();
    return;
  }
  endStep();
  std::unique_lock lock(mutex_);
  if (options_.stepsPerFrame <= 0) {
    boundaryWait(lock, [] { return true; });
    stepStartMs_ = clock_.ms();
    return;
  }
  const long long per = options_.stepsPerFrame;
  // Nothing banked beyond the current frame's budget while idle, so no
  // burst follows.
  steps_ = std::max(steps_, (ticks_ - 1) * per);
  boundaryWait(lock, [&] { return stop_ || waiting_ > 0 || steps_ < ticks_ * per; });
  ++steps_;
  stepStartMs_ = clock_.ms();
}

void AsyncKeyframes::boundaryWait(std::unique_lock<std::mutex>& lock,
                                  const std::function<bool()>& ready) {
  auto go = [&] { return ready() && (!held_ || stop_ || waiting_ > 0); };
  if (go()) return;
  if (held_) {  // unpaced pieces are not finished: the hold covers their rasterisation
    lock.unlock();
    glFinish();
    lock.lock();
  }
  atBoundary_ = true;
  doneCv_.notify_all();
  workCv_.wait(lock, go);
  atBoundary_ = false;
}

double AsyncKeyframes::hold() {
  Stopwatch sw;
  std::unique_lock lock(mutex_);
  held_ = true;
  // Slices: parked_ outside runSlice(). Time pacing: a worker waiting for its
  // budget is at a boundary too, and its pieces end with glFinish.
  doneCv_.wait(lock, [&] { return atBoundary_ || parked_ || idle_ || workerExited_; });
  return sw.ms();
}

void AsyncKeyframes::release() {
  {
    std::lock_guard lock(mutex_);
    held_ = false;
  }
  workCv_.notify_all();
}

double AsyncKeyframes::runSlice() {
  if (!options_.slices || options_.framesPerKeyframe <= 0) return 0.0;
  Stopwatch sw;
  std::unique_lock lock(mutex_);
  if (workerExited_ || (idle_ && queue_.empty())) {
    sliceDebtMs_ = 0;  // nothing to do: no overshoot to pay back
    return 0.0;
  }
  // The share of a frame; a slice ends after the step that uses it up, so
  // what a slice ran over is taken off the next one (the slices average the
  // share instead of share + half a step).
  const double share = std::max(0.5, options_.budgetScale * sharedLastBuildMs_ /
                                         framesPerKeyframe_.load(std::memory_order_relaxed));
  if (sliceDebtMs_ >= share) {
    sliceDebtMs_ -= share;
    return 0.0;
  }
  sliceBudgetMs_ = share - sliceDebtMs_;
  sliceUsedMs_ = 0;
  sliceOpen_ = true;
  workCv_.notify_all();
  doneCv_.wait(lock, [&] {
    return workerExited_ || (idle_ && queue_.empty()) || (parked_ && sliceUsedMs_ >= sliceBudgetMs_);
  });
  sliceOpen_ = false;
  sliceDebtMs_ = parked_ ? std::max(0.0, sliceUsedMs_ - sliceBudgetMs_) : 0.0;
  return sw.ms();
}

void AsyncKeyframes::setFramesPerKeyframe(double frames) {
  if (!(options_.framesPerKeyframe > 0) || !(frames > 0) || !std::isfinite(frames)) return;
  {
    std::lock_guard lock(mutex_);  // a worker between its check and its wait sees it
    framesPerKeyframe_.store(frames, std::memory_order_relaxed);
  }
  workCv_.notify_all();  // a larger budget may let a paced worker go on
}

void AsyncKeyframes::frameTick() {
  {
    std::lock_guard lock(mutex_);
    ++ticks_;
  }
  tickBusyMs_.store(0, std::memory_order_relaxed);
  workCv_.notify_all();
}

void AsyncKeyframes::run(const scenes::Scene* scene, Status* initStatus) {
  if (options_.workerNice != 0)  // best effort: a refused change only costs smoothness
    (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)),
                        options_.workerNice);
  std::unique_ptr<gl::Context> context;
  std::unique_ptr<GeometryRenderer> renderer;
  LodBuilder builder;
  {
    Status s;
    // Current on this thread from here on.
    auto ctx = options_.makeContext ? options_.makeContext() : gl::createSecondHeadlessContext();
    if (!ctx) {
      s = Error{"keyframe worker: " + ctx.error().message};
    } else {
      context = std::move(*ctx);
      auto r = GeometryRenderer::create(*scene, options_.render);
      if (!r) {
        s = Error{"keyframe worker: " + r.error().message};
      } else {
        renderer = std::move(*r);
        if (options_.framesPerKeyframe > 0) {
          renderer->setFlushEvery(options_.flushEveryTriangles, [this] {
            glFinish();  // the piece's rasterisation is part of the step's time
            pace();
          });
        } else {
          renderer->setFlushEvery(options_.flushEveryTriangles, [this] { pace(); });
        }
      }
    }
    std::lock_guard lock(mutex_);
    if (context) glRenderer_ = context->renderer();
    *initStatus = s;
    initDone_ = true;
    if (!s.ok()) workerExited_ = true;
  }
  doneCv_.notify_all();
  if (!renderer) return;

  std::unique_lock lock(mutex_);
  while (true) {
    idle_ = true;
    doneCv_.notify_all();  // an open slice has nothing to run
    workCv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    idle_ = false;
    if (stop_) break;
    const int frame = queue_.front();
    queue_.pop_front();
    building_ = frame;
    std::unique_ptr<CachedKeyframe> e;
    if (!free_.empty()) {
      e = std::move(free_.back());
      free_.pop_back();
    } else {
      e = std::make_unique<CachedKeyframe>();
    }
    lock.unlock();
    buildStepMs_ = 0;
    stepStartMs_ = clock_.ms();  // idle time before is not the build's
    pace();
    const Status s = buildCachedKeyframe(*renderer, builder, options_.mesh, cameraOf_(frame), frame,
                                         *e, [this] { pace(); });
    endStep();
    lastBuildMs_ = buildStepMs_;
    lock.lock();
    sharedLastBuildMs_ = lastBuildMs_;
    building_ = -1;
    busyMs_ += buildStepMs_;
    if (s.ok()) {
      ++built_;
      done_[frame] = std::move(e);
    } else {
      failed_[frame] = s.error();
      free_.push_back(std::move(e));
    }
    doneCv_.notify_all();
  }
  workerExited_ = true;
  lock.unlock();
  doneCv_.notify_all();
  // GL objects go with their context, on this thread.
  renderer.reset();
  context.reset();
}

int AsyncKeyframes::outstandingLocked() const {
  return static_cast<int>(queue_.size() + done_.size()) + (building_ >= 0 ? 1 : 0);
}

bool AsyncKeyframes::knownLocked(int frame) const {
  return building_ == frame || done_.count(frame) || failed_.count(frame) ||
         std::find(queue_.begin(), queue_.end(), frame) != queue_.end();
}

bool AsyncKeyframes::request(int frame) {
  {
    std::lock_guard lock(mutex_);
    if (knownLocked(frame)) return true;
    if (workerExited_ || outstandingLocked() >= options_.maxQueued) return false;
    queue_.push_back(frame);
  }
  workCv_.notify_all();
  return true;
}

bool AsyncKeyframes::ready(int frame, std::size_t* bytes) const {
  std::lock_guard lock(mutex_);
  auto it = done_.find(frame);
  if (it == done_.end()) return false;
  if (bytes) *bytes = cachedKeyframeBytes(*it->second);
  return true;
}

bool AsyncKeyframes::finished(int frame) const {
  std::lock_guard lock(mutex_);
  return done_.count(frame) > 0 || failed_.count(frame) > 0 || workerExited_;
}

Status AsyncKeyframes::take(int frame, std::unique_ptr<CachedKeyframe>* out, double* waitedMs) {
  Stopwatch sw;
  bool waited = false;
  std::unique_lock lock(mutex_);
  if (!knownLocked(frame)) {
    // Needed now and never requested: ahead of everything queued.
    queue_.push_front(frame);
    workCv_.notify_all();
  }
  auto finished = [&] { return done_.count(frame) || failed_.count(frame) || workerExited_; };
  if (!finished()) {
    waited = true;
    ++waiting_;  // lifts pacing
    workCv_.notify_all();
    doneCv_.wait(lock, finished);
    --waiting_;
  }
  if (waitedMs) *waitedMs = waited ? sw.ms() : 0.0;
  if (auto f = failed_.find(frame); f != failed_.end()) {
    Error e = f->second;
    failed_.erase(f);
    return e;
  }
  auto d = done_.find(frame);
  if (d == done_.end())
    return makeError("keyframe worker stopped before keyframe " + std::to_string(frame));
  *out = std::move(d->second);
  done_.erase(d);
  return {};
}

void AsyncKeyframes::recycle(std::unique_ptr<CachedKeyframe> entry) {
  if (!entry) return;
  std::lock_guard lock(mutex_);
  if (free_.size() < 4) free_.push_back(std::move(entry));
}

int AsyncKeyframes::built() const {
  std::lock_guard lock(mutex_);
  return built_;
}

double AsyncKeyframes::workerBusyMs() const {
  std::lock_guard lock(mutex_);
  return busyMs_;
}

}  // namespace hw::keyframe
