// The path's keyframe schedule and cache driving the frame engine, one frame
// per call, as the walk drives it.
#include "session/path_frames.h"

#include <algorithm>
#include <string>
#include <utility>

#include "core/gl/context.h"
#include "core/timer.h"

namespace hw::session {

PathFrames::PathFrames(std::vector<Camera> cameras, const WalkOptions& options)
    : cams_(std::move(cameras)), opt_(options) {}

PathFrames::~PathFrames() = default;

Result<std::unique_ptr<PathFrames>> PathFrames::create(const scenes::Scene& scene,
                                                       std::vector<Camera> cameras,
                                                       int keyframeEvery,
                                                       const WalkOptions& options, bool writeEyeZ) {
  if (cameras.empty()) return makeError("camera path: expected at least one camera, got none");
  if (keyframeEvery < 1)
    return makeError("camera path: keyframe spacing: expected at least 1 frame, got " +
                     std::to_string(keyframeEvery));
  for (std::size_t i = 1; i < cameras.size(); ++i)
    if (cameras[i].width != cameras[0].width || cameras[i].height != cameras[0].height)
      return makeError("camera path: camera " + std::to_string(i) + " is " +
                       std::to_string(cameras[i].width) + "x" + std::to_string(cameras[i].height) +
                       ", expected the first camera's " + std::to_string(cameras[0].width) + "x" +
                       std::to_string(cameras[0].height));
  std::unique_ptr<PathFrames> p(new PathFrames(std::move(cameras), options));
  HW_TRY(p->setUp(scene, keyframeEvery, writeEyeZ));
  return p;
}

Status PathFrames::setUp(const scenes::Scene& scene, int keyframeEvery, bool writeEyeZ) {
  writeEyeZ_ = writeEyeZ;
  auto engine = FrameEngine::create(scene, opt_, writeEyeZ);
  if (!engine) return engine.error();
  engine_ = std::move(*engine);
  const int frames = this->frames();
  schedule_ = pathSchedule(frames, keyframeEvery, opt_.keyframeFrames);
  const keyframe::MeshSpec meshSpec{opt_.mesh, opt_.lod, opt_.tileSize};
  auto cameraOf = [this](int i) { return cams_[static_cast<std::size_t>(i)]; };
  cache_ = std::make_unique<keyframe::KeyframeCache>(
      engine_->renderer(), meshSpec, cameraOf,
      keyframe::CacheOptions{opt_.keyframeCacheBytes, std::max(0, opt_.keyframePrefetch)});
  cache_->setSchedule(schedule_);
  // The walk's warm-up: the first two keyframes before the first frame.
  for (int k : {schedule_.bracket(0).first, schedule_.bracket(frames > 1 ? 1 : 0).second}) {
    auto kf = cache_->get(k);
    if (!kf) return kf.error();
  }
  return {};
}

Status PathFrames::getSource(int k, const keyframe::CachedKeyframe** kfOut, FrameInfo* info) {
  bool built = false;
  auto kf = cache_->get(k, &built);
  if (!kf) return kf.error();
  *kfOut = *kf;
  if (engine_->has(k)) return {};
  warp::WarpStats ws;
  HW_TRY(engine_->upload(k, (*kf)->keyframe, (*kf)->mesh, cams_[static_cast<std::size_t>(k)].eye,
                         &ws));
  const auto& ms = (*kf)->mesh.stats;
  ++info->keyframesBuilt;
  info->uploadMs += ws.uploadMs;
  if (built) {  // built now, not during the warm-up or an earlier frame
    info->keyframeRenderMs += (*kf)->renderMs;
    info->lodMs += ms.deltaMs + ms.subdivideMs + ms.cornersMs;
  }
  return {};
}

Status PathFrames::keyframeFrame(int i, int k0, FrameInfo* info) {
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  const keyframe::CachedKeyframe* kf = nullptr;
  HW_TRY(getSource(k0, &kf, info));
  info->keyframe = true;
  info->quads = kf->mesh.stats.quads;
  InBetweenStats ns;
  HW_TRY(engine_->showKeyframe(cam, k0, kf->keyframe, &ns));
  info->nearMs = std::max(0.0, ns.nearMs);
  if (writeEyeZ_) shownEyeZ_ = kf->keyframe.eyeZ;
  // As the walk: the next keyframe uploaded now if already built.
  if (i + 1 < frames()) {
    const int nextK = schedule_.bracket(i + 1).second;
    if (nextK != k0 && !engine_->has(nextK) && cache_->contains(nextK)) {
      const keyframe::CachedKeyframe* kn = nullptr;
      HW_TRY(getSource(nextK, &kn, info));
    }
  }
  return {};
}

Status PathFrames::inBetweenFrame(int i, int k0, int k1, FrameInfo* info) {
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  const keyframe::CachedKeyframe* kfa = nullptr;
  const keyframe::CachedKeyframe* kfb = nullptr;
  HW_TRY(getSource(k0, &kfa, info));
  HW_TRY(getSource(k1, &kfb, info));
  HW_TRY(engine_->warp(cam, k0, k1, info->inBetween, nullptr));
  if (opt_.renderHoles) HW_TRY(engine_->renderHoles(cam, nullptr, &info->holes));
  info->quads = info->inBetween.quads();
  info->nearMs = std::max(0.0, info->inBetween.nearMs);
  return {};
}

Status PathFrames::step(FrameInfo* info) {
  if (next_ >= frames())
    return makeError("camera path: all " + std::to_string(frames()) +
                     " frames have been drawn; no frame " + std::to_string(next_));
  *info = FrameInfo{};
  Stopwatch total;
  const int i = next_;
  const auto [k0, k1] = schedule_.bracket(i);
  info->k0 = k0;
  info->k1 = k1;
  if (k0 == k1)
    HW_TRY(keyframeFrame(i, k0, info));
  else
    HW_TRY(inBetweenFrame(i, k0, k1, info));
  engine_->present();
  engine_->releaseBefore(k0);
  cache_->releaseBefore(k0);
  gl::drainGlErrors();
  ++next_;
  info->totalMs = total.ms();
  return {};
}

}  // namespace hw::session
