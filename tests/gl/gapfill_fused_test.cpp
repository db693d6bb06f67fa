// The fused two-layer pass (Warper::warpPair) against the paper's
// two separate layers composed on the CPU, and its background skip.
#include <gtest/gtest.h>

#include <cstring>

#include "core/file_io.h"
#include "core/metrics.h"
#include "gapfill/compose.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/warper.h"

namespace hw {
namespace {

class FusedWarpTest : public test::GlTest {
 protected:
  void SetUp() override {
    test::GlTest::SetUp();
    static const scenes::Scene scene = scenes::makeIndoorScene(20000);
    path_ = scenes::defaultIndoorPath();
    auto r = keyframe::GeometryRenderer::create(scene);
    ASSERT_TRUE(r.ok()) << r.error().message;
    renderer_ = std::move(*r);
    warp::WarpOptions wo;
    wo.writeEyeZ = false;
    auto w = warp::Warper::create(wo);
    ASSERT_TRUE(w.ok()) << w.error().message;
    warper_ = std::move(*w);
  }
  Camera camera(int frame) {
    Camera c = path_.cameraAt(frame);
    c.width = c.height = 192;
    return c;
  }
  std::unique_ptr<warp::WarpSource> source(int frame) {
    keyframe::Keyframe kf;
    EXPECT_TRUE(renderer_->renderKeyframe(camera(frame), kf).ok());
    keyframe::LodOptions lo;
    lo.tau = 2048;
    auto m = keyframe::buildQuadMesh(kf, lo);
    EXPECT_TRUE(m.ok());
    auto s = warper_->upload(kf, *m);
    EXPECT_TRUE(s.ok());
    return std::move(*s);
  }
  static bool sameImage(const Image<Rgba8>& a, const Image<Rgba8>& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.data(), b.data(), a.size() * sizeof(Rgba8)) == 0;
  }
  scenes::CameraPath path_;
  std::unique_ptr<keyframe::GeometryRenderer> renderer_;
  std::unique_ptr<warp::Warper> warper_;
};

TEST_F(FusedWarpTest, FusedPairEqualsTheSeparateLayersComposedByTheOverlayRule) {
  auto k0 = source(0), k1 = source(10);
  int framesWithBackground = 0;
  for (int f : {2, 4, 6, 8}) {
    const Camera cam = camera(f);
    const bool fgIsK0 = gapfill::chooseForeground(cam.eye, k0->keyframeCamera().eye,
                                                  k1->keyframeCamera().eye) == 0;
    const warp::WarpSource& fg = fgIsK0 ? *k0 : *k1;
    const warp::WarpSource& bg = fgIsK0 ? *k1 : *k0;
    warp::Layer a, b, fused;
    warp::WarpStats wa;
    ASSERT_TRUE(warper_->warp(fg, cam, a, &wa).ok());
    ASSERT_TRUE(warper_->warp(bg, cam, b).ok());
    gapfill::Frame expected;
    gapfill::compose(a, &b, nullptr, {}, expected);
    warp::PairStats ps;
    ASSERT_TRUE(warper_->warpPair(fg, &bg, cam, fused, true, &ps).ok());
    gapfill::Frame got;
    gapfill::compose(fused, nullptr, nullptr, {}, got);
    // Not a black or empty picture: most pixels come from the foreground.
    EXPECT_GT(expected.fromForeground, cam.width * cam.height / 2) << f;
    EXPECT_TRUE(sameImage(got.colour, expected.colour)) << "frame " << f;
    EXPECT_EQ(ps.fromBackground, expected.fromBackground) << f;
    EXPECT_EQ(ps.uncovered, expected.unfilled) << f;
    // The coverage query counts what the foreground alone leaves empty.
    EXPECT_EQ(ps.uncoveredByForeground, wa.uncovered) << f;
    EXPECT_EQ(ps.backgroundDrawn, wa.uncovered > 0) << f;
    framesWithBackground += ps.fromBackground > 0;
    if (!sameImage(got.colour, expected.colour)) {
      (void)writePng(::testing::TempDir() + "fused_got.png", got.colour);
      (void)writePng(::testing::TempDir() + "fused_expected.png", expected.colour);
    }
  }
  EXPECT_GT(framesWithBackground, 0) << "the background layer never contributed: weak test";
}

TEST_F(FusedWarpTest, SkippingTheBackgroundWhenCoverageIsFullIsBitIdentical) {
  auto k0 = source(0), k1 = source(10);
  // At the foreground keyframe's own camera the foreground covers every pixel
  // (closed rooms; empty pixels would be sky rectangles).
  const Camera cam = camera(0);
  warp::Layer skipped, drawn;
  warp::PairStats s1, s2;
  ASSERT_TRUE(warper_->warpPair(*k0, k1.get(), cam, skipped, true, &s1).ok());
  ASSERT_TRUE(warper_->warpPair(*k0, k1.get(), cam, drawn, false, &s2).ok());
  EXPECT_EQ(s1.uncoveredByForeground, 0);
  EXPECT_FALSE(s1.backgroundDrawn);
  EXPECT_EQ(s1.quadsBackground, 0);
  EXPECT_TRUE(s2.backgroundDrawn);
  EXPECT_GT(s2.quadsBackground, 0);
  EXPECT_TRUE(sameImage(skipped.colour, drawn.colour));
  EXPECT_EQ(s1.uncovered, 0);
  EXPECT_EQ(s2.fromBackground, 0);
}

TEST_F(FusedWarpTest, WithoutABackgroundUncoveredPixelsStayHoles) {
  auto k0 = source(0);
  const Camera cam = camera(8);  // far enough that k0 alone leaves holes
  warp::Layer alone, fusedLayer;
  warp::WarpStats ws;
  ASSERT_TRUE(warper_->warp(*k0, cam, alone, &ws).ok());
  warp::PairStats ps;
  ASSERT_TRUE(warper_->warpPair(*k0, nullptr, cam, fusedLayer, true, &ps).ok());
  ASSERT_GT(ws.uncovered, 0);
  EXPECT_EQ(ps.uncovered, ws.uncovered);
  EXPECT_FALSE(ps.backgroundDrawn);
  EXPECT_TRUE(sameImage(alone.colour, fusedLayer.colour));
}

}  // namespace
}  // namespace hw
