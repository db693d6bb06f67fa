// The walk's frame loop (session/walk.cpp WalkLoop) for the synchronous,
// unbudgeted case, one frame per call: the same calls in the same order.
#include "session/path_frames.h"

#include <algorithm>
#include <string>
#include <utility>

#include "core/gl/context.h"
#include "core/timer.h"

namespace hw::session {

PathFrames::PathFrames(std::vector<Camera> cameras, const WalkOptions& options)
    : cams_(std::move(cameras)), opt_(options), step_(options.inBetween) {}

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

// WalkLoop::setUp, setUpSchedule, setUpKeyframes and warmUp without their
// output, async and budget parts.
Status PathFrames::setUp(const scenes::Scene& scene, int keyframeEvery, bool writeEyeZ) {
  writeEyeZ_ = writeEyeZ;
  keyframe::RenderOptions ropt;
  ropt.depthMode = opt_.depthMode;
  ropt.keyframeExcludeNear = opt_.inBetween.nearDistance;
  auto rendererR = keyframe::GeometryRenderer::create(scene, ropt);
  if (!rendererR) return rendererR.error();
  renderer_ = std::move(*rendererR);
  warp::WarpOptions wopt = opt_.warp;
  wopt.writeEyeZ = opt_.inBetween.needsEyeZ() || writeEyeZ;
  auto warperR = warp::Warper::create(wopt);
  if (!warperR) return warperR.error();
  warper_ = std::move(*warperR);

  const int frames = this->frames();
  schedule_ = keyframe::KeyframeSchedule{frames, keyframeEvery, {}};
  for (int k : opt_.keyframeFrames)
    if (k > 0 && k < frames - 1) schedule_.explicitFrames.push_back(k);
  auto& ex = schedule_.explicitFrames;
  std::sort(ex.begin(), ex.end());
  ex.erase(std::unique(ex.begin(), ex.end()), ex.end());
  if (!opt_.keyframeFrames.empty() && ex.empty()) ex.push_back(frames - 1);

  const keyframe::MeshSpec meshSpec{opt_.mesh, opt_.lod, opt_.tileSize};
  auto cameraOf = [this](int i) { return cams_[static_cast<std::size_t>(i)]; };
  cache_ = std::make_unique<keyframe::KeyframeCache>(
      *renderer_, meshSpec, cameraOf,
      keyframe::CacheOptions{opt_.keyframeCacheBytes, std::max(0, opt_.keyframePrefetch)});
  cache_->setSchedule(schedule_);
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
  if (sources_.count(k)) return {};
  warp::WarpStats ws;
  auto src = warper_->upload((*kf)->keyframe, (*kf)->mesh, &ws);
  if (!src) return src.error();
  sources_[k] = std::move(*src);
  const auto& ms = (*kf)->mesh.stats;
  ++info->keyframesBuilt;
  info->uploadMs += ws.uploadMs;
  if (built) {  // built now, not during the warm-up or an earlier frame
    info->keyframeRenderMs += (*kf)->renderMs;
    info->lodMs += ms.deltaMs + ms.subdivideMs + ms.cornersMs;
  }
  return {};
}

NearGeometry PathFrames::nearGeometry(int k0, int k1) const {
  NearGeometry near;
  near.renderer = renderer_.get();
  near.eyes[0] = cams_[static_cast<std::size_t>(k0)].eye;
  near.eyes[1] = cams_[static_cast<std::size_t>(k1)].eye;
  near.eyeCount = k0 == k1 ? 1 : 2;
  return near;
}

Status PathFrames::keyframeFrame(int i, int k0, FrameInfo* info) {
  const Camera& cam = cams_[static_cast<std::size_t>(i)];
  const keyframe::CachedKeyframe* kf = nullptr;
  HW_TRY(getSource(k0, &kf, info));
  info->keyframe = true;
  info->quads = kf->mesh.stats.quads;
  showKeyframe(kf->keyframe.colour, frame_);
  if (writeEyeZ_) shownEyeZ_ = kf->keyframe.eyeZ;
  if (opt_.inBetween.nearDistance > 0) {
    InBetweenStats ns;
    HW_TRY(step_.drawNear(nearGeometry(k0, k0), cam, kf->keyframe.eyeZ, frame_, ns));
    info->nearMs = ns.nearMs;
  }
  // As the walk: the next keyframe uploaded now if already built (no
  // warm-up draw from it: that made the frames around it slower).
  if (i + 1 < frames()) {
    const int nextK = schedule_.bracket(i + 1).second;
    if (nextK != k0 && !sources_.count(nextK) && cache_->contains(nextK)) {
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
  const int fgPick =
      gapfill::chooseForeground(cam.eye, kfa->keyframe.camera.eye, kfb->keyframe.camera.eye);
  const int fgFrame = fgPick == 0 ? k0 : k1, bgFrame = fgPick == 0 ? k1 : k0;
  const NearGeometry near = nearGeometry(k0, k1);
  HW_TRY(step_.draw(*warper_, *sources_[fgFrame], sources_[bgFrame].get(), cam,
                    havePrevious_ ? &previous_ : nullptr, &near, frame_, info->inBetween));
  if (opt_.renderHoles) HW_TRY(holePass_.run(*renderer_, cam, frame_, step_, {}, &info->holes));
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
  std::swap(previous_, frame_);
  havePrevious_ = true;
  for (auto it = sources_.begin(); it != sources_.end();)
    it = it->first < k0 ? sources_.erase(it) : std::next(it);
  cache_->releaseBefore(k0);
  gl::drainGlErrors();
  ++next_;
  info->totalMs = total.ms();
  return {};
}

}  // namespace hw::session
