// Keyframes around a free camera (the synchronous viewer's policy) and the
// shared in-between step.
#include "session/free_frames.h"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <string>
#include <utility>

#include "core/gl/context.h"
#include "core/short_number.h"
#include "core/timer.h"

namespace hw::session {
namespace {

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
}

bool sameView(const Camera& a, const Camera& b) {
  return a.eye == b.eye && a.forward == b.forward && a.up == b.up && a.width == b.width &&
         a.height == b.height && a.fovYRadians == b.fovYRadians;
}

}  // namespace

FreeFrames::FreeFrames(const WalkOptions& options, const FreeKeyframeOptions& keyframes)
    : opt_(options), kopt_(keyframes) {}

FreeFrames::~FreeFrames() = default;

Result<std::unique_ptr<FreeFrames>> FreeFrames::create(const scenes::Scene& scene,
                                                       const WalkOptions& options,
                                                       const FreeKeyframeOptions& keyframes,
                                                       bool writeEyeZ) {
  if (!(keyframes.distance > 0) || !std::isfinite(keyframes.distance))
    return makeError("keyframe distance: expected a finite number > 0 (scene units), got " +
                     shortNumber(keyframes.distance));
  if (!(keyframes.angleDeg > 0) || !std::isfinite(keyframes.angleDeg))
    return makeError("keyframe angle: expected a finite number > 0 (degrees), got " +
                     shortNumber(keyframes.angleDeg));
  std::unique_ptr<FreeFrames> f(new FreeFrames(options, keyframes));
  HW_TRY(f->setUp(scene, writeEyeZ));
  return f;
}

Status FreeFrames::setUp(const scenes::Scene& scene, bool writeEyeZ) {
  writeEyeZ_ = writeEyeZ;
  auto engine = FrameEngine::create(scene, opt_, writeEyeZ);
  if (!engine) return engine.error();
  engine_ = std::move(*engine);
  return {};
}

double FreeFrames::poseDistance(const Camera& a, const Camera& b) const {
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  return glm::length(a.eye - b.eye) / kopt_.distance +
         angleBetween(a.forward, b.forward) / (kopt_.angleDeg * kDegToRad);
}

Camera FreeFrames::aheadCamera(const Camera& prev, const Camera& cam, double distance) const {
  const double rate = poseDistance(prev, cam);  // pose units per frame
  if (!(rate > 1e-9)) return cam;
  const double t = distance / rate;  // frames ahead
  const glm::dvec3 eye = cam.eye + (cam.eye - prev.eye) * t;
  // The turn from prev to cam, t times over (Rodrigues' rotation).
  glm::dvec3 forward = cam.forward, up = cam.up;
  const glm::dvec3 axis = glm::cross(prev.forward, cam.forward);
  const double s = glm::length(axis);
  if (s > 1e-12) {
    const glm::dvec3 k = axis / s;
    const double angle = std::min(angleBetween(prev.forward, cam.forward) * t, 1.5);
    auto rotate = [&](const glm::dvec3& v) {
      return v * std::cos(angle) + glm::cross(k, v) * std::sin(angle) +
             k * glm::dot(k, v) * (1 - std::cos(angle));
    };
    forward = glm::normalize(rotate(forward));
    up = glm::normalize(rotate(up));
  }
  if (!std::isfinite(eye.x + eye.y + eye.z) || std::abs(glm::dot(forward, up)) > 0.999) return cam;
  return Camera::lookAt(eye, eye + forward, up, cam.fovYRadians, cam.width, cam.height,
                        cam.nearPlane, cam.farPlane);
}

Status FreeFrames::build(Slot& slot, const Camera& cam, FrameInfo* info) {
  slot.valid = false;
  engine_->release(slot.serial);
  if (!slot.kf) slot.kf = std::make_unique<keyframe::CachedKeyframe>();
  const keyframe::MeshSpec spec{opt_.mesh, opt_.lod, opt_.tileSize};
  HW_TRY(keyframe::buildCachedKeyframe(engine_->renderer(), builder_, spec, cam, 0, *slot.kf));
  warp::WarpStats ws;
  HW_TRY(engine_->upload(serial_ + 1, slot.kf->keyframe, slot.kf->mesh, cam.eye, &ws));
  slot.valid = true;
  slot.serial = ++serial_;
  const auto& ms = slot.kf->mesh.stats;
  ++info->keyframesBuilt;
  info->keyframeRenderMs += slot.kf->renderMs;
  info->lodMs += ms.deltaMs + ms.subdivideMs + ms.cornersMs;
  info->uploadMs += ws.uploadMs;
  return {};
}

Status FreeFrames::draw(const Camera& cam, FrameInfo* info) {
  *info = FrameInfo{};
  Stopwatch total;
  // Keyframes of another size or projection cannot be warped to this one.
  for (Slot& s : slots_)
    if (s.valid &&
        (s.kf->keyframe.camera.width != cam.width || s.kf->keyframe.camera.height != cam.height ||
         s.kf->keyframe.camera.fovYRadians != cam.fovYRadians ||
         s.kf->keyframe.camera.nearPlane != cam.nearPlane ||
         s.kf->keyframe.camera.farPlane != cam.farPlane)) {
      s.valid = false;
      engine_->release(s.serial);
    }
  if (engine_->hasPrevious() && (engine_->previous().colour.width() != cam.width ||
                                 engine_->previous().colour.height() != cam.height))
    engine_->forgetPrevious();
  const bool moving = havePrevCam_ && poseDistance(cam, prevCam_) > 1e-9;
  SurveySlot in[2];
  for (int i = 0; i < 2; ++i) {
    const Slot& sl = slots_[static_cast<std::size_t>(i)];
    in[i] = {sl.valid, sl.serial, sl.valid ? poseDistance(sl.kf->keyframe.camera, cam) : 0.0};
  }
  const KeyframeSurvey k = surveyKeyframes(in, moving, newestSerialPrev_, newestSPrev_);
  const int nearest = k.nearest;
  const bool lost = k.lost, wanted = k.wanted;
  if (lost) {
    HW_TRY(build(slots_[static_cast<std::size_t>(nearest < 0 ? 0 : 1 - nearest)], cam, info));
  } else if (wanted) {
    const Camera ahead = aheadCamera(prevCam_, cam, 1.0);
    if (poseDistance(ahead, cam) > kPassedNewest)
      HW_TRY(build(slots_[static_cast<std::size_t>(1 - nearest)], ahead, info));
  }
  int a = -1, b = -1;
  int newest = -1;
  for (int i = 0; i < 2; ++i) {
    const Slot& sl = slots_[static_cast<std::size_t>(i)];
    if (!sl.valid) continue;
    if (newest < 0 || sl.serial > slots_[static_cast<std::size_t>(newest)].serial) newest = i;
    if (poseDistance(sl.kf->keyframe.camera, cam) >= kUseless) continue;
    (a < 0 ? a : b) = i;
  }
  HW_CHECK(a >= 0);  // a keyframe at the camera was built if none was near
  if (newest >= 0) {
    newestSPrev_ = poseDistance(slots_[static_cast<std::size_t>(newest)].kf->keyframe.camera, cam);
    newestSerialPrev_ = slots_[static_cast<std::size_t>(newest)].serial;
  }
  // The nearer keyframe in front (the engine's rule); a keyframe at this very
  // view is the frame itself.
  if (b >= 0 && gapfill::chooseForeground(
                    cam.eye, slots_[static_cast<std::size_t>(a)].kf->keyframe.camera.eye,
                    slots_[static_cast<std::size_t>(b)].kf->keyframe.camera.eye) == 1)
    std::swap(a, b);
  const Slot& fg = slots_[static_cast<std::size_t>(a)];
  const Slot* bg = b >= 0 ? &slots_[static_cast<std::size_t>(b)] : nullptr;
  if (sameView(fg.kf->keyframe.camera, cam)) {
    info->keyframe = true;
    info->quads = fg.kf->mesh.stats.quads;
    InBetweenStats ns;
    HW_TRY(engine_->showKeyframe(cam, fg.serial, fg.kf->keyframe, &ns, bg ? bg->serial : -1));
    info->nearMs = std::max(0.0, ns.nearMs);
    if (writeEyeZ_) shownEyeZ_ = fg.kf->keyframe.eyeZ;
  } else {
    HW_TRY(engine_->warp(cam, fg.serial, bg ? bg->serial : -1, info->inBetween, nullptr));
    if (opt_.renderHoles) HW_TRY(engine_->renderHoles(cam, nullptr, &info->holes));
    info->quads = info->inBetween.quads();
    info->nearMs = std::max(0.0, info->inBetween.nearMs);
  }
  engine_->present();
  prevCam_ = cam;
  havePrevCam_ = true;
  gl::drainGlErrors();
  info->totalMs = total.ms();
  return {};
}

}  // namespace hw::session
