// The public renderer: option structs mapped onto the walk's options (its
// defaults where the caller left a field at zero / Default), frames from the
// session layer (session/path_frames.h along a path, session/free_frames.h
// at free cameras), copied out with their stats.
#include "hybridwalk/renderer.h"

#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <limits>
#include <string>
#include <utility>

#include "api/gl/glue.h"
#include "api/internal.h"
#include "core/gl/context.h"
#include "core/metrics.h"
#include "core/short_number.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "session/free_frames.h"
#include "session/path_frames.h"
#include "session/presets.h"
#include "session/walk.h"
#include "warp/layer.h"

namespace hybridwalk {

struct Renderer::Impl {
  // Declared first: destroyed last, after every GL object below.
  std::unique_ptr<hw::gl::Context> ownContext;
  std::string glRenderer;
  RendererDesc desc;
  hw::session::WalkOptions walk;
  std::unique_ptr<hw::session::PathFrames> path;
  std::unique_ptr<hw::session::FreeFrames> free;
  std::unique_ptr<hw::keyframe::GeometryRenderer> ownGeometry;  // Mode::Geometry
  hw::keyframe::GeometryRenderer* geometry = nullptr;
  std::unique_ptr<detail::Presenter> presenter;
  hw::Image<hw::Rgba8> colour;
  hw::keyframe::Keyframe keyframe;
  std::vector<float> previousDepth;
  std::vector<hw::Camera> geometryPath;  // Mode::Geometry along a path
  int geometryNext = 0;

  bool followsPath() const { return path || !geometryPath.empty(); }
  int next() const { return path ? path->next() : geometryNext; }
  int frames() const { return path ? path->frames() : static_cast<int>(geometryPath.size()); }

  ~Impl() {
    makeCurrent();
    presenter.reset();
    path.reset();
    free.reset();
    ownGeometry.reset();
  }
  void makeCurrent() {
    if (ownContext) ownContext->makeCurrent();
  }
};

namespace {

hw::Status mapOptions(const RendererDesc& d, hw::session::WalkOptions& w) {
  auto bad = [](const std::string& what, double v, const char* expected) {
    return hw::makeError("renderer: " + what + ": expected " + expected + ", got " +
                         hw::shortNumber(v));
  };
  const LodDesc& l = d.lod;
  if (!(l.tau >= 0) || !std::isfinite(l.tau)) return bad("lod.tau", l.tau, "a finite number >= 0");
  if (!(l.tauParallaxPx >= 0) || !std::isfinite(l.tauParallaxPx))
    return bad("lod.tauParallaxPx", l.tauParallaxPx, "a finite number >= 0");
  if (l.tau > 0) {
    w.lod.tau = l.tau;
    w.lod.tauParallaxPx = 0;  // an explicit τ replaces the preset's parallax bound
  }
  if (l.tauParallaxPx > 0) w.lod.tauParallaxPx = l.tauParallaxPx;
  if (l.criterion == Criterion::FivePoint)
    w.lod.criterion = hw::keyframe::DeltaCriterion::FivePoint;
  if (l.criterion == Criterion::PerAxisMax)
    w.lod.criterion = hw::keyframe::DeltaCriterion::PerAxisMax;
  if (l.planarity == Planarity::Stencil) w.lod.planarity = hw::keyframe::Planarity::Stencil;
  if (l.planarity == Planarity::RegionLocal) w.lod.planarity = hw::keyframe::Planarity::RegionLocal;
  if (l.mergeStrips != Toggle::Default) w.lod.mergeStrips = l.mergeStrips == Toggle::On;
  if (d.compose == Compose::Overlay) w.inBetween.compose.mode = hw::gapfill::ComposeMode::Overlay;
  if (d.compose == Compose::DepthMerge)
    w.inBetween.compose.mode = hw::gapfill::ComposeMode::DepthMerge;
  switch (d.warper) {
    case Warper::Auto:
      w.warper = hw::warp::WarperChoice::Auto;
      break;
    case Warper::Gl:
      w.warper = hw::warp::WarperChoice::Gl;
      break;
    case Warper::Cpu:
      w.warper = hw::warp::WarperChoice::Cpu;
      break;
  }
  if (!(d.nearDistance >= 0) || !std::isfinite(d.nearDistance))
    return bad("nearDistance", d.nearDistance, "a finite number >= 0 (scene units)");
  if (d.nearDistance > 0) w.inBetween.nearDistance = d.nearDistance;
  switch (d.depthBuffer) {
    case DepthBuffer::Fixed24:
      w.depthMode = hw::DepthMode::Fixed24;
      break;
    case DepthBuffer::Float32:
      w.depthMode = hw::DepthMode::Float32;
      break;
    case DepthBuffer::Float32Reversed:
      w.depthMode = hw::DepthMode::Float32Reversed;
      break;
    case DepthBuffer::Default:
      break;
  }
  const KeyframeDesc& k = d.keyframes;
  if (!(k.distance >= 0) || !std::isfinite(k.distance))
    return bad("keyframes.distance", k.distance, "a finite number >= 0 (scene units)");
  if (!(k.angleDeg >= 0) || !std::isfinite(k.angleDeg))
    return bad("keyframes.angleDeg", k.angleDeg, "a finite number >= 0 (degrees)");
  return {};
}

void copyColour(const hw::Image<hw::Rgba8>& img, Frame& out) {
  out.width = img.width();
  out.height = img.height();
  out.rgba.resize(img.size() * 4);
  // Alpha is 255: the warper keeps bookkeeping in a layer's alpha.
  std::uint8_t* d = out.rgba.data();
  const hw::Rgba8* p = img.data();
  for (std::size_t i = 0; i < img.size(); ++i, d += 4) {
    d[0] = p[i].r;
    d[1] = p[i].g;
    d[2] = p[i].b;
    d[3] = 255;
  }
}

float depthOf(float z) { return z >= hw::warp::kSkyEyeZ ? 0.0f : z; }

// The depth behind each pixel of an in-between frame: the layer that gave
// it (by the composition's rule), else the previous frame's depth where the
// previous frame filled it, else 0.
void inBetweenDepth(hw::session::InBetweenStep& step, const hw::session::InBetweenStats& st,
                    const hw::gapfill::Frame& frame, const hw::session::InBetweenOptions& opt,
                    const std::vector<float>& previous, std::vector<float>& out) {
  const hw::warp::Layer& a = step.layerA();
  const hw::warp::Layer& b = step.layerB();
  const std::size_t n = frame.colour.size();
  out.assign(n, 0.0f);
  const bool haveB = !st.fused && st.backgroundDrawn && b.eyeZ.size() == n;
  const bool merge = opt.compose.mode == hw::gapfill::ComposeMode::DepthMerge;
  for (std::size_t p = 0; p < n; ++p) {
    const bool inA = a.coverage.data()[p] != 0;
    const bool inB = haveB && b.coverage.data()[p] != 0;
    float z = 0;
    if (inA && inB && merge) {
      const float za = a.eyeZ.data()[p], zb = b.eyeZ.data()[p];
      z = zb < (1.0f - opt.compose.depthTolerance) * za ? zb : za;
    } else if (inA) {
      z = a.eyeZ.size() == n ? a.eyeZ.data()[p] : 0.0f;
    } else if (inB) {
      z = b.eyeZ.data()[p];
    } else if (frame.valid.size() == n && frame.valid.data()[p] && previous.size() == n) {
      z = previous[p];
      out[p] = z;
      continue;
    }
    out[p] = depthOf(z);
  }
}

void fillStats(const hw::session::FrameInfo& info, const hw::gapfill::Frame& frame, FrameStats& s) {
  s.kind = info.keyframe ? FrameKind::Keyframe : FrameKind::Warped;
  s.keyframesBuilt = info.keyframesBuilt;
  s.quads = info.quads;
  s.holeFraction = frame.holeFractionBefore;
  s.keyframeRenderMs = info.keyframeRenderMs;
  s.lodMs = info.lodMs;
  s.uploadMs = info.uploadMs;
  s.warpMs = info.keyframe ? 0.0 : info.inBetween.warpMs();
  s.composeMs = info.keyframe ? 0.0 : info.inBetween.composeMs;
  s.nearMs = info.nearMs;
}

}  // namespace

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Result<Renderer> Renderer::create(const Scene& scene, const RendererDesc& desc) {
  auto impl = std::make_unique<Impl>();
  impl->desc = desc;
  // The walk's preset, in hybrid mode: the per-segment mode choice is not
  // in the API; keyframes are built when needed (the walk's asynchronous
  // keyframes give the same frames).
  impl->walk = hw::session::presetOptions(
      desc.preset == Preset::Paper ? hw::session::Preset::Paper : hw::session::Preset::Default);
  impl->walk.mode = hw::session::FrameMode::Hybrid;
  impl->walk.asyncKeyframes = false;
  HW_TRY(mapOptions(desc, impl->walk));
  std::vector<hw::Camera> cams;
  for (std::size_t i = 0; i < desc.path.cameras.size(); ++i) {
    HW_TRY(detail::checkCamera(desc.path.cameras[i], "path camera " + std::to_string(i)));
    cams.push_back(detail::toInternal(desc.path.cameras[i]));
  }
  if (!cams.empty() && desc.path.keyframeEvery < 1)
    return hw::makeError("renderer: path.keyframeEvery: expected at least 1, got " +
                         std::to_string(desc.path.keyframeEvery));
  if (desc.context == ContextKind::Own) {
    hw::gl::HeadlessOptions ho = hw::gl::headlessOptions();  // HYBRIDWALK_GL
    if (desc.headlessGl == HeadlessGl::Auto) ho.backend = hw::gl::Backend::Auto;
    if (desc.headlessGl == HeadlessGl::Egl) ho.backend = hw::gl::Backend::Egl;
    if (desc.headlessGl == HeadlessGl::OsMesa) ho.backend = hw::gl::Backend::OsMesa;
    if (desc.eglDevice >= 0) ho.eglDevice = desc.eglDevice;
    auto ctx = desc.headlessGl == HeadlessGl::Env && desc.eglDevice < 0
                   ? hw::gl::createHeadlessContext()  // reports a bad HYBRIDWALK_GL
                   : hw::gl::createHeadlessContext(ho);
    if (!ctx) return ctx.error();
    impl->ownContext = std::move(*ctx);
    impl->glRenderer = impl->ownContext->renderer();
  } else {
    auto r = detail::adoptCurrentContext(desc.getProcAddress);
    if (!r) return r.error();
    impl->glRenderer = *r;
  }
  const hw::scenes::Scene& s = scene.impl().scene;
  if (desc.mode == Mode::Geometry) {
    hw::keyframe::RenderOptions ropt;
    ropt.depthMode = impl->walk.depthMode;
    auto g = hw::keyframe::GeometryRenderer::create(s, ropt);
    if (!g) return g.error();
    impl->ownGeometry = std::move(*g);
    impl->geometry = impl->ownGeometry.get();
    impl->geometryPath = std::move(cams);
  } else if (!cams.empty()) {
    auto p = hw::session::PathFrames::create(s, std::move(cams), desc.path.keyframeEvery,
                                             impl->walk, desc.depth);
    if (!p) return p.error();
    impl->path = std::move(*p);
    impl->geometry = &impl->path->renderer();
  } else {
    hw::session::FreeKeyframeOptions k;
    const glm::vec3 diag = s.boundsMax - s.boundsMin;
    const double diagonal = glm::length(glm::dvec3(diag));
    k.distance = desc.keyframes.distance > 0 ? desc.keyframes.distance
                                             : (diagonal > 0 ? diagonal / 16.0 : 1.0);
    if (desc.keyframes.angleDeg > 0) k.angleDeg = desc.keyframes.angleDeg;
    auto f = hw::session::FreeFrames::create(s, impl->walk, k, desc.depth);
    if (!f) return f.error();
    impl->free = std::move(*f);
    impl->geometry = &impl->free->renderer();
  }
  return Renderer(std::move(impl));
}

Status Renderer::render(const Camera& camera, Frame& out) {
  Impl& m = *impl_;
  if (m.followsPath())
    return hw::makeError(
        "renderer: render(camera) on a renderer that follows a path: call renderNext()");
  HW_TRY(detail::checkCamera(camera, "render: camera"));
  if (m.desc.mode == Mode::Geometry) return renderGeometry(camera, out);
  m.makeCurrent();
  hw::Stopwatch sw;
  hw::session::FrameInfo info;
  HW_TRY(m.free->draw(detail::toInternal(camera), &info));
  const hw::gapfill::Frame& f = m.free->frame();
  copyColour(f.colour, out);
  out.stats = FrameStats{};
  fillStats(info, f, out.stats);
  out.depth.clear();
  if (m.desc.depth) {
    if (info.keyframe)
      out.depth.assign(m.free->keyframeEyeZ().data(),
                       m.free->keyframeEyeZ().data() + m.free->keyframeEyeZ().size());
    else
      inBetweenDepth(m.free->inBetweenStep(), info.inBetween, f, m.walk.inBetween, m.previousDepth,
                     out.depth);
    m.previousDepth = out.depth;
  }
  out.stats.totalMs = sw.ms();
  return {};
}

Status Renderer::renderNext(Frame& out) {
  Impl& m = *impl_;
  if (!m.followsPath())
    return hw::makeError(
        "renderer: renderNext() on a renderer without a path: set RendererDesc::path, or call "
        "render(camera)");
  if (m.next() >= m.frames())
    return hw::makeError("renderer: renderNext(): all " + std::to_string(m.frames()) +
                         " frames of the path have been drawn");
  const int i = m.next();
  if (!m.path) {  // Mode::Geometry
    HW_TRY(renderGeometry(detail::fromInternal(m.geometryPath[static_cast<std::size_t>(i)]), out));
    out.stats.index = i;
    ++m.geometryNext;
    return {};
  }
  m.makeCurrent();
  hw::Stopwatch sw;
  hw::session::FrameInfo info;
  HW_TRY(m.path->step(&info));
  const hw::gapfill::Frame& f = m.path->frame();
  copyColour(f.colour, out);
  out.stats = FrameStats{};
  fillStats(info, f, out.stats);
  out.stats.index = i;
  out.stats.keyframes[0] = info.k0;
  out.stats.keyframes[1] = info.k1;
  out.depth.clear();
  if (m.desc.depth) {
    if (info.keyframe)
      out.depth.assign(m.path->keyframeEyeZ().data(),
                       m.path->keyframeEyeZ().data() + m.path->keyframeEyeZ().size());
    else
      inBetweenDepth(m.path->inBetweenStep(), info.inBetween, f, m.walk.inBetween, m.previousDepth,
                     out.depth);
    m.previousDepth = out.depth;
  }
  out.stats.totalMs = sw.ms();
  return {};
}

int Renderer::frameIndex() const { return impl_->next(); }
int Renderer::frameCount() const { return impl_->frames(); }

Status Renderer::renderGeometry(const Camera& camera, Frame& out) {
  Impl& m = *impl_;
  HW_TRY(detail::checkCamera(camera, "renderGeometry: camera"));
  m.makeCurrent();
  hw::Stopwatch sw;
  hw::keyframe::RenderStats rs;
  const hw::Camera cam = detail::toInternal(camera);
  out.stats = FrameStats{};
  out.depth.clear();
  if (m.desc.depth) {
    HW_TRY(m.geometry->renderKeyframe(cam, m.keyframe, &rs));
    copyColour(m.keyframe.colour, out);
    out.depth.assign(m.keyframe.eyeZ.data(), m.keyframe.eyeZ.data() + m.keyframe.eyeZ.size());
  } else {
    HW_TRY(m.geometry->renderColour(cam, m.colour, &rs));
    copyColour(m.colour, out);
  }
  out.stats.kind = FrameKind::Geometry;
  out.stats.geometryMs = rs.drawMs + rs.readbackMs;
  out.stats.totalMs = sw.ms();
  return {};
}

Status Renderer::present(const Frame& frame, int viewportWidth, int viewportHeight) {
  Impl& m = *impl_;
  if (m.ownContext)
    return hw::makeError(
        "renderer: present() draws into the caller's window: create the renderer with "
        "ContextKind::Current");
  if (frame.width < 1 || frame.height < 1 ||
      frame.rgba.size() != static_cast<std::size_t>(frame.width) * frame.height * 4)
    return hw::makeError(
        "renderer: present(): the frame is empty or its rgba is not width*height*4 bytes");
  if (viewportWidth < 1 || viewportHeight < 1)
    return hw::makeError("renderer: present(): viewport " + std::to_string(viewportWidth) + "x" +
                         std::to_string(viewportHeight) + ": expected at least 1x1");
  if (!m.presenter) {
    auto p = detail::Presenter::create();
    if (!p) return p.error();
    m.presenter = std::move(*p);
  }
  return m.presenter->draw(frame.rgba.data(), frame.width, frame.height, viewportWidth,
                           viewportHeight);
}

const std::string& Renderer::glRenderer() const { return impl_->glRenderer; }

double psnr(const Frame& a, const Frame& b) {
  if (a.width != b.width || a.height != b.height || a.width < 1 || a.height < 1 ||
      a.rgba.size() != b.rgba.size() ||
      a.rgba.size() != static_cast<std::size_t>(a.width) * a.height * 4)
    return std::numeric_limits<double>::quiet_NaN();
  hw::Image<hw::Rgba8> ia(a.width, a.height), ib(b.width, b.height);
  std::memcpy(ia.data(), a.rgba.data(), a.rgba.size());
  std::memcpy(ib.data(), b.rgba.data(), b.rgba.size());
  return hw::psnr(ia, ib);
}

}  // namespace hybridwalk
