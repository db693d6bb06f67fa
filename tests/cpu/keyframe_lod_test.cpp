// LOD builder (Zheng et al. 1999 §1.2): properties of the binary subdivision
// and of the recovered quad corners on analytic depth buffers (no GL).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/file_io.h"
#include "keyframe/analytic_scene.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"

namespace hw::keyframe {
namespace {

constexpr double kTau11 = 2048.0;
constexpr double kPi = 3.141592653589793;

Camera frontCamera(int w, int h, double n = 0.1, double f = 100.0) {
  return Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, w, h, n, f);
}

AnalyticScene onePlane(const glm::dvec3& point, const glm::dvec3& normal) {
  AnalyticScene s;
  s.planes.push_back({point, glm::normalize(normal)});
  return s;
}

// Every valid pixel (covered, finite z') in exactly one leaf, others in none.
void expectTiling(const QuadMesh& mesh, const Image<double>& z, const Image<std::uint8_t>& cov) {
  const int w = z.width(), h = z.height();
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
  long long empty = 0, bad = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool valid = cov(x, y) != 0 && std::isfinite(z(x, y));
      empty += !valid;
      if (count(x, y) != (valid ? 1 : 0)) {
        if (++bad < 5)
          ADD_FAILURE() << "pixel " << x << "," << y << " in " << count(x, y) << " leaves";
      }
    }
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(mesh.stats.emptyPixels, empty);
  EXPECT_EQ(mesh.stats.quads, static_cast<int>(mesh.quads.size()));
}

// Leaves larger than one pixel are planar within τ (by the criterion used).
void expectLeavesWithinTau(const QuadMesh& mesh, const Image<float>& delta, double tau) {
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    float m = 0;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) m = std::max(m, delta(x, y));
    EXPECT_EQ(q.maxDelta, m);
    if (r.area() > 1) {
      EXPECT_LE(q.maxDelta, tau);
    }
  }
}

// Corners finite, in front of the eye, and on the rays through the rectangle
// corners: they reproject within 0.5 px.
void expectCorners(const QuadMesh& mesh, const Camera& cam) {
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
    const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
    for (int i = 0; i < 4; ++i) {
      ASSERT_TRUE(std::isfinite(q.world[i].x) && std::isfinite(q.world[i].y) &&
                  std::isfinite(q.world[i].z));
      ASSERT_TRUE(std::isfinite(q.eyeZ[i]));
      ASSERT_GT(q.eyeZ[i], 0.0);
      EXPECT_EQ(q.pixel[i].x, us[i]);
      EXPECT_EQ(q.pixel[i].y, vs[i]);
      const ProjectedPoint p = cam.project(q.world[i]);
      EXPECT_NEAR(p.u, us[i], 0.5);
      EXPECT_NEAR(p.v, vs[i], 0.5);
      EXPECT_NEAR(p.zEye, q.eyeZ[i], 1e-9 * q.eyeZ[i]);
      // The builder's hoisted unprojection agrees with Camera::unproject.
      const glm::dvec3 ref = cam.unproject(us[i], vs[i], q.eyeZ[i]);
      EXPECT_LE(glm::length(ref - q.world[i]), 1e-12 * (1.0 + glm::length(ref)));
    }
  }
}

QuadMesh buildChecked(const Keyframe& kf, const LodOptions& o) {
  LodBuilder b;
  QuadMesh mesh;
  const Status st = b.build(kf, o, &mesh);
  EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message);
  expectTiling(mesh, kf.zPrime, kf.covered);
  expectLeavesWithinTau(mesh, b.delta(), b.tauZPrime());
  expectCorners(mesh, kf.camera);
  return mesh;
}

TEST(LodBuilder, FaceOnPlaneIsOneQuadWithExactCorners) {
  const Camera cam = frontCamera(256, 192);
  const Keyframe kf = renderAnalyticKeyframe(onePlane({0, 0, -5}, {0, 0, 1}), cam);
  const QuadMesh mesh = buildChecked(kf, LodOptions{});
  ASSERT_EQ(mesh.quads.size(), 1u);
  for (const glm::dvec3& p : mesh.quads[0].world) EXPECT_NEAR(p.z, -5.0, 1e-4);
  EXPECT_EQ(mesh.stats.clampedCorners, 0);
  EXPECT_EQ(mesh.stats.tauZPrime, kTau11);
  EXPECT_EQ(mesh.stats.criterion, DeltaCriterion::FivePoint);
}

TEST(LodBuilder, ObliquePlaneIsAHandfulOfQuadsOnThePlane) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.4, 0.6, 1.0));
  const glm::dvec3 p0(0, 0, -6);
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    for (auto [w, h] : {std::pair{512, 512}, std::pair{320, 200}}) {
      const Camera cam = frontCamera(w, h);
      const Keyframe kf = renderAnalyticKeyframe(onePlane(p0, n), cam);
      ASSERT_EQ(std::count(kf.covered.pixels().begin(), kf.covered.pixels().end(), 1),
                static_cast<long>(w) * h);
      LodOptions o;
      o.criterion = c;
      const QuadMesh mesh = buildChecked(kf, o);
      EXPECT_LE(mesh.quads.size(), 4u);
      // Corners recovered from 24-bit depth lie on the plane.
      for (const Quad& q : mesh.quads)
        for (const glm::dvec3& p : q.world) EXPECT_NEAR(glm::dot(p - p0, n), 0.0, 1e-4);
    }
  }
}

// Oblique wall with a box and a sphere in front: the wall is cut into many
// leaves. Leaves entirely on the wall (at least 2×2, so the fit has both
// slopes) have every corner on the wall plane, hence neighbours meet in 3-D
// with no crack, including at T-junctions.
TEST(LodBuilder, WallLeavesShareEdgesIn3D) {
  AnalyticScene s;
  const glm::dvec3 n = glm::normalize(glm::dvec3(-0.5, 0.2, 1.0));
  const glm::dvec3 p0(0, 0, -8);
  s.planes.push_back({p0, n});
  s.boxes.push_back({{-1.5, -1.0, -5.0}, {-0.2, 0.4, -4.0}});
  s.spheres.push_back({{1.2, 0.8, -5.5}, 0.7});
  const Camera cam = frontCamera(384, 384);
  Image<int> ids;
  const Keyframe kf = renderAnalyticKeyframe(s, cam, true, &ids);
  const QuadMesh mesh = buildChecked(kf, LodOptions{});
  const double sceneSize = 10.0, tol = 1e-4 * sceneSize;
  std::map<std::pair<int, int>, glm::dvec3> cornerAt;
  int wallLeaves = 0, shared = 0;
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    if (r.width() < 2 || r.height() < 2) continue;
    bool onWall = true;
    for (int y = r.y0; y < r.y1 && onWall; ++y)
      for (int x = r.x0; x < r.x1 && onWall; ++x) onWall = ids(x, y) == 0;
    if (!onWall) continue;
    ++wallLeaves;
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(glm::dot(q.world[i] - p0, n), 0.0, tol);
      const auto key = std::pair{int(q.pixel[i].x), int(q.pixel[i].y)};
      const auto [it, inserted] = cornerAt.emplace(key, q.world[i]);
      if (!inserted) {
        ++shared;
        EXPECT_LT(glm::length(it->second - q.world[i]), tol);
      }
    }
  }
  EXPECT_GE(wallLeaves, 5);
  EXPECT_GE(shared, 4);
  EXPECT_GT(mesh.stats.onePixelLeaves, 0);  // silhouettes of the box and sphere
}

TEST(LodBuilder, FollowsThePapersCutRule) {
  // A step between columns 5 and 6 (8×8): columns 5 and 6 are dirty.
  const Camera cam = frontCamera(8, 8);
  Image<double> z(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) z(x, y) = x < 6 ? 1'000'000.0 : 1'005'000.0;
  const Image<std::uint8_t> cov(8, 8, 1);
  LodBuilder b;
  QuadMesh mesh;
  ASSERT_TRUE(b.build(z.view(), cov.view(), cam, LodOptions{}, &mesh).ok());
  expectTiling(mesh, z, cov);
  auto has = [&](int x0, int y0, int x1, int y1) {
    return std::any_of(mesh.quads.begin(), mesh.quads.end(), [&](const Quad& q) {
      return q.rect.x0 == x0 && q.rect.y0 == y0 && q.rect.x1 == x1 && q.rect.y1 == y1;
    });
  };
  // x cut: 5 clean columns from the left (≥ 8/4) → cut after them.
  EXPECT_TRUE(has(0, 0, 5, 8));
  // Right part [5,8): y cut, every row dirty → middle (4). Then x cuts: one
  // clean column from the right end (≥ 3/4) → cut before it.
  EXPECT_TRUE(has(7, 0, 8, 4));
  EXPECT_TRUE(has(7, 4, 8, 8));
  EXPECT_EQ(mesh.stats.onePixelLeaves, 16);  // columns 5 and 6
  EXPECT_EQ(mesh.quads.size(), 19u);
}

TEST(LodBuilder, PerAxisMaxSplitsASaddleThatFivePointMisses) {
  // z' = C + k·((x − cx)² − (y − cy)²): Δ²ₓ = 2k, Δ²ᵧ = −2k, eq. (3) gives 0.
  const int w = 64, h = 64;
  const double k = kTau11;  // |Δ²ₓ| = 2τ
  const Camera cam = frontCamera(w, h);
  Image<double> z(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double dx = x - 31.5, dy = y - 31.5;
      z(x, y) = 8'000'000.0 + k * (dx * dx - dy * dy);
    }
  const Image<std::uint8_t> cov(w, h, 1);
  LodOptions o;
  o.criterion = DeltaCriterion::FivePoint;
  const Result<QuadMesh> five = buildQuadMesh(z.view(), cov.view(), cam, o);
  o.criterion = DeltaCriterion::PerAxisMax;
  const Result<QuadMesh> axis = buildQuadMesh(z.view(), cov.view(), cam, o);
  ASSERT_TRUE(five.ok() && axis.ok());
  expectTiling(five.value(), z, cov);
  expectTiling(axis.value(), z, cov);
  EXPECT_EQ(axis->stats.criterion, DeltaCriterion::PerAxisMax);
  // Five-point: only the border ring (where extrapolation makes one axis 0)
  // is dirty; the interior is a few big leaves.
  long long biggest = 0, inBigLeaves = 0;
  for (const Quad& q : five.value().quads) {
    biggest = std::max(biggest, q.rect.area());
    if (q.rect.area() >= 16) inBigLeaves += q.rect.area();
  }
  EXPECT_GE(biggest, 15 * 15);
  EXPECT_GE(inBigLeaves, w * h * 8 / 10);
  EXPECT_LE(five.value().quads.size(), static_cast<size_t>(w) * h / 8);
  // Per-axis: every pixel is dirty, every leaf is one pixel.
  EXPECT_EQ(axis->quads.size(), static_cast<size_t>(w) * h);
  EXPECT_EQ(axis->stats.onePixelLeaves, w * h);
}

TEST(LodBuilder, RoomSceneProperties) {
  const AnalyticScene s = makeRoomScene();
  for (auto [w, h] : {std::pair{256, 256}, std::pair{300, 170}}) {
    const Keyframe kf = renderAnalyticKeyframe(s, makeRoomCamera(w, h));
    size_t prev = std::numeric_limits<size_t>::max();
    for (double tau : {256.0, 2048.0, 32768.0, 65536.0}) {
      for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
        LodOptions o;
        o.tau = tau;
        o.criterion = c;
        const QuadMesh mesh = buildChecked(kf, o);
        EXPECT_GT(mesh.quads.size(), 10u);
        EXPECT_LT(mesh.quads.size(), static_cast<size_t>(w) * h / 4);
        if (c == DeltaCriterion::FivePoint) {
          EXPECT_LE(mesh.quads.size(), prev) << "larger τ, fewer quads";
          prev = mesh.quads.size();
        }
      }
    }
  }
}

TEST(LodBuilder, RandomDepthAndCoverage) {
  std::mt19937 rng(12345);
  for (int iter = 0; iter < 40; ++iter) {
    const int w = 1 + static_cast<int>(rng() % 70), h = 1 + static_cast<int>(rng() % 70);
    const Camera cam = frontCamera(w, h);
    Image<double> z(w, h);
    Image<std::uint8_t> cov(w, h);
    const int mode = iter % 4;
    std::uniform_real_distribution<double> uni(0.0, kZPrimeScale);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        // Mixtures of smooth planes, noise, holes and non-finite values.
        const double plane = 4e6 + 1500.0 * x + 700.0 * y + ((x / 9 + y / 7) % 2) * 3e5;
        z(x, y) = mode == 0 ? uni(rng) : std::round(plane + (rng() % 3 == 0 ? uni(rng) * 1e-3 : 0));
        cov(x, y) = (rng() % 10) < (mode == 2 ? 5u : 9u);
        if (mode == 3 && rng() % 50 == 0)
          z(x, y) = (rng() % 2) ? std::nan("") : std::numeric_limits<double>::infinity();
        if (mode == 3 && rng() % 60 == 0) z(x, y) = (rng() % 2 ? 1 : -1) * 1e300;
      }
    for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
      LodOptions o;
      o.criterion = c;
      o.tau = std::ldexp(1.0, static_cast<int>(rng() % 17));
      LodBuilder b;
      QuadMesh mesh;
      ASSERT_TRUE(b.build(z.view(), cov.view(), cam, o, &mesh).ok());
      expectTiling(mesh, z, cov);
      expectLeavesWithinTau(mesh, b.delta(), b.tauZPrime());
      expectCorners(mesh, cam);
    }
  }
}

TEST(LodBuilder, CornersPastInfinityAreClamped) {
  // An affine z' ramp (one leaf) whose top edge extrapolates half a pixel
  // past z' = S·f/(f−n) — depth beyond infinity, as near a horizon — and whose
  // bottom rows are in front of the near plane (z' < 0).
  const int w = 64, h = 256;
  const Camera cam = frontCamera(w, h, 0.1, 1000.0);
  const double zInf = kZPrimeScale * cam.farPlane / (cam.farPlane - cam.nearPlane);
  const double k = 1e5;
  Image<double> z(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) z(x, y) = zInf - k * (y + 0.5 - 0.3);
  const Image<std::uint8_t> cov(w, h, 1);
  LodOptions o;
  o.tau = 32768;
  const Result<QuadMesh> mesh = buildQuadMesh(z.view(), cov.view(), cam, o);
  ASSERT_TRUE(mesh.ok());
  expectTiling(mesh.value(), z, cov);
  expectCorners(mesh.value(), cam);
  EXPECT_LE(mesh.value().quads.size(), 4u);
  EXPECT_GE(mesh.value().stats.clampedCorners, 2);  // the two top corners
  for (const Quad& q : mesh.value().quads)
    for (double ze : q.eyeZ) {
      EXPECT_LE(ze, 100.0 * cam.farPlane);
      EXPECT_GE(ze, 0.5 * cam.nearPlane);
    }
}

TEST(LodBuilder, FloorUpToTheHorizonHasFiniteCorners) {
  AnalyticScene s = onePlane({0, 0, 0}, {0, 1, 0});
  for (double far : {1000.0, 1e6}) {
    const Camera cam =
        Camera::lookAt({0, 1.7, 0}, {0, 1.6, -1}, {0, 1, 0}, kPi / 3, 256, 256, 0.1, far);
    const Keyframe kf = renderAnalyticKeyframe(s, cam);
    for (double tau : {2048.0, 32768.0, 1e9}) {
      LodOptions o;
      o.tau = tau;
      const QuadMesh mesh = buildChecked(kf, o);
      EXPECT_GT(mesh.quads.size(), 0u);
      for (const Quad& q : mesh.quads)
        for (double ze : q.eyeZ) EXPECT_LE(ze, 100.0 * far);
    }
  }
}

TEST(LodBuilder, ParallaxThresholdIsConvertedAndReported) {
  const Keyframe kf = renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(128, 128));
  LodOptions o;
  o.tau = 1.0;  // ignored
  o.tauParallaxPx = 0.01;
  const Camera& c = kf.camera;
  const double expected =
      0.01 * kZPrimeScale * c.farPlane * c.nearPlane / (c.fx() * (c.farPlane - c.nearPlane));
  const QuadMesh mesh = buildChecked(kf, o);
  EXPECT_DOUBLE_EQ(mesh.stats.tauZPrime, expected);
  EXPECT_EQ(mesh.stats.tauParallaxPx, 0.01);
  EXPECT_DOUBLE_EQ(tauFromParallax(0.01, c), expected);
  // The same bound means the same thing with a 10× larger near plane: the
  // z'-unit threshold scales with n (Δ²z' ∝ n·Δ²(1/z)).
  Camera c10 = c;
  c10.nearPlane *= 10;
  EXPECT_NEAR(tauFromParallax(0.01, c10) / expected,
              10.0 * (c.farPlane - c.nearPlane) / (c.farPlane - c10.nearPlane), 1e-12);
}

TEST(LodBuilder, ThinImages) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.4, 0.6, 1.0));
  for (auto [w, h] : {std::pair{1, 97}, std::pair{97, 1}, std::pair{1, 1}, std::pair{2, 1}}) {
    const Camera cam = frontCamera(w, h);
    AnalyticScene s = onePlane({0, 0, -6}, n);
    s.spheres.push_back({{0, 0, -3}, 0.3});
    const Keyframe kf = renderAnalyticKeyframe(s, cam);
    for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
      LodOptions o;
      o.criterion = c;
      const QuadMesh mesh = buildChecked(kf, o);
      EXPECT_GE(mesh.quads.size(), 1u);
    }
  }
}

TEST(LodBuilder, AllEmptyIsAValidEmptyMesh) {
  const Camera cam = frontCamera(33, 21);
  const Keyframe kf = renderAnalyticKeyframe(AnalyticScene{}, cam);
  const Result<QuadMesh> mesh = buildQuadMesh(kf, LodOptions{});
  ASSERT_TRUE(mesh.ok());
  EXPECT_TRUE(mesh->quads.empty());
  EXPECT_EQ(mesh->stats.emptyPixels, 33 * 21);
  EXPECT_EQ(mesh->width, 33);
}

TEST(LodBuilder, SphereInTheVoid) {
  AnalyticScene s;
  s.spheres.push_back({{0.3, -0.2, -4}, 1.2});
  const Keyframe kf = renderAnalyticKeyframe(s, frontCamera(200, 150));
  for (double tau : {16.0, 2048.0, 32768.0}) {
    LodOptions o;
    o.tau = tau;
    const QuadMesh mesh = buildChecked(kf, o);
    EXPECT_GT(mesh.stats.emptyPixels, 0);
  }
}

TEST(LodBuilder, BadInputIsAnError) {
  const Camera cam = frontCamera(16, 12);
  Keyframe kf = renderAnalyticKeyframe(onePlane({0, 0, -5}, {0, 0, 1}), cam);
  auto fails = [](const Result<QuadMesh>& r, const char* what) {
    EXPECT_FALSE(r.ok()) << what;
    if (!r.ok()) {
      EXPECT_NE(r.error().message.find("LOD builder"), std::string::npos);
    }
  };
  {
    Keyframe k = kf;
    k.colour.resize(15, 12);
    fails(buildQuadMesh(k, LodOptions{}), "colour size");
  }
  {
    Keyframe k = kf;
    k.zPrime.resize(16, 11);
    fails(buildQuadMesh(k, LodOptions{}), "depth size");
  }
  {
    Keyframe k = kf;
    k.covered.resize(17, 12);
    fails(buildQuadMesh(k, LodOptions{}), "mask size");
  }
  {
    Keyframe k = kf;
    k.camera.width = 32;
    fails(buildQuadMesh(k, LodOptions{}), "camera size");
  }
  {
    Keyframe k = kf;
    k.camera.nearPlane = 0;
    fails(buildQuadMesh(k, LodOptions{}), "near");
    k.camera.nearPlane = 200;
    fails(buildQuadMesh(k, LodOptions{}), "near > far");
    k = kf;
    k.camera.fovYRadians = kPi;
    fails(buildQuadMesh(k, LodOptions{}), "fov");
    k = kf;
    k.camera.eye.x = std::nan("");
    fails(buildQuadMesh(k, LodOptions{}), "eye");
  }
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    LodOptions o;
    o.tau = bad;
    fails(buildQuadMesh(kf, o), "tau");
    o = LodOptions{};
    o.tauParallaxPx = bad;
    fails(buildQuadMesh(kf, o), "tauParallaxPx");
  }
  {
    LodOptions o;
    o.criterion = static_cast<DeltaCriterion>(7);
    fails(buildQuadMesh(kf, o), "criterion");
  }
  {
    Keyframe k;
    k.camera = cam;
    k.camera.width = 0;
    k.camera.height = 0;
    fails(buildQuadMesh(k, LodOptions{}), "0 pixels");
  }
  // A failed build leaves the output empty.
  LodBuilder b;
  QuadMesh mesh;
  ASSERT_TRUE(b.build(kf, LodOptions{}, &mesh).ok());
  ASSERT_FALSE(mesh.quads.empty());
  LodOptions o;
  o.tau = -1;
  EXPECT_FALSE(b.build(kf, o, &mesh).ok());
  EXPECT_TRUE(mesh.quads.empty());
}

TEST(LodBuilder, NonFiniteDepthIsEmpty) {
  const Camera cam = frontCamera(40, 30);
  Keyframe kf = renderAnalyticKeyframe(onePlane({0, 0, -5}, {0.2, 0.1, 1}), cam);
  kf.zPrime(3, 4) = std::nan("");
  kf.zPrime(20, 15) = std::numeric_limits<double>::infinity();
  kf.zPrime(39, 29) = -std::numeric_limits<double>::infinity();
  const QuadMesh mesh = buildChecked(kf, LodOptions{});
  EXPECT_EQ(mesh.stats.emptyPixels, 3);
}

TEST(LodBuilder, ReusedBuilderGivesTheSameMeshWithoutReallocating) {
  const Keyframe kf = renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(160, 120));
  LodBuilder b;
  QuadMesh m1, m2;
  ASSERT_TRUE(b.build(kf, LodOptions{}, &m1).ok());
  const float* deltaData = b.delta().data();
  ASSERT_TRUE(b.build(kf, LodOptions{}, &m2).ok());
  EXPECT_EQ(b.delta().data(), deltaData);
  ASSERT_EQ(m1.quads.size(), m2.quads.size());
  for (size_t i = 0; i < m1.quads.size(); ++i) {
    EXPECT_EQ(m1.quads[i].rect.x0, m2.quads[i].rect.x0);
    EXPECT_EQ(m1.quads[i].world[2], m2.quads[i].world[2]);
  }
  // Steps run separately give the same as build().
  QuadMesh m3;
  ASSERT_TRUE(b.prepare(kf.zPrime.view(), kf.covered.view(), kf.camera, LodOptions{}).ok());
  b.subdivide();
  b.recoverCorners(&m3);
  EXPECT_EQ(m3.quads.size(), m1.quads.size());
}

TEST(Overlay, OutlinesTintsAndDims) {
  AnalyticScene s = onePlane({0, 0, -5}, {0, 0, 1});
  s.spheres.push_back({{0, 0, -3}, 0.5});
  Camera cam = frontCamera(64, 48);
  Keyframe kf = renderAnalyticKeyframe(s, cam);
  kf.covered(0, 0) = 0;  // one empty pixel
  const QuadMesh mesh = buildChecked(kf, LodOptions{});
  OverlayOptions o;
  const Image<Rgba8> img = drawQuadOverlay(kf.colour, mesh, o);
  ASSERT_EQ(img.width(), 64);
  long long outline = 0;
  for (const Rgba8& p : img.pixels()) outline += p == o.outline;
  EXPECT_GT(outline, 0);
  EXPECT_LT(outline, 64 * 48);
  EXPECT_EQ(img(0, 0).r, static_cast<std::uint8_t>(kf.colour(0, 0).r * o.emptyDim));
  for (const Quad& q : mesh.quads) {
    if (q.rect.area() == 1) {
      EXPECT_NE(img(q.rect.x0, q.rect.y0), kf.colour(q.rect.x0, q.rect.y0));
    } else {
      EXPECT_EQ(img(q.rect.x0, q.rect.y0), o.outline);
    }
  }
  LodBuilder b;
  QuadMesh m;
  ASSERT_TRUE(b.build(kf, LodOptions{}, &m).ok());
  DeltaImageOptions dopt;
  dopt.tau = 2048;
  const Image<Rgba8> d = deltaToImage(b.delta().view(), dopt);
  EXPECT_EQ(d(0, 0), dopt.empty);
  EXPECT_EQ(d(1, 0), dopt.discontinuity);
  EXPECT_EQ(d(30, 5), (Rgba8{0, 0, 0, 255}));  // a plane: Δ² = 0
  // Pictures for a human (like Plate I-A); not compared.
  const std::string dir = ::testing::TempDir();
  const Keyframe room = renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(512, 512));
  for (double tau : {2048.0, 32768.0}) {
    LodOptions lo;
    lo.tau = tau;
    ASSERT_TRUE(b.build(room, lo, &m).ok());
    const std::string tag = std::to_string(int(tau));
    EXPECT_TRUE(
        writePng(dir + "/lod_room_overlay_" + tag + ".png", drawQuadOverlay(room.colour, m)).ok());
  }
  EXPECT_TRUE(writePng(dir + "/lod_room_delta.png", deltaToImage(b.delta().view())).ok());
}

}  // namespace
}  // namespace hw::keyframe
