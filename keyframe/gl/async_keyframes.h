#pragma once
// Keyframes rendered and meshed ahead of need on a worker thread with its own
// OSMesa context, GeometryRenderer and LodBuilder, so an in-between frame does
// not wait for one ("stable frame rate"; Rail-Track's prefetch along
// the path). The main thread only uploads what the worker hands over: no GL
// object crosses contexts. Same build code as KeyframeCache's synchronous path
// (buildCachedKeyframe), hence bit-identical keyframes.
//
// Mesa note (measured on Mesa 22.3 llvmpipe): every OSMesa context of a process
// shares one pipe screen, so LP_NUM_THREADS is read once, at the first context,
// and the worker's context adds no rasteriser threads; both contexts queue
// their rasterisation on the same threads, in order.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/camera.h"
#include "core/gl/context.h"
#include "core/result.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "scenes/scene.h"

namespace hw::keyframe {

struct AsyncKeyframeOptions {
  RenderOptions render;  // as the main thread's renderer, for identical keyframes
  // The worker's renderer flushes after about this many triangles (see
  // GeometryRenderer::setFlushEvery; 0 = once per keyframe), so frames on the
  // main context wait behind one piece of a keyframe on llvmpipe's shared
  // rasteriser threads, and pacing can act between pieces.
  std::size_t flushEveryTriangles = 8192;
  MeshSpec mesh;
  // Keyframes requested, being built or built and not yet taken; request()
  // refuses more. ≥ 1.
  int maxQueued = 3;
  // Added to the worker thread's nice value (Linux, per thread; 0 = as the
  // main thread). Only its own CPU work (binning, meshing) is lowered: the
  // rasteriser threads are Mesa's and shared.
  int workerNice = 0;
  // Pacing: the worker takes at most this many steps (a piece of the render,
  // see RenderOptions::flushEveryTriangles; the readback; the mesh build) per
  // frameTick(), so its cost is spread over the frames instead of landing on
  // one or two. Lifted while the main thread waits for a keyframe. 0 = as
  // fast as it can.
  int stepsPerFrame = 0;
  // Time pacing instead (when > 0): the worker's steps may take, per
  // frameTick(), budgetScale × (its last keyframe's build time) /
  // framesPerKeyframe ms of wall time, each render piece finished (glFinish)
  // so its rasterisation counts; a step that runs over is paid back by
  // waiting the next frames. Spreads a keyframe evenly over the frames that
  // precede its need. Lifted while the main thread waits.
  double framesPerKeyframe = 0;
  double budgetScale = 2.0;
  // Slices (with framesPerKeyframe > 0): the worker runs only inside
  // runSlice(), which the main thread calls between frames and which returns
  // once the worker has used the slice (the same budget as time pacing) or
  // has nothing to do. The two never share the CPUs or llvmpipe's rasteriser
  // queue, so a frame's time is its own work plus an even slice of keyframe
  // work instead of its work slowed by an unknown share of a keyframe's.
  // Lifted while the main thread waits for a keyframe, as the others.
  bool slices = false;
  // Makes the worker's GL context: called on the worker thread, returns a
  // context current on that thread, which the worker destroys there when it
  // exits. Empty: a second OSMesa context (gl::createSecondHeadlessContext;
  // the main thread's entry-point table must then come from OSMesa). With a
  // GLFW window as the main context: a hidden window made on the main thread
  // (gl::createSecondWindowContext) and attached here (gl::attachWindowContext).
  std::function<Result<std::unique_ptr<gl::Context>>()> makeContext;
};

class AsyncKeyframes final : public KeyframeProducer {
 public:
  // Starts the worker and waits until its context and renderer are up, so a
  // context or scene-upload failure comes back here. `scene` is only read
  // during create(); `cameraOf` is called on the worker thread (it must be
  // safe to call concurrently with the main thread, e.g. CameraPath::cameraAt)
  // and what it refers to must outlive this object. The worker's context
  // comes from AsyncKeyframeOptions::makeContext (default: OSMesa, which
  // needs the main thread's GL entry-point table to come from OSMesa too).
  static Result<std::unique_ptr<AsyncKeyframes>> create(const scenes::Scene& scene,
                                                        std::function<Camera(int)> cameraOf,
                                                        const AsyncKeyframeOptions& options);
  // Drops the queue, lets the keyframe in progress finish, joins the worker.
  ~AsyncKeyframes() override;
  AsyncKeyframes(const AsyncKeyframes&) = delete;
  AsyncKeyframes& operator=(const AsyncKeyframes&) = delete;

  bool request(int frame) override;
  bool ready(int frame, std::size_t* bytes = nullptr) const override;
  // Built or failed: take() returns at once (the keyframe or its build
  // error). A caller that polls instead of waiting must use this, not
  // ready(), or a failed build stays pending forever.
  bool finished(int frame) const;
  Status take(int frame, std::unique_ptr<CachedKeyframe>* out, double* waitedMs) override;
  void recycle(std::unique_ptr<CachedKeyframe> entry) override;

  // The main thread started a frame (pacing; see stepsPerFrame).
  void frameTick();
  // Time pacing and slices: spread a keyframe over this many frames from now
  // on instead of AsyncKeyframeOptions::framesPerKeyframe (> 0; any thread),
  // e.g. the viewer's measured keyframe interval. Ignored when the worker
  // was created without framesPerKeyframe (no time pacing) or frames <= 0.
  void setFramesPerKeyframe(double frames);
  double framesPerKeyframe() const { return framesPerKeyframe_.load(std::memory_order_relaxed); }
  // Wall ms of the worker's steps (render pieces, readback, mesh-build steps)
  // that ended since the last frameTick(): the keyframe work that ran beside
  // (or, with slices, inside) the current frame. A step still running is not
  // counted until it ends.
  double workerMsSinceTick() const { return tickBusyMs_.load(std::memory_order_relaxed); }
  // Main thread, with AsyncKeyframeOptions::slices, between frames: lets the
  // worker run one slice and waits for it. Returns the ms waited (0 without
  // slices, or when the worker has nothing to do).
  double runSlice();
  // Main thread: the worker stops at its next step boundary (its GL work
  // finished) and stays there until release(), so what the main thread
  // measures meanwhile (a reference render) shares neither the CPUs nor
  // llvmpipe's rasteriser queue with keyframe work. Returns the ms waited for
  // the step in progress. A take() that has to wait lifts the hold.
  double hold();
  void release();

  int built() const;            // keyframes the worker finished
  double workerBusyMs() const;  // time it spent building them (pacing waits excluded)
  const std::string& glRenderer() const { return glRenderer_; }

 private:
  AsyncKeyframes() = default;
  void run(const scenes::Scene* scene, Status* initStatus);
  int outstandingLocked() const;
  void pace();     // worker: wait for a step of the budget
  void endStep();  // worker: account the step that just ended
  // worker, under mutex_: waits until ready() and not held (see hold()),
  // marked as stopped at a step boundary meanwhile.
  void boundaryWait(std::unique_lock<std::mutex>& lock, const std::function<bool()>& ready);
  bool knownLocked(int frame) const;

  std::function<Camera(int)> cameraOf_;
  AsyncKeyframeOptions options_;
  std::string glRenderer_;

  mutable std::mutex mutex_;
  std::condition_variable workCv_;  // worker: a job or stop
  std::condition_variable doneCv_;  // main: a keyframe finished (or init done)
  std::deque<int> queue_;           // requested, not started, in order
  int building_ = -1;
  std::map<int, std::unique_ptr<CachedKeyframe>> done_;
  std::map<int, Error> failed_;
  std::vector<std::unique_ptr<CachedKeyframe>> free_;  // recycled buffers
  bool stop_ = false, initDone_ = false, workerExited_ = false;
  int waiting_ = 0;                  // main thread blocked in take()
  long long ticks_ = 0, steps_ = 0;  // pacing
  // Time pacing (worker thread only, except ticks_): ms of steps run in the
  // current frame window minus budgets granted, and the last build's cost.
  double debtMs_ = 0, lastBuildMs_ = 0, stepStartMs_ = 0, buildStepMs_ = 0;
  long long paidTicks_ = 0;
  // Slices (under mutex_): a slice is open, its budget and what the worker
  // used of it, the worker is parked in pace() / waiting for a job, and the
  // last build's cost as the main thread may read it.
  bool sliceOpen_ = false, parked_ = false, idle_ = false;
  // hold() requested; the worker waits at a step boundary (boundaryWait).
  bool held_ = false, atBoundary_ = false;
  double sliceBudgetMs_ = 0, sliceUsedMs_ = 0, lastStepMs_ = 0, sharedLastBuildMs_ = 0;
  double sliceDebtMs_ = 0;  // what the last slice ran over its budget
  Stopwatch clock_;
  std::atomic<double> tickBusyMs_{0};         // see workerMsSinceTick()
  std::atomic<double> framesPerKeyframe_{0};  // see setFramesPerKeyframe()
  int built_ = 0;
  double busyMs_ = 0;
  std::thread thread_;
};

}  // namespace hw::keyframe
