// The GL warp pass against its CPU counterpart and against the keyframe itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "core/file_io.h"
#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/reproject.h"
#include "warp/warper.h"

namespace hw {
namespace {

class WarpTest : public test::GlTest {
 protected:
  void SetUp() override {
    test::GlTest::SetUp();
    static const scenes::Scene scene = scenes::makeIndoorScene(20000);
    path_ = scenes::defaultIndoorPath();
    auto r = keyframe::GeometryRenderer::create(scene);
    ASSERT_TRUE(r.ok()) << r.error().message;
    renderer_ = std::move(*r);
  }
  Camera camera(int frame, int size) {
    Camera c = path_.cameraAt(frame);
    c.width = c.height = size;
    return c;
  }
  void build(const Camera& cam, double tau, keyframe::Keyframe& kf, keyframe::QuadMesh& mesh) {
    ASSERT_TRUE(renderer_->renderKeyframe(cam, kf).ok());
    keyframe::LodOptions lo;
    lo.tau = tau;
    auto m = keyframe::buildQuadMesh(kf, lo);
    ASSERT_TRUE(m.ok()) << m.error().message;
    mesh = std::move(*m);
  }
  // Writes actual/expected/diff PNGs for a failing image comparison.
  static void dump(const std::string& name, const Image<Rgba8>& actual, const Image<Rgba8>& expected) {
    const std::string dir = ::testing::TempDir();
    (void)writePng(dir + name + "_actual.png", actual);
    (void)writePng(dir + name + "_expected.png", expected);
    (void)writePng(dir + name + "_diff.png", diffImage(actual, expected, 4));
    std::fprintf(stderr, "images written to %s%s_*.png\n", dir.c_str(), name.c_str());
  }
  scenes::CameraPath path_;
  std::unique_ptr<keyframe::GeometryRenderer> renderer_;
};

TEST_F(WarpTest, IdentityWarpReproducesTheKeyframe) {
  const Camera cam = camera(5, 256);
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  build(cam, 2048, kf, mesh);
  ASSERT_GT(mesh.stats.quads, 10);
  auto w = warp::Warper::create();
  ASSERT_TRUE(w.ok()) << w.error().message;
  auto src = (*w)->upload(kf, mesh);
  ASSERT_TRUE(src.ok()) << src.error().message;
  warp::Layer layer;
  ASSERT_TRUE((*w)->warp(**src, cam, layer).ok());
  // Every covered keyframe pixel is covered by exactly the quads' union.
  long long uncovered = 0;
  for (std::size_t i = 0; i < kf.covered.size(); ++i)
    uncovered += kf.covered.data()[i] && !layer.coverage.data()[i];
  EXPECT_EQ(uncovered, 0);
  const double p = psnr(layer.colour, kf.colour);
  if (!(p >= 50.0)) dump("identity", layer.colour, kf.colour);
  EXPECT_GE(p, 50.0);
  // Depth written by the warp matches the keyframe's eye z.
  double maxRel = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      if (kf.covered(x, y))
        maxRel = std::max(maxRel, std::abs(double(layer.eyeZ(x, y)) - kf.eyeZ(x, y)) / kf.eyeZ(x, y));
  EXPECT_LT(maxRel, 0.05);
}

TEST_F(WarpTest, ProjectiveTexcoordsBeatAffineAtTheKeyframeCamera) {
  const Camera cam = camera(5, 256);
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  build(cam, 32768, kf, mesh);  // large quads: where the two mappings differ most
  double p[2];
  for (int k = 0; k < 2; ++k) {
    warp::WarpOptions o;
    o.texcoords = k == 0 ? warp::TexcoordMode::Projective : warp::TexcoordMode::Affine;
    auto w = warp::Warper::create(o);
    ASSERT_TRUE(w.ok());
    auto src = (*w)->upload(kf, mesh);
    ASSERT_TRUE(src.ok());
    warp::Layer layer;
    ASSERT_TRUE((*w)->warp(**src, cam, layer).ok());
    p[k] = psnr(layer.colour, kf.colour);
  }
  std::fprintf(stderr, "identity warp at tau 2^15: projective %.2f dB, affine %.2f dB\n", p[0], p[1]);
  EXPECT_GE(p[0], 50.0);
  EXPECT_GT(p[0], p[1] + 3.0);
}

TEST_F(WarpTest, GlWarpAgreesWithCpuReprojection) {
  const Camera key = camera(20, 256);
  const Camera target = camera(24, 256);
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  build(key, 2048, kf, mesh);
  auto w = warp::Warper::create();
  ASSERT_TRUE(w.ok());
  auto src = (*w)->upload(kf, mesh);
  ASSERT_TRUE(src.ok());
  warp::Layer layer;
  ASSERT_TRUE((*w)->warp(**src, target, layer).ok());
  const auto samples = warp::reprojectSamples(kf, mesh, target, 3);
  ASSERT_GT(samples.size(), 500u);
  int inside = 0, depthAgree = 0, colourAgree = 0;
  for (const auto& s : samples) {
    const int x = static_cast<int>(std::floor(s.targetU)), y = static_cast<int>(std::floor(s.targetV));
    if (x < 1 || y < 1 || x >= target.width - 1 || y >= target.height - 1) continue;
    ++inside;
    if (!layer.coverage(x, y)) continue;
    // Occluded samples (another quad in front) are not comparable.
    if (std::abs(layer.eyeZ(x, y) - s.targetZ) > 0.01 * s.targetZ) continue;
    ++depthAgree;
    const Rgba8 c = layer.colour(x, y);
    const int d = std::max({std::abs(c.r - s.colour.r), std::abs(c.g - s.colour.g),
                            std::abs(c.b - s.colour.b)});
    colourAgree += d <= 40;
  }
  ASSERT_GT(inside, 300);
  // Most samples are visible where the CPU says they land, at the CPU's depth.
  EXPECT_GT(depthAgree, 0.85 * inside) << depthAgree << " of " << inside;
  EXPECT_GT(colourAgree, 0.9 * depthAgree) << colourAgree << " of " << depthAgree;
}

TEST_F(WarpTest, MismatchedMeshIsAnError) {
  const Camera cam = camera(0, 64);
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  build(cam, 2048, kf, mesh);
  mesh.width = 32;
  auto w = warp::Warper::create();
  ASSERT_TRUE(w.ok());
  auto src = (*w)->upload(kf, mesh);
  ASSERT_FALSE(src.ok());
  EXPECT_NE(src.error().message.find("32x"), std::string::npos) << src.error().message;
}

}  // namespace
}  // namespace hw
