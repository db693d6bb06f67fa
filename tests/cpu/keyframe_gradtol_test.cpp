// The gradient-following tolerance of the LOD builder ("a fixed τ
// measures rasteriser noise"; LodOptions::tauGradient): the robust depth
// gradient, the noise it absorbs on a steep plane, the depth steps it must
// still cut, and that tauGradient = 0 (or a vanishing one) changes nothing.
// Tiling and corner invariants of the variant are in keyframe_strips_test
// (allVariants), the GL warp at the keyframe's camera in warp_strips_test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "keyframe/analytic_scene.h"
#include "keyframe/lod_builder.h"

namespace hw::keyframe {
namespace {

constexpr double kPi = 3.141592653589793;

Camera frontCamera(int w, int h) {
  return Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, w, h, 0.1, 100.0);
}

Keyframe blankKeyframe(int w, int h) {
  Keyframe kf;
  kf.camera = frontCamera(w, h);
  kf.zPrime.resize(w, h);
  kf.covered.resize(w, h, 1);
  kf.colour.resize(w, h);
  return kf;
}

// A steep plane z' = a + b·x + c·y as the rasteriser draws it: the image is
// tiled by 16-pixel cells split along their diagonal, and every triangle's
// plane is shifted by its own sub-pixel vertex-snapping offset (up to
// `snapPx` in x and y), then z' is rounded to integers. The second
// differences are therefore ~snapPx·|∇z'| across triangle edges (the noise
// NOTES-GL.md measures), zero inside a triangle up to rounding. 1/2048 px
// at |∇z'| ≈ 7000 gives |Δ²| up to ~25, about the ratio of rendered floors
// (keyframe_lod_gl_test: |Δ²| 9 at |∇z'| 4300, 24-bit depth).
double noisyPlane(int x, int y, double a, double b, double c, double snapPx, unsigned seed) {
  const int cx = x / 16, cy = y / 16;
  const int tri = (x % 16) > (y % 16) ? 1 : 0;
  std::mt19937 rng(seed ^ static_cast<unsigned>(cx * 73856093) ^
                   static_cast<unsigned>(cy * 19349663) ^ static_cast<unsigned>(tri * 83492791));
  std::uniform_real_distribution<double> u(-snapPx, snapPx);
  const double sx = u(rng), sy = u(rng);
  return std::round(a + b * (x + sx) + c * (y + sy));
}

QuadMesh build(const Keyframe& kf, const LodOptions& o, LodBuilder* b = nullptr) {
  LodBuilder local;
  LodBuilder& builder = b ? *b : local;
  QuadMesh mesh;
  const Status st = builder.build(kf, o, &mesh);
  EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message);
  return mesh;
}

TEST(LodGradTol, DefaultIsOffAndBadValuesAreRefused) {
  EXPECT_EQ(LodOptions{}.tauGradient, 0.0);
  const Keyframe kf = blankKeyframe(8, 8);
  for (double bad : {-0.01, std::nan(""), std::numeric_limits<double>::infinity()}) {
    LodOptions o;
    o.tauGradient = bad;
    LodBuilder b;
    QuadMesh mesh;
    const Status st = b.build(kf, o, &mesh);
    ASSERT_FALSE(st.ok()) << bad;
    EXPECT_NE(st.error().message.find("tauGradient"), std::string::npos) << st.error().message;
    EXPECT_TRUE(mesh.quads.empty());
  }
}

// Per axis the smaller one-sided difference (a step does not raise its own
// tolerance), one-sided at empty neighbours and the border, max of the axes.
TEST(LodGradTol, RobustGradient) {
  const int w = 6, h = 3;
  Image<double> z(w, h);
  Image<std::uint8_t> valid(w, h, 1);
  // Row profile: slope 10 per pixel, a step of 1000 between x = 2 and 3; rows
  // differ by 3 per pixel.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) z(x, y) = 10.0 * x + (x >= 3 ? 1000.0 : 0.0) + 3.0 * y;
  Image<float> g;
  computeDepthGradient(z.view(), valid.view(), &g);
  ASSERT_EQ(g.width(), w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) EXPECT_EQ(g(x, y), 10.0f) << x << "," << y;  // also at the step
  // An isolated valid pixel has no neighbour: 0. An empty pixel: 0. A pixel
  // whose only x neighbour is across the step: that difference (one-sided).
  valid(1, 1) = 0;
  valid(3, 1) = 0;
  valid(4, 1) = 0;
  valid(2, 0) = 0;
  valid(2, 2) = 0;
  computeDepthGradient(z.view(), valid.view(), &g);
  EXPECT_EQ(g(1, 1), 0.0f);
  EXPECT_EQ(g(2, 1), 0.0f);   // no valid neighbour at all
  EXPECT_EQ(g(0, 1), 3.0f);   // x: none (1 empty, border); y: min(3, 3)
  EXPECT_EQ(g(5, 1), 3.0f);   // x: none (4 empty, border)
  EXPECT_EQ(g(3, 0), 10.0f);  // x: left empty → right only; y: down empty → 0
  EXPECT_EQ(g(1, 0), 10.0f);
  z(0, 2) = 1e6;  // a spike at the corner: its only neighbours differ a lot
  computeDepthGradient(z.view(), valid.view(), &g);
  EXPECT_GT(g(0, 2), 9e5f);
}

// The reason for the variant: at a small τ a steep rendered plane is cut into
// many leaves by snapping noise; the gradient tolerance keeps it whole.
TEST(LodGradTol, SteepNoisyPlaneStaysWhole) {
  const int w = 160, h = 128;
  Keyframe kf = blankKeyframe(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      kf.zPrime(x, y) = noisyPlane(x, y, 6e6, 4000.0, 6000.0, 1 / 2048.0, 7);
  float maxDelta = 0;
  {
    LodBuilder b;
    build(kf, LodOptions{}, &b);
    for (int y = 1; y < h - 1; ++y)
      for (int x = 1; x < w - 1; ++x) maxDelta = std::max(maxDelta, b.delta()(x, y));
  }
  for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal})
    for (bool merge : {false, true}) {
      LodOptions o;
      o.tau = 8;
      o.planarity = p;
      o.mergeStrips = merge;
      const int fixed = build(kf, o).stats.quads;
      o.tauGradient = suggestedTauGradient();
      const QuadMesh grad = build(kf, o);
      std::printf(
          "steep noisy plane %dx%d (max |Δ²| %.0f), tau 8 %s%s: fixed %d quads, "
          "tauGradient %g: %d\n",
          w, h, maxDelta, planarityName(p), merge ? "+merge" : "", fixed, suggestedTauGradient(),
          grad.stats.quads);
      EXPECT_GE(fixed, 50) << planarityName(p);
      EXPECT_LE(grad.stats.quads, 4) << planarityName(p);
    }
  EXPECT_GT(maxDelta, 8.0f) << "the noise must exceed tau for the test to mean anything";
}

// A real depth step next to (and between) steep noisy planes is still cut
// exactly at the step: no leaf straddles it, with either planarity.
TEST(LodGradTol, StepBesideASteepPlaneIsStillCut) {
  const int w = 128, h = 96, step = 61;
  for (bool vertical : {true, false}) {
    Keyframe kf = blankKeyframe(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool near = vertical ? x >= step : y >= step;
        // Both sides steep; the near side is a different plane ≥ 30 000 z'
        // units in front along the step (≈ 5 pixels' worth of the gradient).
        kf.zPrime(x, y) = near ? noisyPlane(x, y, 5.95e6, 4200.0, 5800.0, 1 / 2048.0, 3)
                               : noisyPlane(x, y, 6e6, 4000.0, 6000.0, 1 / 2048.0, 5);
      }
    for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal})
      for (bool merge : {false, true})
        for (double a : {suggestedTauGradient(), 4 * suggestedTauGradient()}) {
          SCOPED_TRACE(std::string(vertical ? "vertical" : "horizontal") + " step, " +
                       planarityName(p) + (merge ? "+merge" : "") + " A " + std::to_string(a));
          LodOptions o;
          o.tau = 8;
          o.planarity = p;
          o.mergeStrips = merge;
          o.tauGradient = a;
          const QuadMesh mesh = build(kf, o);
          int straddle = 0;
          for (const Quad& q : mesh.quads) {
            const int lo = vertical ? q.rect.x0 : q.rect.y0, hi = vertical ? q.rect.x1 : q.rect.y1;
            straddle += lo < step && hi > step;
          }
          EXPECT_EQ(straddle, 0);
          if (p == Planarity::RegionLocal) {
            EXPECT_EQ(mesh.stats.onePixelLeaves, 0);
            EXPECT_LE(mesh.stats.quads, 12);
          }
        }
  }
}

// tauGradient = 0 is the fixed rule; and a gradient term too small to change
// any threshold (τ + 1e-300·g == τ in double) gives bit-identical meshes
// through the per-pixel code path — both planarities, both criteria, merged
// or not, on noisy depth with holes, steps and non-finite values.
TEST(LodGradTol, VanishingGradientTermIsBitIdentical) {
  std::mt19937 rng(4242);
  auto same = [](const QuadMesh& a, const QuadMesh& b) {
    if (a.quads.size() != b.quads.size()) return false;
    for (std::size_t i = 0; i < a.quads.size(); ++i) {
      const Quad& p = a.quads[i];
      const Quad& q = b.quads[i];
      if (std::memcmp(&p.rect, &q.rect, sizeof p.rect) != 0 ||
          std::memcmp(&p.world, &q.world, sizeof p.world) != 0 ||
          std::memcmp(&p.eyeZ, &q.eyeZ, sizeof p.eyeZ) != 0 || p.maxDelta != q.maxDelta)
        return false;
    }
    return true;
  };
  for (int iter = 0; iter < 24; ++iter) {
    const int w = 8 + static_cast<int>(rng() % 90), h = 8 + static_cast<int>(rng() % 70);
    Keyframe kf = blankKeyframe(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double step = ((x / 11 + y / 9) % 3) * 2e5;
        kf.zPrime(x, y) = noisyPlane(x, y, 5e6 + step, 300.0 * (iter % 5), 800.0, 1 / 128.0, iter);
        kf.covered(x, y) = rng() % 23 != 0;
        if (iter % 4 == 3 && rng() % 97 == 0) kf.zPrime(x, y) = std::nan("");
      }
    for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal})
      for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax})
        for (bool merge : {false, true}) {
          SCOPED_TRACE(std::string(planarityName(p)) + "/" + deltaCriterionName(c) +
                       (merge ? "/merge" : "") + " iter " + std::to_string(iter));
          LodOptions o;
          o.tau = std::ldexp(1.0, static_cast<int>(rng() % 14));
          o.planarity = p;
          o.criterion = c;
          o.mergeStrips = merge;
          LodBuilder reused;
          const QuadMesh fixed = build(kf, o, &reused);
          o.tauGradient = 1e-300;
          const QuadMesh tiny = build(kf, o, &reused);
          EXPECT_TRUE(same(fixed, tiny)) << fixed.quads.size() << " vs " << tiny.quads.size();
          o.tauGradient = 0;  // and back: nothing stale from the gradient build
          EXPECT_TRUE(same(fixed, build(kf, o, &reused)));
        }
  }
}

}  // namespace
}  // namespace hw::keyframe
