// Near objects drawn directly (Zheng et al. 1999 §3): a keyframe
// that leaves out the meshes near its eye, plus those meshes drawn by
// renderNear and composed by depth, is the full picture again.
#include <gtest/gtest.h>

#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class NearTest : public test::GlTest {};

TEST_F(NearTest, ExcludedKeyframePlusNearGeometryIsTheFullFrame) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  auto full = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(full.ok()) << full.error().message;
  keyframe::RenderOptions ro;
  ro.keyframeExcludeNear = 1.5;
  auto part = keyframe::GeometryRenderer::create(scene, ro);
  ASSERT_TRUE(part.ok()) << part.error().message;
  int framesWithNear = 0;
  for (int f : {0, 25, 30}) {
    Camera cam = path.cameraAt(f);
    cam.width = cam.height = 160;
    keyframe::Keyframe whole, without;
    keyframe::RenderStats sw, sp;
    ASSERT_TRUE((*full)->renderKeyframe(cam, whole, &sw).ok());
    ASSERT_TRUE((*part)->renderKeyframe(cam, without, &sp).ok());
    ASSERT_LE(sp.meshesDrawn, sw.meshesDrawn);
    Image<Rgba8> nearColour;
    Image<float> nearZ;
    Image<std::uint8_t> nearCovered;
    keyframe::RenderStats sn;
    ASSERT_TRUE((*part)->renderNear(cam, &cam.eye, 1, 1.5, nearColour, nearZ, nearCovered, &sn).ok());
    // Every mesh is drawn by exactly one of the two passes.
    EXPECT_EQ(sp.meshesDrawn + sn.meshesDrawn, sw.meshesDrawn) << f;
    if (sn.meshesDrawn == 0) continue;
    ++framesWithNear;
    EXPECT_LT(psnr(without.colour, whole.colour), 40.0) << "leaving near meshes out changed nothing";
    Image<Rgba8> composed = without.colour;
    for (std::size_t p = 0; p < composed.size(); ++p)
      if (nearCovered.data()[p] &&
          (!without.covered.data()[p] || nearZ.data()[p] < without.eyeZ.data()[p]))
        composed.data()[p] = nearColour.data()[p];
    EXPECT_GE(psnr(composed, whole.colour), 45.0) << f;
  }
  EXPECT_GT(framesWithNear, 0) << "no frame had a mesh within 1.5 m: weak test";
}

}  // namespace
}  // namespace hw
