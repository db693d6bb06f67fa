#pragma once
// KeyframeCache: keyframes of a camera path and their quad meshes, built once
// on first use and kept while they can still bracket a frame (Zheng et al.
// 1999 §2: every in-between frame uses the two keyframes around it).
#include <functional>
#include <memory>
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

class KeyframeCache {
 public:
  // Where a keyframe comes from when it is not cached: by default the
  // geometry renderer and the mesh builder; a source (e.g. a baked keyframe
  // database) fills `out` (frame, keyframe, mesh, render stats) instead.
  using Source = std::function<Status(int frame, CachedKeyframe& out)>;
  void setSource(Source source) { source_ = std::move(source); }
  // `renderer` must outlive the cache. capacity ≥ 2.
  KeyframeCache(GeometryRenderer& renderer, MeshSpec mesh, std::function<Camera(int)> cameraOf,
                std::size_t capacity = 3);
  // The keyframe of `frame`, built if not cached. *built tells whether it was.
  Result<const CachedKeyframe*> get(int frame, bool* built = nullptr);
  std::size_t builds() const { return builds_; }

 private:
  GeometryRenderer& renderer_;
  MeshSpec mesh_;
  std::function<Camera(int)> cameraOf_;
  std::size_t capacity_;
  LodBuilder builder_;
  std::vector<std::unique_ptr<CachedKeyframe>> entries_;  // most recently used last
  std::size_t builds_ = 0;
  Source source_;
};

}  // namespace hw::keyframe
