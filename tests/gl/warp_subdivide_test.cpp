// Subdivision of large quads at upload (paper §2.1, issue #8): at the
// keyframe's own camera every variant still reproduces the keyframe, and only
// the adaptive one leaves flat quads alone.
#include <gtest/gtest.h>

#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/warper.h"

namespace hw {
namespace {

class SubdivideTest : public test::GlTest {};

TEST_F(SubdivideTest, EveryVariantReproducesTheKeyframeAtItsOwnCamera) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  Camera cam = scenes::defaultIndoorPath().cameraAt(30);
  cam.width = cam.height = 192;
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  keyframe::Keyframe kf;
  ASSERT_TRUE((*r)->renderKeyframe(cam, kf).ok());
  keyframe::LodOptions lo;
  lo.tau = 2048;
  auto mesh = keyframe::buildQuadMesh(kf, lo);
  ASSERT_TRUE(mesh.ok());
  int drawn[3] = {0, 0, 0};
  double affinePsnr[3] = {0, 0, 0};
  const warp::Subdivision modes[3] = {warp::Subdivision::None, warp::Subdivision::Uniform,
                                      warp::Subdivision::Adaptive};
  for (int m = 0; m < 3; ++m) {
    for (warp::TexcoordMode tc : {warp::TexcoordMode::Projective, warp::TexcoordMode::Affine}) {
      warp::WarpOptions wo;
      wo.subdivision = modes[m];
      wo.subdivideCellPx = 8;
      wo.texcoords = tc;
      auto w = warp::Warper::create(wo);
      ASSERT_TRUE(w.ok()) << w.error().message;
      warp::WarpStats us;
      auto src = (*w)->upload(kf, *mesh, &us);
      ASSERT_TRUE(src.ok()) << src.error().message;
      warp::Layer layer;
      warp::WarpStats ws;
      ASSERT_TRUE((*w)->warp(**src, cam, layer, &ws).ok());
      EXPECT_EQ(ws.uncovered, 0) << warp::subdivisionName(modes[m]);
      const double p = psnr(layer.colour, kf.colour);
      // Projective texcoords are exact at the keyframe's camera with or without
      // cells; affine ones (the paper's era) are not, and cells reduce their error.
      if (tc == warp::TexcoordMode::Projective) {
        EXPECT_GE(p, 50.0) << warp::subdivisionName(modes[m]);
      } else {
        affinePsnr[m] = p;
      }
      drawn[m] = us.drawnQuads;
      if (modes[m] == warp::Subdivision::None) {
        EXPECT_EQ(us.subdividedQuads, 0);
      }
    }
  }
  EXPECT_EQ(drawn[0], mesh->stats.quads);
  EXPECT_GT(drawn[1], drawn[0]);      // uniform cuts every quad wider than a cell
  EXPECT_LE(drawn[2], drawn[1]);      // adaptive cuts a subset of those
  EXPECT_GE(drawn[2], drawn[0]);
  EXPECT_GT(affinePsnr[1], affinePsnr[0] + 1.0) << "uniform cells did not reduce affine distortion";
  EXPECT_GE(affinePsnr[2], affinePsnr[0]);
}

}  // namespace
}  // namespace hw
