#include "keyframe/keyframe_cache.h"

#include <algorithm>

#include "core/check.h"
#include "keyframe/baseline_mesh.h"
#include "core/timer.h"

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

KeyframeCache::KeyframeCache(GeometryRenderer& renderer, MeshSpec mesh,
                             std::function<Camera(int)> cameraOf, std::size_t capacity)
    : renderer_(renderer), mesh_(mesh), cameraOf_(std::move(cameraOf)), capacity_(capacity) {
  HW_CHECK_GE(capacity_, std::size_t{2});
}

Result<const CachedKeyframe*> KeyframeCache::get(int frame, bool* built) {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i]->frame != frame) continue;
    std::rotate(entries_.begin() + static_cast<std::ptrdiff_t>(i),
                entries_.begin() + static_cast<std::ptrdiff_t>(i) + 1, entries_.end());
    if (built) *built = false;
    return static_cast<const CachedKeyframe*>(entries_.back().get());
  }
  std::unique_ptr<CachedKeyframe> e;
  if (entries_.size() >= capacity_) {  // reuse the least recently used entry's buffers
    e = std::move(entries_.front());
    entries_.erase(entries_.begin());
  } else {
    e = std::make_unique<CachedKeyframe>();
  }
  e->frame = frame;
  if (source_) {
    HW_TRY(source_(frame, *e));
    e->frame = frame;
    ++builds_;
    entries_.push_back(std::move(e));
    if (built) *built = true;
    return static_cast<const CachedKeyframe*>(entries_.back().get());
  }
  HW_TRY(renderer_.renderKeyframe(cameraOf_(frame), e->keyframe, &e->render));
  e->renderMs = e->render.drawMs + e->render.readbackMs;
  switch (mesh_.method) {
    case MeshMethod::Lod:
      HW_TRY(builder_.build(e->keyframe, mesh_.lod, &e->mesh));
      break;
    case MeshMethod::UniformTiles: {
      auto m = buildUniformTiles(e->keyframe, mesh_.tileSize, &builder_);
      if (!m) return m.error();
      e->mesh = std::move(*m);
      break;
    }
    case MeshMethod::PerPixel: {
      auto m = buildPerPixel(e->keyframe, &builder_);
      if (!m) return m.error();
      e->mesh = std::move(*m);
      break;
    }
  }
  ++builds_;
  entries_.push_back(std::move(e));
  if (built) *built = true;
  return static_cast<const CachedKeyframe*>(entries_.back().get());
}

}  // namespace hw::keyframe
