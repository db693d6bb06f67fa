#include "session/frame_engine.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

#include "core/check.h"
#include "core/gl/gl_api.h"
#include "core/memory_budget.h"
#include "core/timer.h"
#include "keyframe/analytic_scene.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/lod_builder.h"

namespace hw::session {

keyframe::KeyframeSchedule pathSchedule(int frames, int keyframeEvery,
                                        const std::vector<int>& keyframeFrames) {
  keyframe::KeyframeSchedule schedule{frames, keyframeEvery, {}};
  for (int k : keyframeFrames)
    if (k > 0 && k < frames - 1) schedule.explicitFrames.push_back(k);
  auto& ex = schedule.explicitFrames;
  std::sort(ex.begin(), ex.end());
  ex.erase(std::unique(ex.begin(), ex.end()), ex.end());
  if (!keyframeFrames.empty() && ex.empty()) ex.push_back(frames - 1);  // only the two ends
  return schedule;
}

FrameEngine::FrameEngine(const WalkOptions& options)
    : step_(options.inBetween), depthMode_(options.depthMode), holeTiling_(holeTiling(options)) {}

FrameEngine::~FrameEngine() = default;

Result<std::unique_ptr<FrameEngine>> FrameEngine::create(const scenes::Scene& scene,
                                                         const WalkOptions& options,
                                                         bool writeEyeZ, bool markLargeQuads) {
  std::unique_ptr<FrameEngine> e(new FrameEngine(options));
  keyframe::RenderOptions ropt;
  ropt.depthMode = options.depthMode;
  ropt.keyframeExcludeNear = options.inBetween.nearDistance;
  ropt.simplifiedRects = options.renderHoles && options.simplifyHoles;
  auto renderer = keyframe::GeometryRenderer::create(scene, ropt);
  if (!renderer) return renderer.error();
  e->renderer_ = std::move(*renderer);
  e->wopt_ = options.warp;
  e->wopt_.writeEyeZ = options.inBetween.needsEyeZ() || writeEyeZ;
  e->wopt_.markLargeQuads = e->wopt_.markLargeQuads && markLargeQuads;
  HW_TRY(e->createWarper(options.warper, options.warperThreads));
  return e;
}

Status FrameEngine::createWarper(warp::WarperChoice choice, int cpuThreads) {
  const std::string unsupported = warp::cpuWarperUnsupported(wopt_);
  const char* rendererName = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const bool software = rendererName && warp::isSoftwareRasteriser(rendererName);
  if (choice == warp::WarperChoice::Cpu && !unsupported.empty())
    return makeError("--warper cpu: the CPU warper does not support " + unsupported +
                     "; use --warper gl or auto");
  cpuWarper_ = choice == warp::WarperChoice::Cpu ||
               (choice == warp::WarperChoice::Auto && software && unsupported.empty());
  auto warper = cpuWarper_ ? warp::createCpuWarper(wopt_, cpuThreads)
                           : warp::Warper::create(wopt_);
  if (!warper) return warper.error();
  warper_ = std::move(*warper);
  return {};
}

void FrameEngine::present() {
  std::swap(previous_, frame_);
  if (gpu_) gpu_->swap();
  havePrevious_ = true;
}

bool FrameEngine::keepFramesOnGpu(bool on) {
  const InBetweenOptions& o = step_.options();
  if (on && (cpuWarper_ || !o.fused() || o.reprojects() || o.nearDistance > 0)) return false;
  if (on && !gpu_) gpu_ = std::make_unique<gapfill::GpuFrames>();
  if (!on) gpu_.reset();
  havePrevious_ = false;
  return true;
}

void FrameEngine::readFrame(Image<Rgba8>& out) {
  if (gpu_ && gpu_->width() == frame_.colour.width() && gpu_->height() == frame_.colour.height())
    gpu_->readColour(out);
  else
    out = frame_.colour;
}

Status FrameEngine::showImage(const Image<Rgba8>& colour) {
  session::showKeyframe(colour, frame_);
  if (gpu_) {
    HW_TRY(gpu_->resize(colour.width(), colour.height()));
    HW_TRY(gpu_->upload(colour));
  }
  return {};
}

Status FrameEngine::upload(int id, const keyframe::Keyframe& keyframe,
                           const keyframe::QuadMesh& mesh, const glm::dvec3& nearEye,
                           warp::WarpStats* stats) {
  auto src = warper_->upload(keyframe, mesh, stats);
  if (!src) return src.error();
  Entry& e = keyframes_[id];
  e.source = std::move(*src);
  e.keyframeEye = keyframe.camera.eye;
  e.nearEye = nearEye;
  return {};
}

const FrameEngine::Entry& FrameEngine::entry(int id) const {
  auto it = keyframes_.find(id);
  HW_CHECK(it != keyframes_.end());
  return it->second;
}

const warp::WarpSource& FrameEngine::source(int id) const { return *entry(id).source; }

void FrameEngine::releaseBefore(int id) {
  for (auto it = keyframes_.begin(); it != keyframes_.end();)
    it = it->first < id ? keyframes_.erase(it) : std::next(it);
}

Status FrameEngine::showKeyframe(const Camera& cam, int id, const keyframe::Keyframe& keyframe,
                                 InBetweenStats* stats, int alsoNear) {
  HW_TRY(showImage(keyframe.colour));
  if (step_.options().reprojects()) setKeyframeDepth(keyframe, frame_);
  if (step_.options().nearDistance > 0) {
    NearGeometry near;
    near.renderer = renderer_.get();
    near.eyes[0] = entry(id).nearEye;
    near.eyeCount = 1;
    if (alsoNear >= 0) near.eyes[near.eyeCount++] = entry(alsoNear).nearEye;
    HW_TRY(step_.drawNear(near, cam, keyframe.eyeZ, frame_, *stats));
  }
  return {};
}

Status FrameEngine::warp(const Camera& cam, int a, int b, InBetweenStats& stats,
                         int* foreground) {
  const Entry& ea = entry(a);
  const Entry* eb = b >= 0 ? &entry(b) : nullptr;
  NearGeometry near;
  near.renderer = renderer_.get();
  near.eyes[0] = ea.nearEye;
  near.eyeCount = 1;
  if (eb) near.eyes[near.eyeCount++] = eb->nearEye;
  const bool bFront = eb && gapfill::chooseForeground(cam.eye, ea.keyframeEye, eb->keyframeEye) == 1;
  const Entry& fg = bFront ? *eb : ea;
  const Entry* bg = bFront ? &ea : eb;
  if (foreground) *foreground = bFront ? b : a;
  if (gpu_) return warpOnGpu(cam, *fg.source, bg ? bg->source.get() : nullptr, stats);
  return step_.draw(*warper_, *fg.source, bg ? bg->source.get() : nullptr, cam,
                    havePrevious_ ? &previous_ : nullptr, &near, frame_, stats);
}

Status FrameEngine::warpOnGpu(const Camera& cam, const warp::WarpSource& fg,
                             const warp::WarpSource* bg, InBetweenStats& st) {
  st = InBetweenStats{};
  // A previous frame of another size is none (the CPU path requires the
  // caller to forget it).
  const bool previous =
      havePrevious_ && gpu_->width() == cam.width && gpu_->height() == cam.height;
  HW_TRY(gpu_->resize(cam.width, cam.height));
  warp::PairStats ps;
  HW_TRY(warper_->warpPairOnGpu(fg, bg, cam, step_.options().skipBackground, &ps));
  setPairStats(ps, st);
  Stopwatch sc;
  HW_TRY(gpu_->compose(warper_->pairTexture(), previous));
  glFinish();
  st.composeMs = sc.lap();
  gpu_->readMasks(frame_);
  st.readbackMs = sc.ms();  // the masks only
  return {};
}

Status FrameEngine::drawGeometry(const Camera& cam, keyframe::RenderStats* stats) {
  if (gpu_) {
    HW_TRY(gpu_->resize(cam.width, cam.height));
    HW_TRY(renderer_->renderColourTo(cam, gpu_->copyTarget(), stats));
    gpu_->markAllDrawn();
    if (frame_.colour.width() != cam.width || frame_.colour.height() != cam.height)
      frame_.colour.resize(cam.width, cam.height);
    session::showKeyframe(frame_.colour, frame_);  // the masks: no holes
    return {};
  }
  HW_TRY(renderer_->renderColour(cam, frame_.colour, stats));
  session::showKeyframe(frame_.colour, frame_);
  if (step_.options().reprojects()) {  // no depth read back: the next fill copies instead
    frame_.eyeZ.resize(frame_.colour.width(), frame_.colour.height(), 0.0f);
    frame_.camera = cam;
  }
  return {};
}

Status FrameEngine::renderHoles(const Camera& cam, const HoleBudget* budget, HolePassResult* out,
                                double* budgetMsOut) {
  double budgetMs = std::nan("");
  std::function<int(int)> maxRects;
  if (budget && budget->rects >= 0) {
    maxRects = [n = budget->rects](int wanted) { return std::min(n, wanted); };
  } else if (budget && budget->fraction > 0 && budget->geometryMs > 0) {
    budgetMs = std::min(budget->fraction * budget->geometryMs,
                        budget->geometryMs - budget->frameMsSoFar);
    maxRects = [&](int wanted) { return holeCost_.maxRects(budgetMs, wanted); };
  }
  HW_TRY(holePass_.run(*renderer_, cam, frame_, step_, holeTiling_, maxRects, out, gpu_.get()));
  if (out->drawn > 0) holeCost_.update(out->drawn, out->drawMs);
  if (budgetMsOut) *budgetMsOut = budgetMs;
  return {};
}

Status FrameEngine::measureFloor(const Camera& cam, int reps, FloorTimes* out) {
  HW_CHECK_GE(reps, 1);
  // Its keyframe is as large as the walk's: charged while it lives.
  const std::uint64_t bytes = keyframe::keyframePixelBytes(cam.width, cam.height);
  HW_TRY(chargeMemory(bytes,
                      "the fill floor's keyframe: " + std::to_string(cam.width) + "x" +
                          std::to_string(cam.height) + " colour and depth",
                      "--max-memory raises the budget, a smaller --width/--height lowers the need"));
  struct Release {
    std::uint64_t bytes;
    ~Release() { releaseMemory(bytes); }
  } release{bytes};
  keyframe::AnalyticScene wall;
  const double d = std::sqrt(cam.nearPlane * cam.farPlane);  // well inside the depth range
  wall.planes.push_back({cam.eye + cam.forward * d, -cam.forward, Rgba8{128, 128, 128, 255}});
  const keyframe::Keyframe kf = keyframe::renderAnalyticKeyframe(wall, cam);
  keyframe::QuadMesh mesh;
  keyframe::LodBuilder builder;
  HW_TRY(builder.build(kf, keyframe::LodOptions{}, &mesh));
  auto src = warper_->upload(kf, mesh, nullptr);
  if (!src) return src.error();
  InBetweenOptions both = step_.options();
  both.skipBackground = false;
  both.nearDistance = 0;
  InBetweenStep step(both);
  InBetweenStats st;
  gapfill::Frame frame;  // not the engine's: the frames drawn stay as they were
  std::vector<double> one, two;
  for (int rep = 0; rep <= reps; ++rep) {
    Stopwatch sw;
    HW_TRY(step.draw(*warper_, **src, nullptr, cam, nullptr, nullptr, frame, st));
    if (rep > 0) one.push_back(sw.ms());
    sw.restart();
    HW_TRY(step.draw(*warper_, **src, src->get(), cam, nullptr, nullptr, frame, st));
    if (rep > 0) two.push_back(sw.ms());
  }
  out->oneLayerMs = median(one);
  out->twoLayersMs = median(two);
  out->reps = reps;
  return {};
}

}  // namespace hw::session
