// Camera maths (core/camera.h, DESIGN.md "Camera" and "Depth z'"): projection
// and unprojection are inverse, lookAt builds the frame the paper's §1.1
// describes, the GL matrices reproduce project() and eq. (2) in every depth
// mode, and the OpenCV export pose agrees with project().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "core/camera.h"

namespace hw {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// |a − b| ≤ tol · max(1, |a|, |b|): relative, with an absolute floor at 1.
::testing::AssertionResult nearRel(double a, double b, double tol) {
  const double scale = std::max({1.0, std::abs(a), std::abs(b)});
  if (std::abs(a - b) <= tol * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << a << " vs " << b << " differ by " << std::abs(a - b) << " > " << tol << " * "
         << scale;
}

::testing::AssertionResult nearVec(const glm::dvec3& a, const glm::dvec3& b, double tol) {
  const double scale = std::max({1.0, glm::length(a), glm::length(b)});
  if (glm::length(a - b) <= tol * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", "
         << b.z << "), |diff| = " << glm::length(a - b) << " > " << tol << " * " << scale;
}

// Pixel error that the rounding of a world point P (or of the eye) alone
// causes: P carries an absolute error of ~ε·(|E| + |P − E|), which moves its
// image by fx·δ·(1 + |x| + |y|)/z pixels, x = X/Z and y = Y/Z being the
// normalised image coordinates. With |E| ≈ 100 and z = 1e-3 that is ~1e-6 px
// for a narrow fov, whatever the code does; the round trips below are held to
// 1e-9 relative PLUS a small multiple of this floor.
double worldRoundingPx(const Camera& c, const glm::dvec3& P) {
  const glm::dvec3 d = P - c.eye;
  const double z = glm::dot(d, c.forward);
  const double x = glm::dot(d, c.right) / z, y = glm::dot(d, c.up) / z;
  return c.fx() * kEps * (glm::length(c.eye) + glm::length(d)) * (1.0 + std::abs(x) + std::abs(y)) /
         std::abs(z);
}

// |got − want| ≤ 1e-9·max(1, |want|) + 4 × the rounding floor above.
::testing::AssertionResult nearPx(double got, double want, const Camera& c, const glm::dvec3& P) {
  const double tol = 1e-9 * std::max(1.0, std::abs(want)) + 4.0 * worldRoundingPx(c, P);
  if (std::abs(got - want) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << got << " vs " << want << " differ by "
                                       << std::abs(got - want) << " > " << tol << " (floor "
                                       << worldRoundingPx(c, P) << ")";
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  for (;;) {
    const glm::dvec3 v{g(rng), g(rng), g(rng)};
    if (glm::length(v) > 1e-3) return glm::normalize(v);
  }
}

// Random camera: eye within ±100, any orientation, fov 5°..170°, sizes 1..4096
// (odd and even, square and not), near 1e-3..1, far up to 1e6.
Camera randomCamera(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(-100.0, 100.0);
  std::uniform_real_distribution<double> fovDeg(5.0, 170.0);
  std::uniform_int_distribution<int> size(1, 4096);
  std::uniform_real_distribution<double> logNear(-3.0, 0.0);
  std::uniform_real_distribution<double> logFarOverNear(1.0, 9.0);
  const glm::dvec3 eye{pos(rng), pos(rng), pos(rng)};
  const glm::dvec3 dir = randomUnit(rng);
  glm::dvec3 upHint = randomUnit(rng);
  while (glm::length(glm::cross(dir, upHint)) < 0.1) upHint = randomUnit(rng);
  const double n = std::pow(10.0, logNear(rng));
  const double f = std::min(1e6, n * std::pow(10.0, logFarOverNear(rng)));
  return Camera::lookAt(eye, eye + 3.0 * dir, upHint, fovDeg(rng) * kPi / 180.0, size(rng),
                        size(rng), n, f);
}

// Depths spread log-uniformly from 1e-3 to 1e6 so that near/far ratios of
// 1e9 are covered.
double randomDepth(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> e(-3.0, 6.0);
  return std::pow(10.0, e(rng));
}

TEST(Camera, LookAtBuildsOrthonormalFrame) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 eye{0.3 * i, -2.0, 7.0};
    const glm::dvec3 dir = randomUnit(rng);
    glm::dvec3 upHint = 5.0 * randomUnit(rng);  // hint need not be unit
    while (glm::length(glm::cross(dir, glm::normalize(upHint))) < 0.05) upHint = randomUnit(rng);
    const Camera c = Camera::lookAt(eye, eye + 4.0 * dir, upHint, 1.0, 64, 48, 0.1, 100.0);
    const glm::dvec3 U = c.right, V = c.up, W = c.forward;
    EXPECT_NEAR(glm::length(U), 1.0, 1e-14);
    EXPECT_NEAR(glm::length(V), 1.0, 1e-14);
    EXPECT_NEAR(glm::length(W), 1.0, 1e-14);
    EXPECT_NEAR(glm::dot(U, V), 0.0, 1e-14);
    EXPECT_NEAR(glm::dot(V, W), 0.0, 1e-14);
    EXPECT_NEAR(glm::dot(W, U), 0.0, 1e-14);
    // W points at the target (up to the rounding of target − eye, |eye| ≤ 600).
    EXPECT_TRUE(nearVec(W, dir, 1e-12));
    // lookAt builds U = W × hint / |…|, V = U × W. Then (U, V, W) is a
    // LEFT-handed triple: U × V = −W, V × W = −U, W × U = −V. Equivalently
    // (U, V, −W) is the right-handed GL eye frame and (U, −V, W) the
    // right-handed OpenCV frame.
    EXPECT_TRUE(nearVec(glm::cross(U, V), -W, 1e-14));
    EXPECT_TRUE(nearVec(glm::cross(V, W), -U, 1e-14));
    EXPECT_TRUE(nearVec(glm::cross(W, U), -V, 1e-14));
    // V lies in the plane of W and the hint, on the hint's side: "up" is up.
    EXPECT_NEAR(glm::dot(glm::cross(W, upHint), V), 0.0, 1e-12 * glm::length(upHint));
    EXPECT_GT(glm::dot(V, upHint), 0.0);
  }
}

TEST(Camera, LookAtCanonicalFrame) {
  // Looking down −Z with +Y up gives the GL default: U = +X, V = +Y, W = −Z.
  const Camera c =
      Camera::lookAt({1, 2, 3}, {1, 2, -10}, {0, 1, 0}, kPi / 2, 8, 8, 0.1, 10.0);
  EXPECT_TRUE(nearVec(c.right, {1, 0, 0}, 1e-15));
  EXPECT_TRUE(nearVec(c.up, {0, 1, 0}, 1e-15));
  EXPECT_TRUE(nearVec(c.forward, {0, 0, -1}, 1e-15));
}

TEST(Camera, IntrinsicsFromFov) {
  // fy = (N/2) / tan(α/2): the top edge of the image (v = 0) is at angle α/2
  // above W. Square pixels, principal point at the image centre.
  const Camera c = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, 640, 480, 0.1, 100);
  EXPECT_NEAR(c.fy(), 240.0 / std::tan(kPi / 6), 1e-12);
  EXPECT_EQ(c.fx(), c.fy());
  EXPECT_EQ(c.cx(), 320.0);
  EXPECT_EQ(c.cy(), 240.0);
  const glm::dvec3 top = glm::normalize(c.unproject(c.cx(), 0.0, 1.0) - c.eye);
  EXPECT_NEAR(std::acos(glm::dot(top, c.forward)), kPi / 6, 1e-14);
  EXPECT_GT(glm::dot(top, c.up), 0.0);
}

TEST(Camera, HandWorkedPixelRay) {
  // 4×2 image, vertical fov 90°, eye at the origin looking down −Z, +Y up, so
  // U = (1,0,0), V = (0,1,0), W = (0,0,−1).
  //   fy = (N/2)/tan(45°) = 1/1 = 1 = fx;  cx = M/2 = 2, cy = N/2 = 1.
  // Pixel (3, 0) is the top-right pixel; its centre is (u, v) = (3.5, 0.5).
  //   x = (u − cx)/fx = 1.5 (to the right),
  //   y = (cy − v)/fy = 0.5 (up: v grows downward, so a small v is above centre).
  // The ray is W + x·U + y·V = (1.5, 0.5, −1); at eye depth z = 2 along W the
  // point is 2·(1.5, 0.5, −1) = (3, 1, −2).
  const Camera c = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 2, 4, 2, 0.1, 100.0);
  EXPECT_NEAR(c.fx(), 1.0, 1e-15);
  EXPECT_EQ(c.cx(), 2.0);
  EXPECT_EQ(c.cy(), 1.0);
  EXPECT_TRUE(nearVec(c.unproject(3.5, 0.5, 1.0), {1.5, 0.5, -1.0}, 1e-15));
  EXPECT_TRUE(nearVec(c.unproject(3.5, 0.5, 2.0), {3.0, 1.0, -2.0}, 1e-15));
  // Pixel (0, 1), bottom-left, centre (0.5, 1.5): x = −1.5, y = −0.5.
  EXPECT_TRUE(nearVec(c.unproject(0.5, 1.5, 1.0), {-1.5, -0.5, -1.0}, 1e-15));
  // And back: (3, 1, −2) lands in the centre of pixel (3, 0) at depth 2.
  const ProjectedPoint p = c.project({3.0, 1.0, -2.0});
  EXPECT_NEAR(p.u, 3.5, 1e-15);
  EXPECT_NEAR(p.v, 0.5, 1e-15);
  EXPECT_NEAR(p.zEye, 2.0, 1e-15);
  // The same ray moved with the eye: translation does not change directions.
  const Camera c2 = Camera::lookAt({10, -4, 7}, {10, -4, 6}, {0, 1, 0}, kPi / 2, 4, 2, 0.1, 100);
  EXPECT_TRUE(nearVec(c2.unproject(3.5, 0.5, 1.0), glm::dvec3{10, -4, 7} + glm::dvec3{1.5, 0.5, -1},
                      1e-15));
}

TEST(Camera, ProjectUnprojectRoundTrip) {
  // project(unproject(u, v, z)) == (u, v, z) to 1e-9 relative. Pixels range
  // over the image and half an image beyond each edge; depths over 1e-3..1e6.
  std::mt19937_64 rng(2);
  for (int ci = 0; ci < 300; ++ci) {
    const Camera c = randomCamera(rng);
    std::uniform_real_distribution<double> du(-0.5 * c.width, 1.5 * c.width);
    std::uniform_real_distribution<double> dv(-0.5 * c.height, 1.5 * c.height);
    for (int k = 0; k < 100; ++k) {
      const double u = du(rng), v = dv(rng), z = randomDepth(rng);
      const glm::dvec3 P = c.unproject(u, v, z);
      const ProjectedPoint p = c.project(P);
      ASSERT_TRUE(nearPx(p.u, u, c, P)) << "camera " << ci << " z " << z;
      ASSERT_TRUE(nearPx(p.v, v, c, P)) << "camera " << ci << " z " << z;
      ASSERT_TRUE(nearRel(p.zEye, z, 1e-9)) << "camera " << ci;
      ASSERT_LE(std::abs(p.zEye - z), 1e-9 * z) << "camera " << ci;  // relative, no floor
    }
    // Pixel centres exactly, at the extreme depths.
    for (double z : {1e-3, 1.0, 1e6}) {
      for (int j : {0, c.height - 1}) {
        for (int i : {0, c.width - 1}) {
          const glm::dvec3 P = c.unproject(i + 0.5, j + 0.5, z);
          const ProjectedPoint p = c.project(P);
          ASSERT_TRUE(nearPx(p.u, i + 0.5, c, P));
          ASSERT_TRUE(nearPx(p.v, j + 0.5, c, P));
          ASSERT_LE(std::abs(p.zEye - z), 1e-9 * z);
        }
      }
    }
  }
}

TEST(Camera, UnprojectProjectRoundTrip) {
  // unproject(project(P)) == P for any P not in the eye's plane — in front of
  // the eye or behind it (negative z reverses the ray and the depth together).
  std::mt19937_64 rng(3);
  for (int ci = 0; ci < 300; ++ci) {
    const Camera c = randomCamera(rng);
    std::uniform_real_distribution<double> lateral(-2.0, 2.0);
    std::bernoulli_distribution behind(0.2);
    for (int k = 0; k < 100; ++k) {
      const double z = randomDepth(rng) * (behind(rng) ? -1.0 : 1.0);
      const glm::dvec3 offset =
          z * c.forward + std::abs(z) * (lateral(rng) * c.right + lateral(rng) * c.up);
      const glm::dvec3 P = c.eye + offset;
      const ProjectedPoint p = c.project(P);
      ASSERT_LE(std::abs(p.zEye - z), 1e-9 * std::abs(z));
      const glm::dvec3 back = c.unproject(p.u, p.v, p.zEye);
      // Error relative to the distance from the eye, the scale of the input.
      ASSERT_LE(glm::length(back - P), 1e-9 * glm::length(offset))
          << "camera " << ci << " z " << z;
    }
  }
}

TEST(Camera, ProjectIsInvariantAlongRay) {
  // All points of one ray through the eye project to the same pixel.
  std::mt19937_64 rng(4);
  for (int ci = 0; ci < 50; ++ci) {
    const Camera c = randomCamera(rng);
    const double u = 0.37 * c.width, v = 0.81 * c.height;
    for (double z : {1e-3, 0.5, 7.0, 1e3, 1e6}) {
      const glm::dvec3 P = c.unproject(u, v, z);
      const ProjectedPoint p = c.project(P);
      EXPECT_TRUE(nearPx(p.u, u, c, P));
      EXPECT_TRUE(nearPx(p.v, v, c, P));
    }
  }
}

// Window coordinates from a GL projection: clip = P·V·p, ndc = clip/w;
// x_w = (ndc.x+1)/2·M, y from the top = (1−ndc.y)/2·N.
struct Window {
  double u, v, depthNdc, w;
};
Window toWindow(const Camera& c, const glm::dmat4& proj, const glm::dvec3& p) {
  const glm::dvec4 clip = proj * c.viewMatrix() * glm::dvec4(p, 1.0);
  const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
  return Window{(ndc.x + 1.0) / 2.0 * c.width, (1.0 - ndc.y) / 2.0 * c.height, ndc.z, clip.w};
}

TEST(Camera, ViewMatrixIsRigidAndMapsToGlEye) {
  std::mt19937_64 rng(5);
  for (int ci = 0; ci < 200; ++ci) {
    const Camera c = randomCamera(rng);
    const glm::dmat4 m = c.viewMatrix();
    EXPECT_NEAR(glm::determinant(glm::dmat3(m)), 1.0, 1e-12);  // proper rotation
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(c.eye, 1.0)), {0, 0, 0}, 1e-12));
    // GL eye space: U → +x, V → +y, W → −z.
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(c.right, 0.0)), {1, 0, 0}, 1e-14));
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(c.up, 0.0)), {0, 1, 0}, 1e-14));
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(c.forward, 0.0)), {0, 0, -1}, 1e-14));
    EXPECT_EQ(m[0][3], 0.0);
    EXPECT_EQ(m[1][3], 0.0);
    EXPECT_EQ(m[2][3], 0.0);
    EXPECT_EQ(m[3][3], 1.0);
  }
}

TEST(Camera, GlMatricesAgreeWithProjectAndEq2) {
  // For points inside the frustum:
  //  * window (x, y) equals project()'s (u, v);
  //  * clip w equals the eye depth z;
  //  * standard modes: window depth (ndc.z+1)/2 = f/(f−n)·(1 − n/z) = z'/S
  //    (eq. 2);
  //  * reversed (glClipControl ZERO_TO_ONE, so ndc.z is the window depth):
  //    n·f/((f−n)·z) − n/(f−n) = 1 − z'/S.
  std::mt19937_64 rng(6);
  for (int ci = 0; ci < 200; ++ci) {
    const Camera c = randomCamera(rng);
    const double n = c.nearPlane, f = c.farPlane;
    const glm::dmat4 pStd = c.projectionMatrix(DepthMode::Fixed24);
    const glm::dmat4 pF32 = c.projectionMatrix(DepthMode::Float32);
    const glm::dmat4 pRev = c.projectionMatrix(DepthMode::Float32Reversed);
    // Fixed24 and Float32 store depth differently but project identically.
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) EXPECT_EQ(pStd[col][row], pF32[col][row]);

    std::uniform_real_distribution<double> du(0.0, c.width), dv(0.0, c.height);
    std::uniform_real_distribution<double> logZ(std::log(n), std::log(f));
    for (int k = 0; k < 100; ++k) {
      const double z = k == 0 ? n : k == 1 ? f : std::exp(logZ(rng));
      const glm::dvec3 P = c.unproject(du(rng), dv(rng), z);
      const ProjectedPoint pp = c.project(P);
      const double zPrimeOverS = zPrimeFromEyeZ(pp.zEye, n, f) / kZPrimeScale;

      const Window ws = toWindow(c, pStd, P);
      // The GL path computes R·P − R·E instead of R·(P − E), so it rounds
      // where project() does not: hence the rounding floor in nearPx.
      ASSERT_TRUE(nearPx(ws.u, pp.u, c, P)) << "camera " << ci;
      ASSERT_TRUE(nearPx(ws.v, pp.v, c, P)) << "camera " << ci;
      ASSERT_TRUE(nearRel(ws.w, pp.zEye, 1e-9));
      const double depthStd = (ws.depthNdc + 1.0) / 2.0;
      ASSERT_NEAR(depthStd, zPrimeOverS, 1e-9) << "camera " << ci << " z " << z;
      ASSERT_GE(depthStd, -1e-9);
      ASSERT_LE(depthStd, 1.0 + 1e-9);

      const Window wr = toWindow(c, pRev, P);
      ASSERT_TRUE(nearPx(wr.u, pp.u, c, P));
      ASSERT_TRUE(nearPx(wr.v, pp.v, c, P));
      ASSERT_NEAR(wr.depthNdc, 1.0 - zPrimeOverS, 1e-9) << "camera " << ci << " z " << z;
      ASSERT_NEAR(wr.depthNdc, n * f / ((f - n) * z) - n / (f - n), 1e-9);
    }
    // Near plane → 0 (reversed: 1), far plane → 1 (reversed: 0).
    const glm::dvec3 atNear = c.unproject(c.cx(), c.cy(), n);
    const glm::dvec3 atFar = c.unproject(c.cx(), c.cy(), f);
    EXPECT_NEAR((toWindow(c, pStd, atNear).depthNdc + 1.0) / 2.0, 0.0, 1e-9);
    EXPECT_NEAR((toWindow(c, pStd, atFar).depthNdc + 1.0) / 2.0, 1.0, 1e-9);
    EXPECT_NEAR(toWindow(c, pRev, atNear).depthNdc, 1.0, 1e-9);
    EXPECT_NEAR(toWindow(c, pRev, atFar).depthNdc, 0.0, 1e-9);
  }
}

TEST(Camera, InfiniteFarProjection) {
  // Standard, far at infinity: P[2][2] = −1, P[3][2] = −2n, so with z_gl = −z,
  //   clip.z = z − 2n, clip.w = z, ndc.z = 1 − 2n/z, window = 1 − n/z,
  // the f → ∞ limit of eq. (2)'s f/(f−n)·(1 − n/z). It is 0 at z = n and
  // tends to 1 as z → ∞ without reaching it for finite z.
  // Reversed, far at infinity: window = n/z = 1 − (standard window), the
  // f → ∞ limit of n·f/((f−n)·z) − n/(f−n).
  std::mt19937_64 rng(7);
  for (int ci = 0; ci < 100; ++ci) {
    const Camera c = randomCamera(rng);
    const double n = c.nearPlane;
    const glm::dmat4 pInf = c.projectionMatrix(DepthMode::Fixed24, true);
    const glm::dmat4 pRevInf = c.projectionMatrix(DepthMode::Float32Reversed, true);
    std::uniform_real_distribution<double> du(0.0, c.width), dv(0.0, c.height);
    double prevDepth = -1.0;
    for (double z = n; z < 1e12; z *= 3.7) {
      const glm::dvec3 P = c.unproject(du(rng), dv(rng), z);
      const ProjectedPoint pp = c.project(P);
      const Window wi = toWindow(c, pInf, P);
      ASSERT_TRUE(nearPx(wi.u, pp.u, c, P));
      ASSERT_TRUE(nearPx(wi.v, pp.v, c, P));
      const double depth = (wi.depthNdc + 1.0) / 2.0;
      ASSERT_NEAR(depth, 1.0 - n / z, 1e-9) << "z " << z;
      ASSERT_LE(depth, 1.0);
      ASSERT_GT(depth, prevDepth);  // strictly increasing with distance
      prevDepth = depth;
      // Agrees with eq. (2) for a far plane well beyond z: the difference
      // f/(f−n) − 1 = n/(f−n) vanishes as f grows.
      const double fBig = 1e9 * z;
      ASSERT_NEAR(depth, zPrimeFromEyeZ(z, n, fBig) / kZPrimeScale, 1e-8);

      const Window wr = toWindow(c, pRevInf, P);
      ASSERT_TRUE(nearPx(wr.u, pp.u, c, P));
      ASSERT_NEAR(wr.depthNdc, n / z, 1e-9);
      ASSERT_NEAR(wr.depthNdc, 1.0 - depth, 1e-9);
    }
    EXPECT_NEAR(prevDepth, 1.0, 1e-9);
  }
}

TEST(Camera, WorldFromCameraOpenCv) {
  std::mt19937_64 rng(8);
  for (int ci = 0; ci < 200; ++ci) {
    const Camera c = randomCamera(rng);
    const glm::dmat4 m = c.worldFromCameraOpenCv();
    // Camera (0,0,1) is one unit along W; the x axis is U, the y axis −V.
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(0, 0, 1, 1)), c.eye + c.forward, 1e-14));
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(0, 0, 0, 1)), c.eye, 1e-14));
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(1, 0, 0, 0)), c.right, 1e-15));
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(0, 1, 0, 0)), -c.up, 1e-15));
    EXPECT_TRUE(nearVec(glm::dvec3(m * glm::dvec4(0, 0, 1, 0)), c.forward, 1e-15));
    EXPECT_NEAR(glm::determinant(glm::dmat3(m)), 1.0, 1e-12);  // right-handed, rigid
    EXPECT_EQ(m[0][3], 0.0);
    EXPECT_EQ(m[1][3], 0.0);
    EXPECT_EQ(m[2][3], 0.0);
    EXPECT_EQ(m[3][3], 1.0);
    // The exported pose with fx, fy, cx, cy reproduces project(): the pinhole
    // model u = fx·x/z + cx, v = fy·y/z + cy in OpenCV camera coordinates.
    const glm::dmat4 camFromWorld = glm::inverse(m);
    std::uniform_real_distribution<double> du(0.0, c.width), dv(0.0, c.height);
    for (int k = 0; k < 50; ++k) {
      const double z = randomDepth(rng);
      const double u = du(rng), v = dv(rng);
      const glm::dvec3 P = c.unproject(u, v, z);
      const glm::dvec3 q = glm::dvec3(camFromWorld * glm::dvec4(P, 1.0));
      ASSERT_TRUE(nearRel(q.z, z, 1e-9));
      ASSERT_TRUE(nearPx(c.fx() * q.x / q.z + c.cx(), u, c, P));
      ASSERT_TRUE(nearPx(c.fy() * q.y / q.z + c.cy(), v, c, P));
    }
  }
}

TEST(DepthZPrime, EndpointsAndMonotone) {
  // Eq. (2): z' = S·f/(f−n)·(1 − n/z): 0 at the near plane, S at the far
  // plane, S·f/(f−n) at infinity, increasing in z.
  for (double n : {1e-3, 0.1, 1.0}) {
    for (double f : {10.0, 1000.0, 1e6}) {
      EXPECT_NEAR(zPrimeFromEyeZ(n, n, f), 0.0, 1e-6);
      EXPECT_NEAR(zPrimeFromEyeZ(f, n, f), kZPrimeScale, 1e-6);
      EXPECT_NEAR(eyeZFromZPrime(0.0, n, f), n, 1e-12 * n);
      EXPECT_NEAR(eyeZFromZPrime(kZPrimeScale, n, f), f, 1e-6 * f);
      double prev = -std::numeric_limits<double>::infinity();
      for (double z = n; z <= f; z *= 1.5) {
        const double zp = zPrimeFromEyeZ(z, n, f);
        EXPECT_GT(zp, prev);
        prev = zp;
      }
    }
  }
}

TEST(DepthZPrime, InversePairRoundTrip) {
  // eyeZFromZPrime ∘ zPrimeFromEyeZ = id. The inverse is ill-conditioned far
  // from the near plane: with t = n/z, z = n/t and t = 1 − z'(f−n)/(f·S), so
  // an absolute error of k·ε in t (rounding in either function) is a
  // relative error of k·ε/t = k·ε·z/n in z. The tolerance is that bound;
  // for z/n ≤ 1e6 it is below 1e-9.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 20000; ++k) {
    const double n = std::pow(10.0, -3.0 + 3.0 * unit(rng));
    const double f = std::min(1e6, n * std::pow(10.0, 1.0 + 8.0 * unit(rng)));
    const double z = n * std::pow(f / n, unit(rng));
    const double back = eyeZFromZPrime(zPrimeFromEyeZ(z, n, f), n, f);
    ASSERT_LE(std::abs(back - z), 16.0 * kEps * (z / n) * z) << "n " << n << " f " << f;
    if (z / n <= 1e6) {
      ASSERT_LE(std::abs(back - z), 1e-9 * z);
    }
  }
  // The other way round is well conditioned in z' units: a few ulps of S.
  for (int k = 0; k < 20000; ++k) {
    const double n = std::pow(10.0, -3.0 + 3.0 * unit(rng));
    const double f = std::min(1e6, n * std::pow(10.0, 1.0 + 8.0 * unit(rng)));
    const double zp = kZPrimeScale * unit(rng);
    const double back = zPrimeFromEyeZ(eyeZFromZPrime(zp, n, f), n, f);
    ASSERT_LE(std::abs(back - zp), 16.0 * kEps * kZPrimeScale) << "n " << n << " f " << f;
  }
}

TEST(DepthZPrime, BeyondInfinityIsInfinite) {
  // z' = S·f/(f−n) is z = ∞ (t = n/z = 0); beyond it t < 0 would unproject
  // behind the eye, so the function returns +∞ instead of a negative depth.
  const double inf = std::numeric_limits<double>::infinity();
  for (double n : {1e-3, 0.1, 1.0}) {
    for (double f : {10.0, 1000.0, 1e6}) {
      const double zpInf = kZPrimeScale * f / (f - n);
      EXPECT_EQ(eyeZFromZPrime(zpInf * (1 + 1e-12), n, f), inf);
      EXPECT_EQ(eyeZFromZPrime(zpInf + 1.0, n, f), inf);
      EXPECT_EQ(eyeZFromZPrime(2.0 * zpInf, n, f), inf);
      EXPECT_EQ(eyeZFromZPrime(1e30, n, f), inf);
      // Just below infinity: finite, positive and far beyond f.
      const double zJustBelow = eyeZFromZPrime(zpInf * (1 - 1e-9), n, f);
      EXPECT_TRUE(std::isfinite(zJustBelow));
      EXPECT_GT(zJustBelow, f);
      // Never negative for any z' (negative z' lies before the near plane).
      for (double zp = -1e7; zp < 3e7; zp += 9.7e5) EXPECT_GT(eyeZFromZPrime(zp, n, f), 0.0);
    }
  }
}

TEST(DepthMode, NameParseRoundTrip) {
  for (DepthMode m : {DepthMode::Fixed24, DepthMode::Float32, DepthMode::Float32Reversed}) {
    DepthMode parsed = m == DepthMode::Fixed24 ? DepthMode::Float32 : DepthMode::Fixed24;
    ASSERT_TRUE(parseDepthMode(depthModeName(m), &parsed)) << depthModeName(m);
    EXPECT_EQ(parsed, m);
  }
  // Names are distinct.
  EXPECT_STRNE(depthModeName(DepthMode::Fixed24), depthModeName(DepthMode::Float32));
  EXPECT_STRNE(depthModeName(DepthMode::Float32), depthModeName(DepthMode::Float32Reversed));
  EXPECT_STRNE(depthModeName(DepthMode::Fixed24), depthModeName(DepthMode::Float32Reversed));
}

TEST(DepthMode, ParseRejectsJunkAndLeavesOutputAlone) {
  for (const char* junk : {"", "fixed", "float", "Fixed24", "FLOAT32", "float32 ", " float32",
                           "float32-reverse", "float32-reversedx", "fixed24\n", "?", "24"}) {
    DepthMode out = DepthMode::Float32Reversed;
    EXPECT_FALSE(parseDepthMode(junk, &out)) << "'" << junk << "'";
    EXPECT_EQ(out, DepthMode::Float32Reversed) << "'" << junk << "'";
  }
}

TEST(Camera, LookAtRejectsDegenerateInput) {
  EXPECT_DEATH((void)Camera::lookAt({1, 2, 3}, {1, 2, 3}, {0, 1, 0}, 1.0, 8, 8, 0.1, 10),
               "CHECK failed");
  EXPECT_DEATH((void)Camera::lookAt({0, 0, 0}, {0, 5, 0}, {0, 1, 0}, 1.0, 8, 8, 0.1, 10),
               "CHECK failed");
}

}  // namespace
}  // namespace hw
