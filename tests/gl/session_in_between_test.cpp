// The in-between step (session/in_between.h) is the walk's frame: the same
// keyframe pair, camera, previous frame and options give the walk's saved
// frame bit for bit, in every composition mode; the viewer calls the same
// step, so its hybrid frames are these too.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/file_io.h"
#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "session/in_between.h"
#include "session/walk.h"
#include "walk_fixture.h"
#include "warp/warper.h"

namespace hw {
namespace {

class InBetweenStepTest : public test::GlTest,
                          public ::testing::WithParamInterface<session::InBetweenOptions> {};

std::string tempDir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() /
                 ("hw_in_between_" + name + "_" + std::to_string(::testing::UnitTest::GetInstance()
                                                                     ->random_seed()));
  std::filesystem::remove_all(d);
  return d.string();
}

TEST_P(InBetweenStepTest, GivesTheWalksFrameBitForBit) {
  const session::InBetweenOptions ib = GetParam();
  test::Indoor in = test::smallIndoor("indoor:20k", 96, 11, 10);
  session::WalkOptions wo;
  wo.inBetween = ib;
  wo.saveFrames = true;
  wo.strips = 0;
  wo.progress = false;
  wo.outDir = tempDir(std::to_string(static_cast<int>(ib.compose.mode)) +
                      (ib.fusedLayers ? "f" : "s") + (ib.nearDistance > 0 ? "n" : "") +
                      (ib.reprojects() ? "r" : ""));
  auto walk = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(walk.ok()) << walk.error().message;

  // The same frame by hand: keyframes 0 and 10, rendered, meshed and
  // uploaded as the walk does, then the step at frame 1 with keyframe 0's
  // image as the previous frame.
  keyframe::RenderOptions ro;
  ro.depthMode = wo.depthMode;
  ro.keyframeExcludeNear = ib.nearDistance;
  auto renderer = keyframe::GeometryRenderer::create(in.scene, ro);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  warp::WarpOptions wopt = wo.warp;
  wopt.writeEyeZ = ib.needsEyeZ();
  auto warper = test::warperOfWalk(walk->report, wopt);
  ASSERT_TRUE(warper.ok()) << warper.error().message;
  keyframe::Keyframe kf[2];
  std::unique_ptr<warp::WarpSource> src[2];
  for (int k = 0; k < 2; ++k) {
    ASSERT_TRUE((*renderer)->renderKeyframe(in.path.cameraAt(k * 10), kf[k]).ok());
    keyframe::QuadMesh mesh;
    keyframe::LodBuilder builder;
    ASSERT_TRUE(builder.build(kf[k], wo.lod, &mesh).ok());
    auto s = (*warper)->upload(kf[k], mesh);
    ASSERT_TRUE(s.ok()) << s.error().message;
    src[k] = std::move(*s);
  }
  const Camera cam = in.path.cameraAt(1);
  const int fg = gapfill::chooseForeground(cam.eye, kf[0].camera.eye, kf[1].camera.eye);
  gapfill::Frame previous, frame;
  session::showKeyframe(kf[0].colour, previous);
  if (ib.reprojects()) session::setKeyframeDepth(kf[0], previous);
  session::InBetweenStep step(ib);
  session::NearGeometry near;
  near.renderer = renderer->get();
  near.eyes[0] = kf[0].camera.eye;
  near.eyes[1] = kf[1].camera.eye;
  near.eyeCount = 1;
  session::InBetweenStats st;
  if (ib.nearDistance > 0) {  // the shown keyframe had its near objects drawn too
    ASSERT_TRUE(step.drawNear(near, kf[0].camera, kf[0].eyeZ, previous, st).ok());
  }
  near.eyeCount = 2;
  ASSERT_TRUE(step.draw(**warper, *src[fg], src[1 - fg].get(), cam, &previous, &near, frame, st)
                  .ok());
  EXPECT_EQ(st.nearMs >= 0, ib.nearDistance > 0);

  auto saved = readPng(wo.outDir + "/frames/0001.png");
  ASSERT_TRUE(saved.ok()) << saved.error().message;
  ASSERT_EQ(saved->width(), frame.colour.width());
  ASSERT_EQ(saved->height(), frame.colour.height());
  int differing = 0;
  for (std::size_t p = 0; p < frame.colour.size(); ++p) {
    const Rgba8 a = saved->data()[p], b = frame.colour.data()[p];
    differing += a.r != b.r || a.g != b.g || a.b != b.b;
  }
  EXPECT_EQ(differing, 0);
  // Not a blank frame: it looks like the geometry frame.
  Image<Rgba8> reference;
  ASSERT_TRUE((*renderer)->renderColour(cam, reference).ok());
  EXPECT_GT(psnr(frame.colour, reference), 20.0);
  std::filesystem::remove_all(wo.outDir);
}

session::InBetweenOptions options(gapfill::ComposeMode mode, bool fused, double near,
                                  gapfill::Fallback fallback = gapfill::Fallback::Copy) {
  session::InBetweenOptions o;
  o.compose.mode = mode;
  o.fusedLayers = fused;
  o.nearDistance = near;
  o.fallback = fallback;
  return o;
}

INSTANTIATE_TEST_SUITE_P(
    Modes, InBetweenStepTest,
    ::testing::Values(options(gapfill::ComposeMode::Overlay, true, 0),
                      options(gapfill::ComposeMode::Overlay, false, 0),
                      options(gapfill::ComposeMode::DepthMerge, false, 0),
                      options(gapfill::ComposeMode::Overlay, true, 1.5),
                      options(gapfill::ComposeMode::Blend, false, 0),
                      options(gapfill::ComposeMode::Overlay, true, 0, gapfill::Fallback::Reproject),
                      options(gapfill::ComposeMode::Blend, false, 1.5,
                              gapfill::Fallback::Reproject)));

}  // namespace
}  // namespace hw
