#pragma once
// KeyframeCache: keyframes of a camera path and their quad meshes, built once
// on first use and kept while they can still bracket a frame (Zheng et al.
// 1999 §2: every in-between frame uses the two keyframes around it).
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "core/result.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe.h"
#include "keyframe/lod_builder.h"
#include "keyframe/quad_mesh.h"

namespace hw::keyframe {

// Keyframe schedule: every `keyframeEvery`-th frame, plus the last frame so
// that every in-between frame has a keyframe on both sides. A non-empty
// `explicitFrames` (sorted, unique, in [0, frames)) replaces the fixed
// spacing, e.g. an error-driven schedule; frames 0 and frames−1 are always
// keyframes.
struct KeyframeSchedule {
  int frames = 1;
  int keyframeEvery = 1;
  std::vector<int> explicitFrames;
  bool isKeyframe(int frame) const;
  // All keyframes in order.
  std::vector<int> keyframes() const;
  // The keyframes bracketing `frame` (equal when `frame` is a keyframe).
  std::pair<int, int> bracket(int frame) const;
};

// How a keyframe becomes a quad mesh: the paper's Δ²z' subdivision, or one of
// the baselines the sweep compares it with at matched quad count.
enum class MeshMethod {
  Lod,           // binary subdivision with LodOptions (Zheng et al. 1999 §1.2)
  UniformTiles,  // square tiles of tileSize pixels, empty tiles removed (Rail-Track viewer)
  PerPixel,      // one quad per covered pixel (post-rendering warping)
};
const char* meshMethodName(MeshMethod m);  // "lod", "uniform-tiles", "per-pixel"

struct MeshSpec {
  MeshMethod method = MeshMethod::Lod;
  LodOptions lod;
  int tileSize = 8;  // UniformTiles only, pixels
};

struct CachedKeyframe {
  int frame = 0;
  Keyframe keyframe;
  QuadMesh mesh;
  RenderStats render;
  double renderMs = 0;  // geometry draw + readback
};

// Bytes an entry holds: colour, z', eye z, coverage and the quads.
std::size_t cachedKeyframeBytes(const CachedKeyframe& e);

// Bytes a keyframe of `width` x `height` holds before its quads: colour,
// z', eye z and coverage.
std::size_t keyframePixelBytes(int width, int height);
// Whether a keyframe of `camera`'s size for `frame` fits what the run's
// memory budget has left: the refusal names the frame and its size, then
// `note` and what the user can change.
Status checkKeyframeFits(const Camera& camera, int frame, const std::string& note);

// Renders `camera` with `renderer` and meshes it per `spec` into `out`
// (buffers reused when sizes match). The one build path for the synchronous
// cache and the keyframe worker, so both give bit-identical keyframes.
// `betweenSteps`, if set, is called between the render and the mesh build.
Status buildCachedKeyframe(GeometryRenderer& renderer, LodBuilder& builder, const MeshSpec& spec,
                           const Camera& camera, int frame, CachedKeyframe& out,
                           const std::function<void()>& betweenSteps = {});

// Builds keyframes somewhere else (a worker thread, keyframe/gl/async_keyframes.h).
// All calls come from the cache's (main) thread.
class KeyframeProducer {
 public:
  virtual ~KeyframeProducer() = default;
  // Queues `frame` for building, after those queued before. False when the
  // queue is full (try again later); true when queued, building or done.
  virtual bool request(int frame) = 0;
  // Whether `frame` is built (take() would not block); *bytes then gets its
  // cachedKeyframeBytes.
  virtual bool ready(int frame, std::size_t* bytes = nullptr) const = 0;
  // The built keyframe of `frame`, waiting for it if needed (queued first
  // when it was never requested). *waitedMs: time spent waiting (0 when it
  // was ready). A build error comes back here, for the frame that had it.
  virtual Status take(int frame, std::unique_ptr<CachedKeyframe>* out, double* waitedMs) = 0;
  // Gives an evicted entry back so its buffers are reused.
  virtual void recycle(std::unique_ptr<CachedKeyframe> entry) = 0;
};

struct CacheOptions {
  // Bound on the bytes of the cached entries (cachedKeyframeBytes). The two
  // most recently used entries (a bracket) are always kept, so a bound below
  // two keyframes holds two. The run's memory budget (core/memory_budget.h)
  // caps it at what the budget has left when the cache is made; every entry
  // held is charged to the budget, and a keyframe that would pass the budget
  // is refused (its pixel buffers before they are drawn) naming the frame.
  std::size_t maxBytes = std::size_t{256} << 20;
  // Keyframes past the current bracket that prefetch() builds or requests.
  int prefetch = 2;
};

class KeyframeCache {
 public:
  // Where a keyframe comes from when it is not cached: by default the
  // geometry renderer and the mesh builder; a source (e.g. a baked keyframe
  // database) fills `out` (frame, keyframe, mesh, render stats) instead.
  using Source = std::function<Status(int frame, CachedKeyframe& out)>;
  void setSource(Source source) { source_ = std::move(source); }
  // Keyframes are taken from `producer` (not owned; outlives the cache's
  // use of it) instead of being built here. A source takes precedence.
  void setProducer(KeyframeProducer* producer) { producer_ = producer; }
  // The schedule prefetch() follows.
  void setSchedule(KeyframeSchedule schedule);
  // `renderer` must outlive the cache.
  KeyframeCache(GeometryRenderer& renderer, MeshSpec mesh, std::function<Camera(int)> cameraOf,
                CacheOptions options = {});
  ~KeyframeCache();
  // The keyframe of `frame`, built (or taken from the producer) if not
  // cached. *built tells whether it was. The pointer stays valid until a
  // later get() or prefetch() evicts it; the two most recent get()s are
  // never evicted by the next one.
  Result<const CachedKeyframe*> get(int frame, bool* built = nullptr);
  // Ahead of need along the schedule (setSchedule first): the bracket of
  // `frame` and the next CacheOptions::prefetch keyframes. With a producer
  // they are requested and finished ones moved into the cache (never
  // blocks); without one they are built here, now (for idle time).
  Status prefetch(int frame);
  // Drops the entries of keyframes before `frame` (a walk moving forward
  // calls it with its bracket's first keyframe: no later frame can use them),
  // so the cache holds what can still bracket a frame, not `maxBytes` of the
  // past. Their buffers are reused for later builds. When it dropped an
  // entry it also returns the heap's free pages to the kernel
  // (core/memory.h returnFreeHeapPages).
  void releaseBefore(int frame);

  std::size_t builds() const { return builds_; }        // entries built or taken
  std::size_t bytes() const { return bytes_; }          // held now
  std::size_t peakBytes() const { return peakBytes_; }  // most held after any call
  std::size_t evictions() const { return evictions_; }  // by the byte bound
  std::size_t released() const { return released_; }    // by releaseBefore
  std::size_t entries() const { return entries_.size(); }
  bool contains(int frame) const;
  int stalls() const { return stalls_; }             // get()s that waited for the producer
  double stallMs() const { return stallMs_; }        // total time they waited
  double lastWaitMs() const { return lastWaitMs_; }  // of the last get() (0 if none)
  const CacheOptions& options() const { return options_; }
  // The bound in force: options().maxBytes, or less when the memory budget
  // capped it (cappedByBudget()).
  std::size_t boundBytes() const { return bound_; }
  bool cappedByBudget() const { return bound_ < options_.maxBytes; }
  // Whether a keyframe of `frame` fits what the memory budget has left, as
  // get() would refuse it (nothing is evicted or charged).
  Status checkFits(int frame) const;

 private:
  Status insert(std::unique_ptr<CachedKeyframe> e);
  // Refuses a keyframe of `frame` whose pixel buffers alone would pass the
  // budget, before it is drawn; makes room within the bound for it first.
  Status admit(int frame);
  std::string budgetNote() const;
  void remove(std::size_t i);
  void evict(const std::vector<int>& keep, std::size_t incoming = 0);
  std::unique_ptr<CachedKeyframe> freshEntry();

  GeometryRenderer& renderer_;
  MeshSpec mesh_;
  std::function<Camera(int)> cameraOf_;
  CacheOptions options_;
  LodBuilder builder_;
  std::vector<std::unique_ptr<CachedKeyframe>> entries_;  // most recently used last
  std::unique_ptr<CachedKeyframe> spare_;                 // evicted, buffers reused
  std::vector<std::size_t> entryBytes_;                   // parallel to entries_
  std::size_t bound_ = 0;                                 // maxBytes capped by the memory budget
  std::size_t builds_ = 0, bytes_ = 0, peakBytes_ = 0, evictions_ = 0, released_ = 0,
              largestEntry_ = 0;
  int stalls_ = 0;
  double stallMs_ = 0, lastWaitMs_ = 0;
  Source source_;
  KeyframeProducer* producer_ = nullptr;
  KeyframeSchedule schedule_;
  std::vector<int> scheduleKeyframes_;
  std::vector<int> wanted_;  // scratch: prefetch's list
};

}  // namespace hw::keyframe
