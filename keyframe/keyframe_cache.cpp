#include "keyframe/keyframe_cache.h"

#include <algorithm>

#include "core/check.h"
#include "core/memory.h"
#include "core/memory_budget.h"
#include "core/safe_io.h"
#include "core/timer.h"
#include "keyframe/baseline_mesh.h"

namespace hw::keyframe {

bool KeyframeSchedule::isKeyframe(int frame) const {
  if (frame == 0 || frame == frames - 1) return true;
  if (!explicitFrames.empty())
    return std::binary_search(explicitFrames.begin(), explicitFrames.end(), frame);
  return frame % keyframeEvery == 0;
}

std::vector<int> KeyframeSchedule::keyframes() const {
  std::vector<int> k;
  for (int i = 0; i < frames; ++i)
    if (isKeyframe(i)) k.push_back(i);
  return k;
}

std::pair<int, int> KeyframeSchedule::bracket(int frame) const {
  HW_CHECK(frame >= 0 && frame < frames);
  if (isKeyframe(frame)) return {frame, frame};
  if (!explicitFrames.empty()) {
    const auto hi = std::upper_bound(explicitFrames.begin(), explicitFrames.end(), frame);
    const int k1 = hi == explicitFrames.end() ? frames - 1 : *hi;
    const int k0 = hi == explicitFrames.begin() ? 0 : *(hi - 1);
    return {k0, std::min(k1, frames - 1)};
  }
  const int k0 = frame / keyframeEvery * keyframeEvery;
  return {k0, std::min(k0 + keyframeEvery, frames - 1)};
}

const char* meshMethodName(MeshMethod m) {
  switch (m) {
    case MeshMethod::Lod: return "lod";
    case MeshMethod::UniformTiles: return "uniform-tiles";
    case MeshMethod::PerPixel: return "per-pixel";
  }
  return "?";
}

std::size_t cachedKeyframeBytes(const CachedKeyframe& e) {
  const std::size_t px = static_cast<std::size_t>(e.keyframe.colour.width()) *
                         static_cast<std::size_t>(e.keyframe.colour.height());
  const std::size_t zpx = static_cast<std::size_t>(e.keyframe.zPrime.width()) *
                          static_cast<std::size_t>(e.keyframe.zPrime.height());
  const std::size_t ezpx = static_cast<std::size_t>(e.keyframe.eyeZ.width()) *
                           static_cast<std::size_t>(e.keyframe.eyeZ.height());
  const std::size_t cpx = static_cast<std::size_t>(e.keyframe.covered.width()) *
                          static_cast<std::size_t>(e.keyframe.covered.height());
  return sizeof(CachedKeyframe) + px * sizeof(Rgba8) + zpx * sizeof(double) +
         ezpx * sizeof(float) + cpx * sizeof(std::uint8_t) + e.mesh.quads.size() * sizeof(Quad);
}

Status buildCachedKeyframe(GeometryRenderer& renderer, LodBuilder& builder, const MeshSpec& spec,
                           const Camera& camera, int frame, CachedKeyframe& out,
                           const std::function<void()>& betweenSteps) {
  out.frame = frame;
  HW_TRY(renderer.renderKeyframe(camera, out.keyframe, &out.render));
  out.renderMs = out.render.drawMs + out.render.readbackMs;
  if (betweenSteps) betweenSteps();
  switch (spec.method) {
    case MeshMethod::Lod:
      if (!betweenSteps) {
        HW_TRY(builder.build(out.keyframe, spec.lod, &out.mesh));
      } else {
        // build()'s three steps with a pause point between them; the same
        // calls, so the same quads.
        Stopwatch sw;
        out.mesh.quads.clear();
        out.mesh.stats = QuadMeshStats{};
        HW_TRY(builder.prepare(out.keyframe.zPrime.view(), out.keyframe.covered.view(),
                               out.keyframe.camera, spec.lod));
        const double deltaMs = sw.ms();
        betweenSteps();
        const double subdivideMs = builder.subdivide();
        betweenSteps();
        const double cornersMs = builder.recoverCorners(&out.mesh);
        out.mesh.stats.deltaMs = deltaMs;
        out.mesh.stats.subdivideMs = subdivideMs;
        out.mesh.stats.cornersMs = cornersMs;
      }
      break;
    case MeshMethod::UniformTiles: {
      auto m = buildUniformTiles(out.keyframe, spec.tileSize, &builder);
      if (!m) return m.error();
      out.mesh = std::move(*m);
      break;
    }
    case MeshMethod::PerPixel: {
      auto m = buildPerPixel(out.keyframe, &builder);
      if (!m) return m.error();
      out.mesh = std::move(*m);
      break;
    }
  }
  return {};
}

KeyframeCache::KeyframeCache(GeometryRenderer& renderer, MeshSpec mesh,
                             std::function<Camera(int)> cameraOf, CacheOptions options)
    : renderer_(renderer), mesh_(mesh), cameraOf_(std::move(cameraOf)), options_(options) {
  HW_CHECK_GE(options_.prefetch, 0);
  const std::uint64_t budget = memoryBudget(), charged = memoryCharged();
  const std::uint64_t left = budget > charged ? budget - charged : 0;
  bound_ = static_cast<std::size_t>(std::min<std::uint64_t>(options_.maxBytes, left));
}

KeyframeCache::~KeyframeCache() { releaseMemory(bytes_); }

std::string KeyframeCache::budgetNote() const {
  std::string note = entries_.empty()
                         ? "the keyframe cache holds none yet"
                         : "the keyframe cache holds " + std::to_string(entries_.size()) +
                               " keyframe(s), " + formatBytes(bytes_);
  if (cappedByBudget())
    note += "; its bound is capped at " + formatBytes(bound_) +
            " by the memory budget (--keyframe-cache-mb " +
            std::to_string(options_.maxBytes >> 20) + " asked for more)";
  return note;
}

std::size_t keyframePixelBytes(int width, int height) {
  const std::size_t px =
      static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
  return px * (sizeof(Rgba8) + sizeof(double) + sizeof(float) + 1);
}

Status checkKeyframeFits(const Camera& camera, int frame, const std::string& note) {
  return checkMemoryCharge(
      memoryCharged(), keyframePixelBytes(camera.width, camera.height), memoryBudget(),
      "keyframe of frame " + std::to_string(frame) + ": " + std::to_string(camera.width) + "x" +
          std::to_string(camera.height) + " colour and depth",
      note + "; --max-memory raises the budget, a smaller --width/--height lowers the need");
}

Status KeyframeCache::admit(int frame) {
  const Camera c = cameraOf_(frame);
  // Room within the bound first, keeping the two most recent entries (the
  // pointers the caller may still hold).
  std::vector<int> keep;
  for (std::size_t i = entries_.size(); i-- > 0 && keep.size() < 2;)
    keep.push_back(entries_[i]->frame);
  evict(keep, keyframePixelBytes(c.width, c.height));
  return checkKeyframeFits(c, frame, budgetNote());
}

Status KeyframeCache::checkFits(int frame) const {
  return checkKeyframeFits(cameraOf_(frame), frame, budgetNote());
}

void KeyframeCache::setSchedule(KeyframeSchedule schedule) {
  schedule_ = std::move(schedule);
  scheduleKeyframes_ = schedule_.keyframes();
}

bool KeyframeCache::contains(int frame) const {
  for (const auto& e : entries_)
    if (e->frame == frame) return true;
  return false;
}

std::unique_ptr<CachedKeyframe> KeyframeCache::freshEntry() {
  if (spare_) return std::move(spare_);
  return std::make_unique<CachedKeyframe>();
}

Status KeyframeCache::insert(std::unique_ptr<CachedKeyframe> e) {
  const std::size_t b = cachedKeyframeBytes(*e);
  const int frame = e->frame;
  const std::size_t quads = e->mesh.quads.size();
  if (Status ok = chargeMemory(b,
                               "keyframe of frame " + std::to_string(frame) +
                                   ": colour, depth and " + std::to_string(quads) + " quads",
                               budgetNote() + "; --max-memory raises the budget");
      !ok) {
    if (producer_ && !source_)
      producer_->recycle(std::move(e));
    else
      spare_ = std::move(e);
    return ok;
  }
  entries_.push_back(std::move(e));
  entryBytes_.push_back(b);
  bytes_ += b;
  largestEntry_ = std::max(largestEntry_, b);
  return {};
}

// Drops entry i; its buffers go back to the producer or become the spare.
void KeyframeCache::remove(std::size_t i) {
  bytes_ -= entryBytes_[i];
  releaseMemory(entryBytes_[i]);
  std::unique_ptr<CachedKeyframe> gone = std::move(entries_[i]);
  entries_.erase(entries_.begin() + static_cast<std::ptrdiff_t>(i));
  entryBytes_.erase(entryBytes_.begin() + static_cast<std::ptrdiff_t>(i));
  if (producer_ && !source_)
    producer_->recycle(std::move(gone));
  else
    spare_ = std::move(gone);
}

// Least recently used first, skipping `keep`, until `incoming` more bytes fit
// within the bound.
void KeyframeCache::evict(const std::vector<int>& keep, std::size_t incoming) {
  for (std::size_t i = 0; i < entries_.size() && bytes_ + incoming > bound_;) {
    if (std::find(keep.begin(), keep.end(), entries_[i]->frame) != keep.end()) {
      ++i;
      continue;
    }
    remove(i);
    ++evictions_;
  }
}

void KeyframeCache::releaseBefore(int frame) {
  const std::size_t releasedBefore = released_;
  for (std::size_t i = 0; i < entries_.size();) {
    if (entries_[i]->frame >= frame) {
      ++i;
      continue;
    }
    remove(i);
    ++released_;
  }
  // Once per keyframe step, after the keyframe's render and mesh build have
  // freed their temporaries (llvmpipe's bins: MiBs for the largest views)
  // and the walk has dropped the GPU copies of the keyframes released here:
  // without it the heap keeps the high-water mark of the largest keyframe
  // seen (docs/notes/memory.md).
  if (released_ != releasedBefore) returnFreeHeapPages();
}

Result<const CachedKeyframe*> KeyframeCache::get(int frame, bool* built) {
  lastWaitMs_ = 0;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i]->frame != frame) continue;
    std::rotate(entries_.begin() + static_cast<std::ptrdiff_t>(i),
                entries_.begin() + static_cast<std::ptrdiff_t>(i) + 1, entries_.end());
    std::rotate(entryBytes_.begin() + static_cast<std::ptrdiff_t>(i),
                entryBytes_.begin() + static_cast<std::ptrdiff_t>(i) + 1, entryBytes_.end());
    if (built) *built = false;
    return static_cast<const CachedKeyframe*>(entries_.back().get());
  }
  HW_TRY(admit(frame));
  std::unique_ptr<CachedKeyframe> e;
  if (source_) {
    e = freshEntry();
    e->frame = frame;
    HW_TRY(source_(frame, *e));
    e->frame = frame;
  } else if (producer_) {
    double waited = 0;
    HW_TRY(producer_->take(frame, &e, &waited));
    HW_CHECK(e != nullptr);
    HW_CHECK_EQ(e->frame, frame);
    if (waited > 0) {
      ++stalls_;
      stallMs_ += waited;
      lastWaitMs_ = waited;
    }
  } else {
    e = freshEntry();
    HW_TRY(buildCachedKeyframe(renderer_, builder_, mesh_, cameraOf_(frame), frame, *e));
  }
  ++builds_;
  HW_TRY(insert(std::move(e)));
  // Keep this entry and the one used before it (the other end of a bracket).
  std::vector<int> keep{frame};
  if (entries_.size() >= 2) keep.push_back(entries_[entries_.size() - 2]->frame);
  evict(keep);
  peakBytes_ = std::max(peakBytes_, bytes_);
  if (built) *built = true;
  return static_cast<const CachedKeyframe*>(entries_.back().get());
}

Status KeyframeCache::prefetch(int frame) {
  HW_CHECK(!scheduleKeyframes_.empty());
  const auto [k0, k1] = schedule_.bracket(frame);
  wanted_.clear();
  wanted_.push_back(k0);
  if (k1 != k0) wanted_.push_back(k1);
  const std::size_t bracket = wanted_.size();
  auto it = std::upper_bound(scheduleKeyframes_.begin(), scheduleKeyframes_.end(), k1);
  for (int n = 0; n < options_.prefetch && it != scheduleKeyframes_.end(); ++n, ++it)
    wanted_.push_back(*it);
  if (source_) return {};  // a source is synchronous and may not be thread-safe
  auto wantedBytes = [&] {
    std::size_t b = 0;
    for (std::size_t i = 0; i < entries_.size(); ++i)
      if (std::find(wanted_.begin(), wanted_.end(), entries_[i]->frame) != wanted_.end())
        b += entryBytes_[i];
    return b;
  };
  for (std::size_t w = 0; w < wanted_.size(); ++w) {
    const int f = wanted_[w];
    if (contains(f)) continue;
    const bool ahead = w >= bracket;  // the bracket always comes in (get() would take it)
    if (producer_) {
      std::size_t b = 0;
      if (!producer_->ready(f, &b)) {
        if (!producer_->request(f)) break;  // queue full: later
        continue;
      }
      // Finished: moved in if it fits beside the entries still wanted,
      // otherwise it waits in the producer until get() takes it.
      if (ahead && wantedBytes() + b > bound_) continue;
      std::unique_ptr<CachedKeyframe> e;
      double waited = 0;
      HW_TRY(producer_->take(f, &e, &waited));
      ++builds_;
      if (Status in = insert(std::move(e)); !in) {
        if (ahead) break;  // over the budget: get() takes it when it is needed
        return in;
      }
    } else {
      if (ahead && wantedBytes() + largestEntry_ > bound_) break;
      if (Status room = admit(f); !room) {
        if (ahead) break;
        return room;
      }
      std::unique_ptr<CachedKeyframe> e = freshEntry();
      HW_TRY(buildCachedKeyframe(renderer_, builder_, mesh_, cameraOf_(f), f, *e));
      ++builds_;
      if (Status in = insert(std::move(e)); !in) {
        if (ahead) break;
        return in;
      }
      if (ahead && wantedBytes() > bound_) {  // larger than any before: drop it
        bytes_ -= entryBytes_.back();
        releaseMemory(entryBytes_.back());
        entryBytes_.pop_back();
        spare_ = std::move(entries_.back());
        entries_.pop_back();
        ++evictions_;
        break;
      }
    }
    evict(wanted_);
  }
  peakBytes_ = std::max(peakBytes_, bytes_);
  return {};
}

}  // namespace hw::keyframe
