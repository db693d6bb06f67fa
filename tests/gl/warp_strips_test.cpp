// The edge-strip variants of the LOD builder (region-local planarity,
// strip merging) on rendered keyframes, through the real GL warp: every
// variant tiles the covered pixels exactly once and, warped to the keyframe's
// own camera, reproduces the keyframe (≥ 50 dB). Lives in the warp module's
// tests because it links the warper (hw_warp); the CPU properties are in
// tests/cpu/keyframe_strips_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/file_io.h"
#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/warper.h"

namespace hw {
namespace {

class StripsGlTest : public test::GlTest {};

void expectTiling(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh) {
  const int w = kf.colour.width(), h = kf.colour.height();
  Image<int> count(w, h, 0);
  for (const auto& q : mesh.quads) {
    ASSERT_TRUE(q.rect.x0 >= 0 && q.rect.y0 >= 0 && q.rect.x1 <= w && q.rect.y1 <= h &&
                q.rect.x0 < q.rect.x1 && q.rect.y0 < q.rect.y1);
    for (int y = q.rect.y0; y < q.rect.y1; ++y)
      for (int x = q.rect.x0; x < q.rect.x1; ++x) ++count(x, y);
    for (int k = 0; k < 4; ++k) {
      ASSERT_TRUE(std::isfinite(q.world[k].x) && std::isfinite(q.world[k].y) &&
                  std::isfinite(q.world[k].z));
      ASSERT_GT(q.eyeZ[k], 0.0);
    }
  }
  long long gaps = 0, overlaps = 0, onEmpty = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      gaps += kf.covered(x, y) && count(x, y) == 0;
      overlaps += count(x, y) > 1;
      onEmpty += !kf.covered(x, y) && count(x, y) > 0;
    }
  EXPECT_EQ(gaps, 0);
  EXPECT_EQ(overlaps, 0);
  EXPECT_EQ(onEmpty, 0);
}

TEST_F(StripsGlTest, EveryVariantReproducesTheKeyframeAtItsCamera) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto warper = warp::Warper::create();
  ASSERT_TRUE(warper.ok()) << warper.error().message;
  keyframe::LodBuilder builder;
  for (int frame : {0, 60, 110}) {
    Camera cam = path.cameraAt(frame);
    cam.width = cam.height = 256;
    keyframe::Keyframe kf;
    ASSERT_TRUE((*r)->renderKeyframe(cam, kf).ok());
    // The variants at the paper's τ; the gradient tolerance
    // (five-point, 4× its suggested value) also at a small τ, where it acts.
    for (double tau : {8.0, 2048.0, 32768.0})
      for (auto planarity : {keyframe::Planarity::Stencil, keyframe::Planarity::RegionLocal})
        for (auto crit :
             {keyframe::DeltaCriterion::FivePoint, keyframe::DeltaCriterion::PerAxisMax})
          for (bool merge : {false, true})
            for (double grad : {0.0, 4 * keyframe::suggestedTauGradient()}) {
              if (grad == 0 && tau == 8.0) continue;  // fixed τ = 8: many quads, slow
              if (grad > 0 && crit != keyframe::DeltaCriterion::FivePoint) continue;
              keyframe::LodOptions o;
              o.tau = tau;
              o.criterion = crit;
              o.planarity = planarity;
              o.mergeStrips = merge;
              o.tauGradient = grad;
              const std::string what = "frame " + std::to_string(frame) + " tau " +
                                       std::to_string(static_cast<int>(tau)) + " " +
                                       keyframe::planarityName(planarity) + "/" +
                                       keyframe::deltaCriterionName(crit) +
                                       (merge ? "/merge" : "") + (grad > 0 ? "/grad" : "");
              SCOPED_TRACE(what);
              keyframe::QuadMesh mesh;
              ASSERT_TRUE(builder.build(kf, o, &mesh).ok());
              expectTiling(kf, mesh);
              auto src = (*warper)->upload(kf, mesh);
              ASSERT_TRUE(src.ok()) << src.error().message;
              warp::Layer layer;
              ASSERT_TRUE((*warper)->warp(**src, cam, layer).ok());
              long long uncovered = 0;
              for (std::size_t i = 0; i < kf.covered.size(); ++i)
                uncovered += kf.covered.data()[i] && !layer.coverage.data()[i];
              EXPECT_EQ(uncovered, 0);
              const double p = psnr(layer.colour, kf.colour);
              if (!(p >= 50.0)) {
                const std::string base = ::testing::TempDir() + "strips_" + std::to_string(frame);
                (void)writePng(base + "_actual.png", layer.colour);
                (void)writePng(base + "_expected.png", kf.colour);
                (void)writePng(base + "_diff.png", diffImage(layer.colour, kf.colour, 4));
              }
              EXPECT_GE(p, 50.0);
              std::printf("%s: %d quads, %d one-pixel, %.1f dB\n", what.c_str(), mesh.stats.quads,
                          mesh.stats.onePixelLeaves, p);
            }
  }
}

}  // namespace
}  // namespace hw
