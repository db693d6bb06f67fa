// Frames kept on the GPU (FrameEngine::keepFramesOnGpu, gapfill/gl/
// gpu_frames.h) are the CPU path's frames bit for bit: in-between frames with
// holes filled from the previous frame, the hole pass's rectangles, a frame
// with no previous one, keyframes and geometry frames shown; the masks and
// counts read back agree too. Where the engine cannot keep them there it says so.
#include <gtest/gtest.h>

#include <string>

#include "core/gl/gl_api.h"
#include "gapfill/gl/gpu_frames.h"
#include "keyframe/lod_builder.h"
#include "session/frame_engine.h"
#include "session/presets.h"
#include "tests/gl/gl_fixture.h"
#include "tests/gl/walk_fixture.h"

namespace {

using hw::session::FrameEngine;

class GpuFramesTest : public hw::test::GlTest {};

using hw::test::Built;

Built build(FrameEngine& e, const hw::Camera& cam, const hw::session::WalkOptions& wo) {
  return hw::test::buildKeyframe(e.renderer(), cam, wo.lod);
}

hw::session::WalkOptions glOptions() {
  hw::session::WalkOptions wo = hw::session::presetOptions(hw::session::Preset::Default);
  wo.warper = hw::warp::WarperChoice::Gl;
  return wo;
}

int differingPixels(const hw::Image<hw::Rgba8>& a, const hw::Image<hw::Rgba8>& b) {
  if (a.width() != b.width() || a.height() != b.height()) return -1;
  int n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const hw::Rgba8 p = a.data()[i], q = b.data()[i];
    const bool d = p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a;
    if (d && n == 0)
      ADD_FAILURE() << "first difference at pixel " << i << ": " << int(p.r) << "," << int(p.g)
                    << "," << int(p.b) << "," << int(p.a) << " against " << int(q.r) << ","
                    << int(q.g) << "," << int(q.b) << "," << int(q.a);
    n += d;
  }
  return n;
}

int differing(const hw::Image<std::uint8_t>& a, const hw::Image<std::uint8_t>& b) {
  if (a.width() != b.width() || a.height() != b.height()) return -1;
  int n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += a.data()[i] != b.data()[i];
  return n;
}

// Both engines' current frames: the same pixels, masks and counts.
void expectSameFrame(FrameEngine& cpu, FrameEngine& gpu, const std::string& what) {
  hw::Image<hw::Rgba8> onGpu;
  gpu.readFrame(onGpu);
  EXPECT_EQ(differingPixels(onGpu, cpu.frame().colour), 0) << what;
  EXPECT_EQ(differing(gpu.frame().holesBefore, cpu.frame().holesBefore), 0) << what;
  EXPECT_EQ(differing(gpu.frame().valid, cpu.frame().valid), 0) << what;
  EXPECT_EQ(gpu.frame().fromForeground, cpu.frame().fromForeground) << what;
  EXPECT_EQ(gpu.frame().fromBackground, cpu.frame().fromBackground) << what;
  EXPECT_EQ(gpu.frame().fromPrevious, cpu.frame().fromPrevious) << what;
  EXPECT_EQ(gpu.frame().unfilled, cpu.frame().unfilled) << what;
  EXPECT_EQ(gpu.frame().holeFractionBefore, cpu.frame().holeFractionBefore) << what;
  EXPECT_EQ(gpu.frame().holeFractionAfter, cpu.frame().holeFractionAfter) << what;
}

TEST_F(GpuFramesTest, SameFramesAsOnTheCpu) {
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 128, 121, 10);
  const hw::session::WalkOptions wo = glOptions();
  auto ec = FrameEngine::create(in.scene, wo, false);
  auto eg = FrameEngine::create(in.scene, wo, false);
  ASSERT_TRUE(ec.ok() && eg.ok());
  FrameEngine& cpu = **ec;
  FrameEngine& gpu = **eg;
  ASSERT_FALSE(cpu.cpuWarper());
  ASSERT_TRUE(gpu.keepFramesOnGpu(true));
  ASSERT_TRUE(gpu.framesOnGpu());
  EXPECT_FALSE(cpu.framesOnGpu());
  const hw::Camera c0 = in.path.cameraAt(0), c10 = in.path.cameraAt(10);
  const Built k0 = build(cpu, c0, wo), k10 = build(cpu, c10, wo);
  for (FrameEngine* e : {&cpu, &gpu}) {
    ASSERT_TRUE(e->upload(0, k0.kf, k0.mesh, c0.eye, nullptr).ok());
    ASSERT_TRUE(e->upload(10, k10.kf, k10.mesh, c10.eye, nullptr).ok());
  }

  int framesWithHoles = 0, framesFromPrevious = 0, rectsDrawn = 0, unfilledFrames = 0;
  for (int f = 0; f <= 10; ++f) {
    const hw::Camera cam = in.path.cameraAt(f);
    const std::string what = "frame " + std::to_string(f);
    hw::session::InBetweenStats st;
    if (f == 0 || f == 10) {
      for (FrameEngine* e : {&cpu, &gpu})
        ASSERT_TRUE(e->showKeyframe(cam, f, f == 0 ? k0.kf : k10.kf, &st).ok()) << what;
    } else if (f == 7) {
      hw::keyframe::RenderStats rs;
      for (FrameEngine* e : {&cpu, &gpu}) ASSERT_TRUE(e->drawGeometry(cam, &rs).ok()) << what;
    } else {
      if (f == 4)  // holes with nothing to fill them: unfilled
        for (FrameEngine* e : {&cpu, &gpu}) e->forgetPrevious();
      for (FrameEngine* e : {&cpu, &gpu}) ASSERT_TRUE(e->warp(cam, 0, 10, st, nullptr).ok()) << what;
      expectSameFrame(cpu, gpu, what + ", before the hole pass");
      framesWithHoles += cpu.frame().holeFractionBefore > 0;
      framesFromPrevious += cpu.frame().fromPrevious > 0;
      unfilledFrames += cpu.frame().unfilled > 0;
      // Odd frames: the hole pass draws its rectangles.
      if (f % 2 == 1) {
        for (FrameEngine* e : {&cpu, &gpu}) {
          hw::session::HolePassResult hr;
          ASSERT_TRUE(e->renderHoles(cam, nullptr, &hr).ok()) << what;
          if (e == &gpu) rectsDrawn += hr.drawn;
        }
      }
    }
    expectSameFrame(cpu, gpu, what);
    for (FrameEngine* e : {&cpu, &gpu}) e->present();
  }
  // What the comparison covered.
  EXPECT_GE(framesWithHoles, 6);
  EXPECT_GE(framesFromPrevious, 4);
  EXPECT_GT(rectsDrawn, 0);
  EXPECT_GE(unfilledFrames, 1);
  // Not a blank image: the last frame has many colours.
  hw::Image<hw::Rgba8> last;
  gpu.readFrame(last);
  int changes = 0;
  for (std::size_t i = 1; i < last.size(); ++i)
    changes += last.data()[i].r != last.data()[i - 1].r || last.data()[i].g != last.data()[i - 1].g;
  EXPECT_GT(changes, static_cast<int>(last.size() / 20));
  // The texture shown is the frame read back.
  EXPECT_NE(gpu.frameTexture(), 0u);
  EXPECT_EQ(cpu.frameTexture(), 0u);
}

TEST_F(GpuFramesTest, RefusedWhereTheFrameNeedsTheCpu) {
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 64, 3, 2);
  struct Case {
    const char* what;
    void (*change)(hw::session::WalkOptions&);
  };
  const Case cases[] = {
      {"the CPU warper", [](hw::session::WalkOptions& o) { o.warper = hw::warp::WarperChoice::Cpu; }},
      {"near geometry", [](hw::session::WalkOptions& o) { o.inBetween.nearDistance = 1.0; }},
      {"the reprojected fallback",
       [](hw::session::WalkOptions& o) { o.inBetween.fallback = hw::gapfill::Fallback::Reproject; }},
      {"separate layers", [](hw::session::WalkOptions& o) { o.inBetween.fusedLayers = false; }},
  };
  for (const Case& c : cases) {
    hw::session::WalkOptions wo = glOptions();
    c.change(wo);
    auto e = FrameEngine::create(in.scene, wo, false);
    ASSERT_TRUE(e.ok()) << c.what << ": " << e.error().message;
    EXPECT_FALSE((*e)->keepFramesOnGpu(true)) << c.what;
    EXPECT_FALSE((*e)->framesOnGpu()) << c.what;
  }
  auto e = FrameEngine::create(in.scene, glOptions(), false);
  ASSERT_TRUE(e.ok());
  EXPECT_TRUE((*e)->keepFramesOnGpu(true));
  EXPECT_TRUE((*e)->keepFramesOnGpu(false));
  EXPECT_FALSE((*e)->framesOnGpu());
}

TEST_F(GpuFramesTest, CopyIntoAWrongTargetIsAnError) {
  const hw::test::Indoor in = hw::test::smallIndoor("indoor:20k", 64, 3, 2);
  auto r = hw::keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok());
  const hw::Camera cam = in.path.cameraAt(0);
  hw::gapfill::GpuFrames small;
  ASSERT_TRUE(small.resize(32, 32).ok());
  const hw::Status s = (*r)->renderColourTo(cam, small.copyTarget());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("is 32x32, expected a 64x64"), std::string::npos)
      << s.error().message;
  const hw::Status none = (*r)->renderColourTo(cam, 0);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("not a framebuffer"), std::string::npos);
  const hw::PixelRect rect{0, 0, 8, 8};
  EXPECT_FALSE((*r)->renderColourRectsTo(cam, &rect, 1, small.copyTarget()).ok());
  EXPECT_FALSE(small.resize(0, 5).ok());
  EXPECT_EQ(hw::gl::checkGlError("after the errors").ok(), true);
}

}  // namespace
