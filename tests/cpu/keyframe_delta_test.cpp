// Δ buffer (Zheng et al. 1999 eq. 3): hand-computed stencils, border
// extrapolation, coverage rules, and planes giving exactly zero.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "keyframe/delta_buffer.h"

namespace hw::keyframe {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// 4×3 test image (row 0 = top).
Image<double> smallImage() {
  const double v[3][4] = {{1, 2, 4, 8}, {3, 5, 6, 10}, {0, 7, 9, 11}};
  Image<double> z(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) z(x, y) = v[y][x];
  return z;
}

void expectImage(const Image<float>& d, const std::vector<float>& expected) {
  ASSERT_EQ(d.size(), expected.size());
  for (int y = 0; y < d.height(); ++y)
    for (int x = 0; x < d.width(); ++x)
      EXPECT_EQ(d(x, y), expected[static_cast<size_t>(y * d.width() + x)])
          << "at " << x << "," << y;
}

TEST(DeltaBuffer, FivePointMatchesHandComputedStencil) {
  const Image<double> z = smallImage();
  const Image<std::uint8_t> cov(4, 3, 1);
  Image<float> d;
  computeDeltaBuffer(z.view(), cov.view(), DeltaCriterion::FivePoint, &d);
  // Interior (1,1): 4·5 − 3 − 6 − 2 − 7 = 2. (2,1): 24 − 5 − 10 − 4 − 9 = −4.
  // Border rows have Δ²ᵧ = 0, border columns Δ²ₓ = 0 (linear extrapolation):
  // (1,0): |2·2 − 1 − 4| = 1; (0,1): |2·3 − 1 − 0| = 5; (3,1): |20 − 8 − 11| = 1;
  // (1,2): |14 − 0 − 9| = 5; corners 0.
  expectImage(d, {0, 1, 2, 0,  //
                  5, 2, 4, 1,  //
                  0, 5, 0, 0});
}

TEST(DeltaBuffer, PerAxisMaxMatchesHandComputedStencil) {
  const Image<double> z = smallImage();
  const Image<std::uint8_t> cov(4, 3, 1);
  Image<float> d;
  computeDeltaBuffer(z.view(), cov.view(), DeltaCriterion::PerAxisMax, &d);
  // (1,1): Δ²ₓ = 10 − 3 − 6 = 1, Δ²ᵧ = 10 − 2 − 7 = 1 → 1 (five-point: 2).
  // (2,1): Δ²ₓ = 12 − 5 − 10 = −3, Δ²ᵧ = 12 − 4 − 9 = −1 → 3 (five-point: 4).
  expectImage(d, {0, 1, 2, 0,  //
                  5, 1, 3, 1,  //
                  0, 5, 0, 0});
}

TEST(DeltaBuffer, EmptyPixelsAndSilhouettes) {
  const Image<double> z = smallImage();
  Image<std::uint8_t> cov(4, 3, 1);
  cov(3, 0) = 0;
  Image<float> d;
  computeDeltaBuffer(z.view(), cov.view(), DeltaCriterion::FivePoint, &d);
  expectImage(d, {0, 1, kInf, kDeltaEmpty,  //
                  5, 2, 4, kInf,            //
                  0, 5, 0, 0});
}

TEST(DeltaBuffer, NonFiniteDepthIsADiscontinuityNeverNaN) {
  Image<double> z = smallImage();
  z(0, 2) = std::nan("");
  z(3, 0) = std::numeric_limits<double>::infinity();
  const Image<std::uint8_t> cov(4, 3, 1);
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    Image<float> d;
    computeDeltaBuffer(z.view(), cov.view(), c, &d);
    for (float v : d.pixels()) EXPECT_FALSE(std::isnan(v));
    EXPECT_EQ(d(0, 2), kInf);
    EXPECT_EQ(d(0, 1), kInf);
    EXPECT_EQ(d(1, 2), kInf);
    EXPECT_EQ(d(3, 0), kInf);
    EXPECT_EQ(d(2, 0), kInf);
    EXPECT_EQ(d(3, 1), kInf);
    EXPECT_EQ(d(1, 1), c == DeltaCriterion::FivePoint ? 2.0f : 1.0f);
  }
  // Overflow of finite values is a discontinuity too.
  Image<double> big(3, 3, 1e308);
  big(1, 1) = -1e308;
  Image<float> d;
  computeDeltaBuffer(big.view(), Image<std::uint8_t>(3, 3, 1).view(), DeltaCriterion::FivePoint,
                     &d);
  for (float v : d.pixels()) EXPECT_FALSE(std::isnan(v));
  EXPECT_EQ(d(1, 1), kInf);
}

TEST(DeltaBuffer, PlaneTouchingTheBorderIsExactlyZero) {
  // Any affine z' — what a plane gives (eq. 2) — including at the borders.
  for (auto [w, h] :
       {std::pair{17, 9}, std::pair{1, 12}, std::pair{12, 1}, std::pair{1, 1}, std::pair{2, 2}}) {
    Image<double> z(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) z(x, y) = 5'000'000.0 + 1234.0 * x - 777.0 * y;
    for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
      Image<float> d;
      computeDeltaBuffer(z.view(), Image<std::uint8_t>(w, h, 1).view(), c, &d);
      for (float v : d.pixels()) EXPECT_EQ(v, 0.0f) << w << "x" << h;
    }
  }
}

TEST(DeltaBuffer, OneColumnImageUsesTheVerticalStencilOnly) {
  Image<double> z(1, 4);
  const double v[4] = {0, 1, 4, 9};  // y²: Δ²ᵧ = −2 inside
  for (int y = 0; y < 4; ++y) z(0, y) = v[y];
  Image<float> d;
  computeDeltaBuffer(z.view(), Image<std::uint8_t>(1, 4, 1).view(), DeltaCriterion::FivePoint, &d);
  expectImage(d, {0, 2, 2, 0});
}

TEST(DeltaBuffer, RespectsStridesOfSubViews) {
  Image<double> big(10, 8, 0.0);
  Image<std::uint8_t> cov(10, 8, 0);
  const Image<double> z = smallImage();
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      big(x + 3, y + 2) = z(x, y);
      cov(x + 3, y + 2) = 1;
    }
  Image<float> out(12, 9, 99.0f);
  computeDeltaBuffer(big.view().sub(3, 2, 4, 3), cov.view().sub(3, 2, 4, 3),
                     DeltaCriterion::FivePoint, out.view().sub(5, 4, 4, 3));
  Image<float> d(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) d(x, y) = out(x + 5, y + 4);
  expectImage(d, {0, 1, 2, 0, 5, 2, 4, 1, 0, 5, 0, 0});
  EXPECT_EQ(out(4, 4), 99.0f);  // untouched outside the view
  EXPECT_EQ(out(9, 4), 99.0f);
}

TEST(DeltaBuffer, ReusesTheCallersBuffer) {
  const Image<double> z = smallImage();
  const Image<std::uint8_t> cov(4, 3, 1);
  Image<float> d(4, 3);
  const float* before = d.data();
  computeDeltaBuffer(z.view(), cov.view(), DeltaCriterion::FivePoint, &d);
  EXPECT_EQ(d.data(), before);
}

TEST(DeltaBuffer, SaddleCancelsInFivePointOnly) {
  // z' = x² − y²: Δ²ₓ = 2, Δ²ᵧ = −2, so eq. (3) gives 0 inside.
  Image<double> z(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) z(x, y) = 1000.0 + x * x - y * y;
  const Image<std::uint8_t> cov(8, 8, 1);
  Image<float> five, axis;
  computeDeltaBuffer(z.view(), cov.view(), DeltaCriterion::FivePoint, &five);
  computeDeltaBuffer(z.view(), cov.view(), DeltaCriterion::PerAxisMax, &axis);
  for (int y = 1; y < 7; ++y)
    for (int x = 1; x < 7; ++x) {
      EXPECT_EQ(five(x, y), 0.0f);
      EXPECT_EQ(axis(x, y), 2.0f);
    }
}

TEST(DeltaCriterion, NamesRoundTrip) {
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    DeltaCriterion parsed =
        c == DeltaCriterion::FivePoint ? DeltaCriterion::PerAxisMax : DeltaCriterion::FivePoint;
    ASSERT_TRUE(parseDeltaCriterion(deltaCriterionName(c), &parsed));
    EXPECT_EQ(parsed, c);
  }
  DeltaCriterion untouched = DeltaCriterion::PerAxisMax;
  EXPECT_FALSE(parseDeltaCriterion("five", &untouched));
  EXPECT_FALSE(parseDeltaCriterion(nullptr, &untouched));
  EXPECT_EQ(untouched, DeltaCriterion::PerAxisMax);
}

}  // namespace
}  // namespace hw::keyframe
