// The edge-strip variants of the LOD builder (DESIGN.md "Binary
// subdivision", known weakness): region-local planarity and strip merging,
// on analytic depth buffers (no GL). Every variant must tile the covered
// pixels exactly once with corners on their pixel rays; RegionLocal must
// avoid the paper's one-pixel strips along depth edges without letting a leaf
// straddle one; merging must reduce the quad count.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "keyframe/analytic_scene.h"
#include "keyframe/lod_builder.h"

namespace hw::keyframe {
namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kTau11 = 2048.0, kTau15 = 32768.0;

struct Variant {
  Planarity planarity;
  DeltaCriterion criterion;
  bool merge;
  double tauGradient = 0;  // LodOptions::tauGradient (keyframe_gradtol_test)
  std::string name() const {
    return std::string(planarityName(planarity)) + "/" + deltaCriterionName(criterion) +
           (merge ? "/merge" : "") + (tauGradient > 0 ? "/grad" : "");
  }
};

// The variants, then the gradient tolerance (at 4× the suggested
// value, to stress it) with both planarities, five-point, merged or not.
std::vector<Variant> allVariants() {
  std::vector<Variant> v;
  for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal})
    for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax})
      for (bool m : {false, true}) v.push_back({p, c, m});
  for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal})
    for (bool m : {false, true})
      v.push_back({p, DeltaCriterion::FivePoint, m, 4 * suggestedTauGradient()});
  return v;
}

LodOptions optionsFor(const Variant& v, double tau) {
  LodOptions o;
  o.tau = tau;
  o.criterion = v.criterion;
  o.planarity = v.planarity;
  o.mergeStrips = v.merge;
  o.tauGradient = v.tauGradient;
  return o;
}

Camera frontCamera(int w, int h, double n = 0.1, double f = 100.0) {
  return Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, w, h, n, f);
}

// Boxes at several depths in front of a slightly oblique wall, all inside the
// view (the wall fills it: no empty pixels, no box touches the image border).
// Every box is at least ~1.3·10^5 z' units in front of the wall (4·2^15), so
// a step is a discontinuity at both reference thresholds.
AnalyticScene boxesBeforeWall() {
  AnalyticScene s;
  s.planes.push_back({{0, 0, -20}, glm::normalize(glm::dvec3(-0.25, 0.1, 1.0))});
  s.boxes.push_back({{-3.0, -2.0, -6.0}, {-1.4, -0.4, -5.0}});
  s.boxes.push_back({{-0.6, 0.3, -5.0}, {0.9, 1.6, -4.0}});
  s.boxes.push_back({{1.0, -2.2, -7.0}, {2.6, -0.8, -6.2}});
  s.boxes.push_back({{-1.2, -1.4, -3.4}, {-0.4, -0.6, -3.0}});
  s.boxes.push_back({{2.0, 1.0, -8.0}, {3.2, 2.6, -7.5}});
  return s;
}

AnalyticScene sphereBeforeWall() {
  AnalyticScene s;
  s.planes.push_back({{0, 0, -8}, glm::normalize(glm::dvec3(0.2, -0.1, 1.0))});
  s.spheres.push_back({{0.4, -0.3, -4.5}, 1.3});
  return s;
}

// Every valid pixel (covered, finite z') in exactly one leaf, others in none.
void expectTiling(const QuadMesh& mesh, const Keyframe& kf) {
  const int w = kf.zPrime.width(), h = kf.zPrime.height();
  ASSERT_EQ(mesh.width, w);
  ASSERT_EQ(mesh.height, h);
  Image<int> count(w, h, 0);
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    ASSERT_TRUE(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= w && r.y1 <= h && r.x0 < r.x1 && r.y0 < r.y1)
        << r.x0 << "," << r.y0 << "," << r.x1 << "," << r.y1;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) ++count(x, y);
  }
  long long bad = 0, empty = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool valid = kf.covered(x, y) != 0 && std::isfinite(kf.zPrime(x, y));
      empty += !valid;
      if (count(x, y) != (valid ? 1 : 0) && ++bad < 5)
        ADD_FAILURE() << "pixel " << x << "," << y << " in " << count(x, y) << " leaves";
    }
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(mesh.stats.emptyPixels, empty);
  EXPECT_EQ(mesh.stats.quads, static_cast<int>(mesh.quads.size()));
  int onePixel = 0;
  for (const Quad& q : mesh.quads) onePixel += q.rect.area() == 1;
  EXPECT_EQ(mesh.stats.onePixelLeaves, onePixel);
}

// Corners finite, in front of the eye, on the rays through the rectangle's
// corners: they reproject within 0.5 px (unless clamped near a horizon,
// which these scenes do not have).
void expectCorners(const QuadMesh& mesh, const Camera& cam) {
  int worst = 0;
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
    const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
    for (int i = 0; i < 4; ++i) {
      ASSERT_TRUE(std::isfinite(q.world[i].x) && std::isfinite(q.world[i].y) &&
                  std::isfinite(q.world[i].z));
      ASSERT_TRUE(std::isfinite(q.eyeZ[i]));
      ASSERT_GT(q.eyeZ[i], 0.0);
      const ProjectedPoint p = cam.project(q.world[i]);
      if (!(std::fabs(p.u - us[i]) <= 0.5 && std::fabs(p.v - vs[i]) <= 0.5) && ++worst < 5) {
        ADD_FAILURE() << "corner " << i << " of [" << r.x0 << "," << r.x1 << ")x[" << r.y0 << ","
                      << r.y1 << ") reprojects to " << p.u << "," << p.v;
      }
    }
  }
}

// Least-squares plane of z' over a leaf (full grid: the normal equations
// decouple) and the largest |fit − z'| over its pixels.
double fitResidual(const Keyframe& kf, const PixelRect& r) {
  const double cx = 0.5 * (r.x0 + r.x1 - 1), cy = 0.5 * (r.y0 + r.y1 - 1);
  const double z0 = kf.zPrime(r.x0, r.y0);
  double s = 0, su = 0, sv = 0, suu = 0, svv = 0;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const double z = kf.zPrime(x, y) - z0;
      s += z;
      su += z * (x - cx);
      sv += z * (y - cy);
      suu += (x - cx) * (x - cx);
      svv += (y - cy) * (y - cy);
    }
  const double a = s / static_cast<double>(r.area());
  const double b = suu > 0 ? su / suu : 0, c = svv > 0 ? sv / svv : 0;
  double worst = 0;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x)
      worst = std::max(worst, std::fabs(kf.zPrime(x, y) - z0 - (a + b * (x - cx) + c * (y - cy))));
  return worst;
}

QuadMesh buildChecked(const Keyframe& kf, const LodOptions& o, LodBuilder* b = nullptr) {
  LodBuilder local;
  LodBuilder& builder = b ? *b : local;
  QuadMesh mesh;
  const Status st = builder.build(kf, o, &mesh);
  EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message);
  expectTiling(mesh, kf);
  expectCorners(mesh, kf.camera);
  return mesh;
}

TEST(LodStrips, DefaultsAreThePapersRule) {
  const LodOptions o;
  EXPECT_EQ(o.planarity, Planarity::Stencil);
  EXPECT_FALSE(o.mergeStrips);
  EXPECT_EQ(o.mergeToleranceZPrime, 0.0);
  Planarity p = Planarity::Stencil;
  EXPECT_TRUE(parsePlanarity("region-local", &p));
  EXPECT_EQ(p, Planarity::RegionLocal);
  EXPECT_FALSE(parsePlanarity("local", &p));
  EXPECT_EQ(p, Planarity::RegionLocal);
  EXPECT_STREQ(planarityName(Planarity::Stencil), "stencil");
}

TEST(LodStrips, EveryVariantTilesWithCornersOnTheirRays) {
  struct Case {
    const char* name;
    Keyframe kf;
  };
  std::vector<Case> cases;
  cases.push_back({"room 256", renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(256, 256))});
  cases.push_back(
      {"room 300x170", renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(300, 170))});
  cases.push_back({"boxes", renderAnalyticKeyframe(boxesBeforeWall(), frontCamera(256, 192))});
  cases.push_back({"sphere", renderAnalyticKeyframe(sphereBeforeWall(), frontCamera(200, 200))});
  AnalyticScene voidSphere;
  voidSphere.spheres.push_back({{0.3, -0.2, -4}, 1.2});
  cases.push_back(
      {"sphere in the void", renderAnalyticKeyframe(voidSphere, frontCamera(160, 120))});
  LodBuilder reused;  // one builder across sizes and variants
  for (const Case& c : cases)
    for (const Variant& v : allVariants())
      for (double tau : {kTau11, kTau15}) {
        SCOPED_TRACE(std::string(c.name) + " " + v.name() + " tau " + std::to_string(tau));
        const QuadMesh mesh = buildChecked(c.kf, optionsFor(v, tau), &reused);
        EXPECT_GT(mesh.quads.size(), 0u);
        EXPECT_EQ(reused.leavesBeforeMerge() >= static_cast<int>(mesh.quads.size()), true);
        if (!v.merge) {
          EXPECT_EQ(reused.leavesBeforeMerge(), static_cast<int>(mesh.quads.size()));
        }
      }
}

// Depth buffers with noise, holes, non-finite and huge values: tiling and
// finite corners for every variant (what the fuzzer checks for the paper's
// rule).
TEST(LodStrips, RandomDepthAndCoverage) {
  std::mt19937 rng(777);
  for (int iter = 0; iter < 40; ++iter) {
    const int w = 1 + static_cast<int>(rng() % 60), h = 1 + static_cast<int>(rng() % 60);
    Keyframe kf;
    kf.camera = frontCamera(w, h);
    kf.zPrime.resize(w, h);
    kf.covered.resize(w, h);
    kf.colour.resize(w, h);
    const int mode = iter % 4;
    std::uniform_real_distribution<double> uni(0.0, kZPrimeScale);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double plane = 4e6 + 1500.0 * x + 700.0 * y + ((x / 9 + y / 7) % 2) * 3e5;
        kf.zPrime(x, y) = mode == 0 ? uni(rng) : std::round(plane + (rng() % 3 == 0 ? 3.0 : 0.0));
        kf.covered(x, y) = (rng() % 10) < (mode == 2 ? 5u : 9u);
        if (mode == 3 && rng() % 50 == 0)
          kf.zPrime(x, y) = (rng() % 2) ? std::nan("") : std::numeric_limits<double>::infinity();
        if (mode == 3 && rng() % 60 == 0) kf.zPrime(x, y) = (rng() % 2 ? 1 : -1) * 1e300;
      }
    for (const Variant& v : allVariants()) {
      SCOPED_TRACE(v.name() + " iter " + std::to_string(iter));
      LodOptions o = optionsFor(v, std::ldexp(1.0, static_cast<int>(rng() % 17)));
      LodBuilder b;
      QuadMesh mesh;
      ASSERT_TRUE(b.build(kf, o, &mesh).ok());
      expectTiling(mesh, kf);
      for (const Quad& q : mesh.quads)
        for (int i = 0; i < 4; ++i) {
          ASSERT_TRUE(std::isfinite(q.world[i].x) && std::isfinite(q.world[i].y) &&
                      std::isfinite(q.world[i].z));
          ASSERT_GT(q.eyeZ[i], 0.0);
        }
    }
  }
}

// A step between columns 5 and 6 of an 8×8 buffer. The paper's rule leaves
// columns 5 and 6 as 16 one-pixel leaves (keyframe_lod_test); region-local
// planarity cuts exactly at the step: two leaves.
TEST(LodStrips, RegionLocalCutsOnTheStep) {
  Keyframe kf;
  kf.camera = frontCamera(8, 8);
  kf.zPrime.resize(8, 8);
  kf.covered.resize(8, 8, 1);
  kf.colour.resize(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) kf.zPrime(x, y) = (x < 6 ? 1'000'000.0 : 1'005'000.0) + 300.0 * y;
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    LodOptions o;
    o.criterion = c;
    o.planarity = Planarity::RegionLocal;
    const QuadMesh mesh = buildChecked(kf, o);
    ASSERT_EQ(mesh.quads.size(), 2u);
    EXPECT_EQ(mesh.quads[0].rect.x1, 6);
    EXPECT_EQ(mesh.quads[1].rect.x0, 6);
    EXPECT_EQ(mesh.stats.onePixelLeaves, 0);
  }
}

// A 2-wide region straddling a step has no Δ²ₓ inside it; the guard (the
// full stencils of both columns dirty) must keep it from being a leaf. It
// also splits a 2-pixel-thin object into columns (indistinguishable).
TEST(LodStrips, TwoWideRegionsDoNotStraddleSteps) {
  auto columns = [](const std::vector<double>& zCol, int h) {
    Keyframe kf;
    const int w = static_cast<int>(zCol.size());
    kf.camera = frontCamera(w, h);
    kf.zPrime.resize(w, h);
    kf.covered.resize(w, h, 1);
    kf.colour.resize(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) kf.zPrime(x, y) = zCol[static_cast<std::size_t>(x)] + 100.0 * x;
    return kf;
  };
  LodOptions o;
  o.planarity = Planarity::RegionLocal;
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    o.criterion = c;
    // A A | C | B B B B B: the first cut lands at 2, and then [2, 4) would
    // pass as a steep plane from C to B without the guard.
    for (double cz : {3e6, 1e6}) {
      const Keyframe kf = columns({2e6, 2e6, cz, 2.5e6, 2.5e6, 2.5e6, 2.5e6, 2.5e6}, 6);
      const QuadMesh mesh = buildChecked(kf, o);
      for (const Quad& q : mesh.quads) {
        const PixelRect& r = q.rect;
        EXPECT_TRUE(r.x1 <= 2 || (r.x0 == 2 && r.x1 == 3) || r.x0 >= 3)
            << "[" << r.x0 << ", " << r.x1 << ") straddles a step";
      }
    }
    // A A | B B | A A: no leaf crosses the thin object's edges.
    const Keyframe thin = columns({3e6, 3e6, 2e6, 2e6, 3e6, 3e6}, 6);
    for (bool merge : {false, true}) {
      o.mergeStrips = merge;
      const QuadMesh mesh = buildChecked(thin, o);
      for (const Quad& q : mesh.quads) {
        const PixelRect& r = q.rect;
        EXPECT_TRUE(r.x1 <= 2 || (r.x0 >= 2 && r.x1 <= 4) || r.x0 >= 4) << r.x0 << ", " << r.x1;
      }
    }
    o.mergeStrips = false;
  }
}

// The reason for the variant: on boxes in front of a wall the paper's rule
// leaves one-pixel strips along every box edge; region-local planarity does
// not, and no leaf (merged or not) straddles a depth edge.
TEST(LodStrips, RegionLocalAvoidsEdgeStripsWithoutStraddlingEdges) {
  Image<int> ids;
  const Keyframe kf = renderAnalyticKeyframe(boxesBeforeWall(), frontCamera(384, 288), true, &ids);
  for (double tau : {kTau11, kTau15})
    for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
      int quads[2][2] = {}, onePixel[2][2] = {};
      for (const Variant& v : allVariants()) {
        if (v.criterion != c) continue;
        SCOPED_TRACE(v.name() + " tau " + std::to_string(tau));
        LodBuilder builder;
        const QuadMesh mesh = buildChecked(kf, optionsFor(v, tau), &builder);
        const int p = v.planarity == Planarity::RegionLocal, m = v.merge;
        if (v.tauGradient == 0) {
          quads[p][m] = mesh.stats.quads;
          onePixel[p][m] = mesh.stats.onePixelLeaves;
        }
        // No leaf holds the wall and a box (they are apart in depth, so that
        // would be a straddled step). The plane fit over a leaf departs from
        // z' by at most 2τ (plus the merge tolerance): second differences
        // ≤ τ do not bound the residual — a crease whose slope change is
        // ≤ τ passes both rules — so the measured worst is 1 z' (paper's
        // rule) / 0.54·τ (region-local: a box's front face with the first
        // pixel of its side face, where the paper's stencil, reaching one
        // pixel further, sees the next slope change) at 2^11, and 1.25·τ /
        // 1.98·τ at 2^15 (box sides seen obliquely). A straddled step would
        // be ≥ 4·2^15.
        // With the gradient tolerance the same holds with τ replaced by the
        // leaf's largest τ + A·g.
        const double mergeTol = v.merge ? std::max(tau / 4, kMergeNoiseFloor) : 0.0;
        double worstResidual = 0, worstExcess = 0;
        int mixed = 0;
        for (const Quad& q : mesh.quads) {
          const PixelRect& r = q.rect;
          const int id = ids(r.x0, r.y0);
          float gMax = 0;
          for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
              mixed += ids(x, y) != id && ids(x, y) * id == 0;
              if (v.tauGradient > 0) gMax = std::max(gMax, builder.gradient()(x, y));
            }
          const double residual = fitResidual(kf, r);
          worstResidual = std::max(worstResidual, residual);
          worstExcess =
              std::max(worstExcess, residual - (2 * (tau + v.tauGradient * gMax) + mergeTol));
        }
        EXPECT_EQ(mixed, 0);
        EXPECT_LE(worstExcess, 0.0) << "residual beyond 2·(τ + A·g) + merge tolerance";
        std::printf("  %s tau %g: worst leaf residual %.0f z'\n", v.name().c_str(), tau,
                    worstResidual);
      }
      std::printf(
          "boxes 384x288 tau %g %s: quads / one-pixel: stencil %d/%d, +merge %d/%d; "
          "region-local %d/%d, +merge %d/%d\n",
          tau, deltaCriterionName(c), quads[0][0], onePixel[0][0], quads[0][1], onePixel[0][1],
          quads[1][0], onePixel[1][0], quads[1][1], onePixel[1][1]);
      // Measured: see the printout; the bounds leave room.
      EXPECT_LE(onePixel[1][0] * 10, onePixel[0][0]) << "region-local: < 1/10 of the strips";
      EXPECT_LT(quads[1][0], quads[0][0]);
      EXPECT_LT(quads[0][1], quads[0][0]) << "merging reduces the quad count";
      EXPECT_LE(quads[1][1], quads[1][0]);
    }
}

// Merged quads: fewer of them, each planar within the merge tolerance (the
// builder's bound is an upper bound of the real residual), and their corners
// reproject within 0.5 px (checked by buildChecked).
TEST(LodStrips, MergedQuadsArePlanarWithinTheTolerance) {
  const Keyframe kf = renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(320, 240));
  for (double tau : {kTau11, kTau15})
    for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal}) {
      SCOPED_TRACE(std::string(planarityName(p)) + " tau " + std::to_string(tau));
      LodOptions o;
      o.tau = tau;
      o.planarity = p;
      const QuadMesh plain = buildChecked(kf, o);
      o.mergeStrips = true;
      LodBuilder b;
      const QuadMesh merged = buildChecked(kf, o, &b);
      EXPECT_EQ(b.mergeToleranceZPrime(), std::max(tau / 4, kMergeNoiseFloor));
      EXPECT_EQ(b.leavesBeforeMerge(), plain.stats.quads);
      EXPECT_LT(merged.stats.quads, plain.stats.quads);
      EXPECT_LT(merged.stats.onePixelLeaves, plain.stats.onePixelLeaves);
      // Only quads the merge made (not a leaf of the plain build) are bound
      // by the tolerance; leaves themselves are bound by Δ² only.
      std::set<std::array<int, 4>> plainRects;
      for (const Quad& q : plain.quads)
        plainRects.insert({q.rect.x0, q.rect.y0, q.rect.x1, q.rect.y1});
      double worst = 0;
      int mergedCount = 0;
      for (const Quad& q : merged.quads) {
        if (plainRects.count({q.rect.x0, q.rect.y0, q.rect.x1, q.rect.y1}) != 0) continue;
        ++mergedCount;
        worst = std::max(worst, fitResidual(kf, q.rect));
      }
      EXPECT_GT(mergedCount, 0);
      EXPECT_LE(worst, b.mergeToleranceZPrime());
      std::printf(
          "room 320x240 %s tau %g: %d -> %d quads (%d merged), one-pixel %d -> %d, "
          "worst merged residual %.1f z' (tolerance %.0f)\n",
          planarityName(p), tau, plain.stats.quads, merged.stats.quads, mergedCount,
          plain.stats.onePixelLeaves, merged.stats.onePixelLeaves, worst, b.mergeToleranceZPrime());
      // A tolerance of 0 merges nothing that is not exactly coplanar; an
      // explicit one is used as given.
      o.mergeToleranceZPrime = 1e-9;
      const QuadMesh strict = buildChecked(kf, o, &b);
      EXPECT_EQ(b.mergeToleranceZPrime(), 1e-9);
      EXPECT_GE(strict.stats.quads, merged.stats.quads);
      EXPECT_LE(strict.stats.quads, plain.stats.quads);
    }
}

// A tent z' = k·|x − 7.5| leaves the paper's rule with columns 7 and 8 as
// 1×1 leaves (their stencils reach across the ridge). Each column is
// coplanar with its side: the merge stacks them into 1×16 strips, then joins
// each strip to its side's leaves: two quads, the two planes.
TEST(LodStrips, OnePixelRunsMergeIntoStripsAndPlanes) {
  Keyframe kf;
  const int w = 16, h = 16;
  kf.camera = frontCamera(w, h);
  kf.zPrime.resize(w, h);
  kf.covered.resize(w, h, 1);
  kf.colour.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) kf.zPrime(x, y) = 5e6 + 4e4 * std::fabs(x - 7.5) + 200.0 * y;
  LodOptions o;
  const QuadMesh plain = buildChecked(kf, o);
  EXPECT_GE(plain.stats.onePixelLeaves, 2 * h);
  o.mergeStrips = true;
  const QuadMesh merged = buildChecked(kf, o);
  ASSERT_EQ(merged.quads.size(), 2u);
  for (const Quad& q : merged.quads) {
    EXPECT_EQ(q.rect.width(), 8);
    EXPECT_EQ(q.rect.height(), h);
    EXPECT_TRUE(q.rect.x0 == 0 || q.rect.x0 == 8);
  }
}

TEST(LodStrips, BadMergeToleranceIsAnError) {
  const Keyframe kf = renderAnalyticKeyframe(sphereBeforeWall(), frontCamera(16, 16));
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    LodOptions o;
    o.mergeStrips = true;
    o.mergeToleranceZPrime = bad;
    const Result<QuadMesh> r = buildQuadMesh(kf, o);
    EXPECT_FALSE(r.ok());
  }
  LodOptions o;
  o.planarity = static_cast<Planarity>(9);
  EXPECT_FALSE(buildQuadMesh(kf, o).ok());
}

}  // namespace
}  // namespace hw::keyframe
