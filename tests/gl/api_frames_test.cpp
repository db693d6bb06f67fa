// The library's frames (include/hybridwalk) against the walk's: along a path
// bit for bit the PNGs `runWalk` saves for the same scene, cameras and
// options; at free cameras close to the geometry frame; depth consistent
// with the geometry renderer's; bad input as errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "api/internal.h"
#include "core/gl/context.h"
#include "core/file_io.h"
#include "hybridwalk/hybridwalk.h"
#include "session/presets.h"
#include "session/walk.h"
#include "tests/gl/gl_fixture.h"
#include "tests/gl/walk_fixture.h"

namespace {

namespace hwa = hybridwalk;

hwa::Path apiPath(const hw::scenes::CameraPath& p) {
  hwa::Path out;
  out.keyframeEvery = p.keyframeEvery;
  for (const hw::Camera& c : p.cameras()) out.cameras.push_back(hwa::detail::fromInternal(c));
  return out;
}

// Walks `in` with `wo` (frames saved), then renders the same path through the
// library with `desc`; every frame must equal the walk's in R, G and B.
void expectWalkFrames(const std::string& spec, const hw::test::Indoor& in,
                      hw::session::WalkOptions wo, hwa::RendererDesc desc,
                      const std::string& name) {
  const std::string dir = ::testing::TempDir() + "api_frames_" + name;
  std::filesystem::remove_all(dir);
  wo.outDir = dir;
  wo.saveFrames = true;
  wo.progress = false;
  hw::test::glContext()->makeCurrent();
  auto walk = hw::session::runWalk(in.scene, spec, in.path, wo);
  ASSERT_TRUE(walk.ok()) << walk.error().message;

  auto scene = hwa::Scene::load(spec);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  desc.path = apiPath(in.path);
  auto r = hwa::Renderer::create(*scene, desc);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->frameCount(), in.path.frames);
  hwa::Frame f;
  int warped = 0;
  for (int i = 0; i < in.path.frames; ++i) {
    ASSERT_EQ(r->frameIndex(), i);
    auto st = r->renderNext(f);
    ASSERT_TRUE(st.ok()) << st.error().message;
    EXPECT_EQ(f.stats.index, i);
    warped += f.stats.kind == hwa::FrameKind::Warped;
    char file[32];
    std::snprintf(file, sizeof file, "/frames/%04d.png", i);
    auto png = hw::readPng(dir + file);
    ASSERT_TRUE(png.ok()) << png.error().message;
    ASSERT_EQ(png->width(), f.width);
    ASSERT_EQ(png->height(), f.height);
    long long differ = 0;
    for (std::size_t p = 0; p < png->size(); ++p) {
      const hw::Rgba8 w = png->data()[p];
      differ += w.r != f.rgba[4 * p] || w.g != f.rgba[4 * p + 1] || w.b != f.rgba[4 * p + 2];
    }
    EXPECT_EQ(differ, 0) << name << ": frame " << i << " differs from the walk's in " << differ
                         << " pixels";
  }
  EXPECT_GT(warped, in.path.frames / 2);
  auto past = r->renderNext(f);
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.error().message.find("all"), std::string::npos) << past.error().message;
}

TEST(ApiFrames, PathFramesAreTheWalksWithDefaultOptions) {
  const auto in = hw::test::smallIndoor("indoor:20k", 160, 23, 6);
  // `hybridwalk walk --mode hybrid`: the default preset, keyframes built
  // ahead on a worker thread.
  hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
  wo.mode = hw::session::FrameMode::Hybrid;
  ASSERT_TRUE(wo.asyncKeyframes);
  hwa::RendererDesc desc;
  desc.depth = true;  // the layers then carry eye z too: the same colours
  expectWalkFrames("indoor:20k", in, wo, desc, "defaults");
}

TEST(ApiFrames, PathFramesAreTheWalksWithOtherOptions) {
  const auto in = hw::test::smallIndoor("indoor:20k", 128, 14, 5);
  hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Paper);
  wo.lod.tau = 32768;
  wo.lod.planarity = hw::keyframe::Planarity::RegionLocal;
  wo.inBetween.compose.mode = hw::gapfill::ComposeMode::DepthMerge;
  wo.depthMode = hw::DepthMode::Fixed24;
  hwa::RendererDesc desc;
  desc.preset = hwa::Preset::Paper;
  desc.lod.tau = 32768;
  desc.lod.planarity = hwa::Planarity::RegionLocal;
  desc.compose = hwa::Compose::DepthMerge;
  desc.depthBuffer = hwa::DepthBuffer::Fixed24;
  expectWalkFrames("indoor:20k", in, wo, desc, "options");
}

// Each warper the walk can use gives the library the walk's frames, so the
// choice reaches the frame engine (the two warpers' frames differ by rounding).
TEST(ApiFrames, PathFramesAreTheWalksWithEachWarper) {
  const auto in = hw::test::smallIndoor("indoor:20k", 128, 14, 5);
  for (const auto& [choice, warper] :
       {std::pair{hw::warp::WarperChoice::Gl, hwa::Warper::Gl},
        std::pair{hw::warp::WarperChoice::Cpu, hwa::Warper::Cpu}}) {
    hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
    wo.mode = hw::session::FrameMode::Hybrid;
    wo.warper = choice;
    hwa::RendererDesc desc;
    desc.warper = warper;
    expectWalkFrames("indoor:20k", in, wo, desc, hw::warp::warperChoiceName(choice));
  }
}

TEST(ApiFrames, FreeCameraFramesAreCloseToGeometry) {
  auto scene = hwa::Scene::load("indoor:20k");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  // The default path's own speed (120 frames), its first 60 frames.
  const auto in = hw::test::smallIndoor("indoor:20k", 160, 120, 10);
  hwa::Path path = apiPath(in.path);
  path.cameras.resize(60);
  hwa::RendererDesc desc;
  desc.depth = true;
  desc.keyframes.distance = 1.0;
  auto r = hwa::Renderer::create(*scene, desc);
  ASSERT_TRUE(r.ok()) << r.error().message;
  hwa::Frame f, ref;
  std::vector<double> psnrs;
  int keyframes = 0, built = 0;
  for (std::size_t i = 0; i < path.cameras.size(); ++i) {
    auto st = r->render(path.cameras[i], f);
    ASSERT_TRUE(st.ok()) << st.error().message;
    ASSERT_TRUE(r->renderGeometry(path.cameras[i], ref).ok());
    if (i == 0) {
      EXPECT_EQ(f.stats.kind, hwa::FrameKind::Keyframe);  // nothing to warp yet
    }
    keyframes += f.stats.kind == hwa::FrameKind::Keyframe;
    built += f.stats.keyframesBuilt;
    ASSERT_EQ(f.depth.size(), static_cast<std::size_t>(f.width) * f.height);
    ASSERT_EQ(ref.depth.size(), f.depth.size());
    if (f.stats.kind == hwa::FrameKind::Keyframe) {
      EXPECT_TRUE(std::isinf(hwa::psnr(f, ref))) << "frame " << i;  // the keyframe is the geometry
      EXPECT_EQ(f.depth, ref.depth) << "frame " << i;
      continue;
    }
    EXPECT_GT(f.stats.quads, 0);
    psnrs.push_back(hwa::psnr(f, ref));
    // Depth where both see something: relative error median under 1 %, and
    // under 10 % but for depth edges (a tenth of the pixels at most).
    std::vector<float> rel;
    for (std::size_t p = 0; p < f.depth.size(); ++p)
      if (f.depth[p] > 0 && ref.depth[p] > 0)
        rel.push_back(std::abs(f.depth[p] - ref.depth[p]) / ref.depth[p]);
    ASSERT_GT(rel.size(), f.depth.size() / 2) << "frame " << i;
    std::sort(rel.begin(), rel.end());
    EXPECT_LT(rel[rel.size() / 2], 0.01f) << "frame " << i;
    EXPECT_LT(rel[rel.size() * 9 / 10], 0.1f) << "frame " << i;
  }
  ASSERT_GT(psnrs.size(), path.cameras.size() / 2) << "few frames were warped";
  std::sort(psnrs.begin(), psnrs.end());
  EXPECT_GT(psnrs[psnrs.size() / 2], 24.0);
  EXPECT_GT(built, 1);
  EXPECT_LT(built, static_cast<int>(path.cameras.size()) / 3);
  std::printf("free camera: %zu frames, %d shown keyframes, %d built, median PSNR %.2f dB\n",
              path.cameras.size(), keyframes, built, psnrs[psnrs.size() / 2]);
}

TEST(ApiFrames, BadInputIsAnError) {
  hwa::SceneDesc d;
  d.meshes.push_back({"tri", {0, 0, 0, 1, 0, 0, 0, 1, 0}, {}, {}, {0, 1, 3}, 0});
  auto s = hwa::Scene::build(d);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("index 2 is 3"), std::string::npos) << s.error().message;
  d.meshes[0].indices = {0, 1, 2};
  d.meshes[0].material = 1;
  s = hwa::Scene::build(d);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("material 1"), std::string::npos) << s.error().message;
  EXPECT_FALSE(hwa::Scene::build(hwa::SceneDesc{}).ok());
  EXPECT_FALSE(hwa::Scene::load("/nonexistent/model.obj").ok());
  EXPECT_FALSE(hwa::loadPath("/nonexistent/path.json").ok());
  EXPECT_FALSE(hwa::Camera::lookAt({0, 0, 0}, {0, 0, 0}).ok());
  EXPECT_FALSE(hwa::Camera::lookAt({0, 0, 0}, {0, 5, 0}).ok());  // along up

  d.meshes[0].material = 0;
  s = hwa::Scene::build(d);
  ASSERT_TRUE(s.ok()) << s.error().message;
  hwa::RendererDesc desc;
  desc.context = hwa::ContextKind::Current;  // no getProcAddress
  auto r = hwa::Renderer::create(*s, desc);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("getProcAddress"), std::string::npos) << r.error().message;
  desc = {};
  desc.lod.tau = -1;
  EXPECT_FALSE(hwa::Renderer::create(*s, desc).ok());

  auto cam = hwa::Camera::lookAt({0.3, 0.3, 2}, {0.3, 0.3, 0}, {0, 1, 0}, 1.0, 64, 48);
  ASSERT_TRUE(cam.ok()) << cam.error().message;
  desc = {};
  desc.path.cameras = {*cam, *cam};
  desc.path.cameras[1].width = 32;
  r = hwa::Renderer::create(*s, desc);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("camera 1"), std::string::npos) << r.error().message;
  desc.path.cameras[1] = *cam;
  r = hwa::Renderer::create(*s, desc);
  ASSERT_TRUE(r.ok()) << r.error().message;
  hwa::Frame f;
  EXPECT_FALSE(r->render(*cam, f).ok());     // a path renderer
  EXPECT_FALSE(r->present(f, 64, 48).ok());  // its own context

  desc = {};
  desc.headlessGl = hwa::HeadlessGl::Egl;
  desc.eglDevice = 99;
  r = hwa::Renderer::create(*s, desc);
  ASSERT_FALSE(r.ok());
  if (hw::gl::backendBuilt(hw::gl::Backend::Egl)) {
    EXPECT_NE(r.error().message.find("EGL device 99 does not exist"), std::string::npos)
        << r.error().message;
    desc.eglDevice = 0;
    r = hwa::Renderer::create(*s, desc);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_NE(r->glRenderer().find("llvmpipe"), std::string::npos) << r->glRenderer();
  } else {  // an OSMesa-only build names what is missing
    EXPECT_NE(r.error().message.find("built without EGL"), std::string::npos) << r.error().message;
  }

  r = hwa::Renderer::create(*s, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_FALSE(r->renderNext(f).ok());  // no path
  hwa::Camera bent = *cam;
  bent.forward = {0, 0.5, -1};
  EXPECT_FALSE(r->render(bent, f).ok());
  ASSERT_TRUE(r->render(*cam, f).ok());
  EXPECT_EQ(f.width, 64);
  EXPECT_EQ(f.height, 48);
  EXPECT_EQ(f.rgba.size(), 64u * 48u * 4u);
}

}  // namespace
