// convertDepth (core/depth.h): raw depth readback → z' (eq. 2, 2^24 units),
// eye z and coverage, for the three depth modes. The raw buffers are built
// from the analytic window-depth formulas of each mode (DESIGN.md "Depth z'"),
// so every expectation is a property of eq. (2), not a recorded number.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "core/camera.h"
#include "core/depth.h"

namespace hw {
namespace {

constexpr double kFloatEps = std::numeric_limits<float>::epsilon();  // 2^-23

struct Out {
  Image<double> zPrime;
  Image<float> eyeZ;
  Image<std::uint8_t> covered;
};

template <class T>
Out convert(const std::vector<T>& raw, int w, int h, DepthMode mode, double n, double f) {
  Out o;
  convertDepth(raw.data(), w, h, mode, n, f, o.zPrime, o.eyeZ, o.covered);
  return o;
}

// Standard window depth f/(f−n)·(1 − n/z) = z'/S (eq. 2).
double standardWindowDepth(double z, double n, double f) { return f / (f - n) * (1.0 - n / z); }
// Reversed-Z window depth (glClipControl ZERO_TO_ONE): n·f/((f−n)·z) − n/(f−n).
double reversedWindowDepth(double z, double n, double f) {
  return n * f / ((f - n) * z) - n / (f - n);
}

void expectEmpty(const Out& o, int x, int y) {
  EXPECT_EQ(o.covered(x, y), 0) << "(" << x << ", " << y << ")";
  EXPECT_EQ(o.zPrime(x, y), kZPrimeScale) << "(" << x << ", " << y << ")";
  EXPECT_EQ(o.eyeZ(x, y), 0.0f) << "(" << x << ", " << y << ")";
}

struct Planes {
  double n, f;
};
const Planes kPlanes[] = {{0.1, 1000.0}, {1.0, 10.0}, {1e-3, 1e6}, {0.5, 2.0}};

TEST(ConvertDepth, Fixed24GivesD24Exactly) {
  // Fixed24 read as GL_UNSIGNED_INT: the top 24 bits are the depth, so
  // uint32 = d24 << 8 must give z' = d24 exactly and eye z = eyeZFromZPrime.
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::uint32_t> d24dist(0, 0xFFFFFEu);
  for (const Planes& pl : kPlanes) {
    const int w = 37, h = 23;
    std::vector<std::uint32_t> raw(w * h);
    std::vector<std::uint32_t> d24(w * h);
    for (int i = 0; i < w * h; ++i) {
      d24[i] = i == 0 ? 0u : i == 1 ? 0xFFFFFEu : d24dist(rng);
      // Low 8 bits (stencil / conversion bits) must not matter.
      raw[i] = (d24[i] << 8) | static_cast<std::uint32_t>(i % 256);
    }
    const Out o = convert(raw, w, h, DepthMode::Fixed24, pl.n, pl.f);
    for (int gy = 0; gy < h; ++gy) {
      for (int x = 0; x < w; ++x) {
        const int y = h - 1 - gy;
        const double zp = static_cast<double>(d24[gy * w + x]);
        ASSERT_EQ(o.covered(x, y), 1);
        ASSERT_EQ(o.zPrime(x, y), zp);
        ASSERT_EQ(o.eyeZ(x, y), static_cast<float>(eyeZFromZPrime(zp, pl.n, pl.f)));
      }
    }
    EXPECT_NEAR(o.eyeZ(0, h - 1), pl.n, 1e-6 * pl.n);  // d24 = 0 is the near plane
  }
}

TEST(ConvertDepth, Fixed24FromGlUnsignedIntConversion) {
  // What GL really returns for GL_UNSIGNED_INT from a 24-bit buffer:
  // round(d24 / (2^24−1) · (2^32−1)) = 256·d24 + round(d24·255/(2^24−1)), and
  // the second term is < 256, so the top 24 bits are still d24. The geometry
  // z' then matches eq. (2) to the 24-bit rounding (half a unit).
  const double n = 0.1, f = 1000.0;
  std::mt19937 rng(12);
  // Up to 0.999·f: at f itself d24 rounds to the clear value.
  std::uniform_real_distribution<double> logZ(std::log(n), std::log(0.999 * f));
  const int w = 64, h = 16;
  std::vector<std::uint32_t> raw(w * h);
  std::vector<double> zs(w * h), d24s(w * h);
  for (int i = 0; i < w * h; ++i) {
    zs[i] = std::exp(logZ(rng));
    d24s[i] = std::round(standardWindowDepth(zs[i], n, f) * kZPrimeScale);
    raw[i] = static_cast<std::uint32_t>(std::round(d24s[i] / kZPrimeScale * 4294967295.0));
  }
  const Out o = convert(raw, w, h, DepthMode::Fixed24, n, f);
  for (int gy = 0; gy < h; ++gy) {
    for (int x = 0; x < w; ++x) {
      const int y = h - 1 - gy;
      const double z = zs[gy * w + x];
      ASSERT_EQ(o.covered(x, y), 1);
      ASSERT_EQ(o.zPrime(x, y), d24s[gy * w + x]);
      ASSERT_LE(std::abs(o.zPrime(x, y) - zPrimeFromEyeZ(z, n, f)), 0.5 + 1e-6);
    }
  }
}

TEST(ConvertDepth, Fixed24ClearValueIsEmpty) {
  // Clear to depth 1.0: 0xFFFFFF00 (d24 << 8) or 0xFFFFFFFF (GL's full-range
  // uint conversion of 1.0). Both are the far plane: empty.
  const int w = 4, h = 3;
  std::vector<std::uint32_t> raw(w * h, 0xFFFFFF00u);
  raw[1] = 0xFFFFFFFFu;
  raw[2] = 0xFFFFFF7Fu;
  raw[5] = 0x00000000u;  // near plane: covered
  const Out o = convert(raw, w, h, DepthMode::Fixed24, 0.1, 100.0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x == 1 && y == h - 1 - 1) {  // raw[5]: GL row 1, column 1
        EXPECT_EQ(o.covered(x, y), 1);
        EXPECT_EQ(o.zPrime(x, y), 0.0);
        EXPECT_NEAR(o.eyeZ(x, y), 0.1, 1e-7);
      } else {
        expectEmpty(o, x, y);
      }
    }
  }
}

TEST(ConvertDepth, Float32FromAnalyticDepth) {
  // Float32: window depth d = f/(f−n)·(1 − n/z) stored as float. z' = d·S
  // exactly (in double), eye z = eyeZFromZPrime(z'), and z' is within one
  // unit of eq. (2) (float rounding of d ≤ 2^-25 for d in [0.5, 1), so
  // |Δz'| ≤ S·2^-25 < 1; smaller for smaller d). Eye z: a relative error δ
  // in d gives δ·d/(d_∞ − d) ≈ δ·z/n relative in z.
  std::mt19937 rng(13);
  for (const Planes& pl : kPlanes) {
    std::uniform_real_distribution<double> logZ(std::log(pl.n), std::log(pl.f));
    const int w = 33, h = 17;
    std::vector<float> raw(w * h);
    std::vector<double> zs(w * h);
    for (int i = 0; i < w * h; ++i) {
      zs[i] = i == 0 ? pl.n : std::exp(logZ(rng));
      raw[i] = static_cast<float>(standardWindowDepth(zs[i], pl.n, pl.f));
      if (raw[i] >= 1.0f) {  // at the far plane in float: would be empty
        zs[i] = pl.n;
        raw[i] = 0.0f;
      }
    }
    const Out o = convert(raw, w, h, DepthMode::Float32, pl.n, pl.f);
    for (int gy = 0; gy < h; ++gy) {
      for (int x = 0; x < w; ++x) {
        const int y = h - 1 - gy;
        const int i = gy * w + x;
        const double z = zs[i];
        ASSERT_EQ(o.covered(x, y), 1);
        const double zp = static_cast<double>(raw[i]) * kZPrimeScale;
        ASSERT_EQ(o.zPrime(x, y), zp);
        ASSERT_LE(std::abs(o.zPrime(x, y) - zPrimeFromEyeZ(z, pl.n, pl.f)), 1.0);
        ASSERT_EQ(o.eyeZ(x, y), static_cast<float>(eyeZFromZPrime(zp, pl.n, pl.f)));
        // Bound 2^-24·(1 + z/n) (d rounding, then z rounding to float), doubled
        // for the second-order terms.
        ASSERT_LE(std::abs(o.eyeZ(x, y) - z), kFloatEps * (1.0 + z / pl.n) * z)
            << "n " << pl.n << " f " << pl.f << " z " << z;
      }
    }
  }
}

TEST(ConvertDepth, Float32ClearAndOutOfRangeAreEmpty) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> raw = {1.0f, nan, inf, -inf, 1.5f, -0.25f, 0.5f, 0.0f};
  const Out o = convert(raw, 8, 1, DepthMode::Float32, 0.1, 100.0);
  for (int x = 0; x < 6; ++x) expectEmpty(o, x, 0);
  EXPECT_EQ(o.covered(6, 0), 1);
  EXPECT_EQ(o.zPrime(6, 0), 0.5 * kZPrimeScale);
  EXPECT_EQ(o.covered(7, 0), 1);
  EXPECT_EQ(o.zPrime(7, 0), 0.0);
  EXPECT_NEAR(o.eyeZ(7, 0), 0.1, 1e-7);
  // The largest float below 1 is still geometry.
  const std::vector<float> justBelow = {std::nextafter(1.0f, 0.0f)};
  const Out b = convert(justBelow, 1, 1, DepthMode::Float32, 0.1, 100.0);
  EXPECT_EQ(b.covered(0, 0), 1);
  EXPECT_LT(b.zPrime(0, 0), kZPrimeScale);
  EXPECT_GT(b.eyeZ(0, 0), 99.0f);
}

TEST(ConvertDepth, Float32ReversedFromAnalyticDepth) {
  // Reversed: d = n·f/((f−n)·z) − n/(f−n) stored as float; z' = (1 − d)·S,
  // within one unit of eq. (2). Eye z comes from d directly,
  // z = n·f/((f−n)·d + n): a relative error δ in d gives at most δ relative
  // in z, so eye z is good to float precision at every distance — the point
  // of reversed Z. Bound: rounding d to float (≤ 2^-24 relative) plus
  // rounding z to float (≤ 2^-24): 2^-23 = FLT_EPSILON, plus double noise.
  std::mt19937 rng(14);
  for (const Planes& pl : kPlanes) {
    std::uniform_real_distribution<double> logZ(std::log(pl.n), std::log(pl.f));
    const int w = 29, h = 19;
    std::vector<float> raw(w * h);
    std::vector<double> zs(w * h);
    for (int i = 0; i < w * h; ++i) {
      zs[i] = i == 0 ? pl.n : std::exp(logZ(rng));
      raw[i] = static_cast<float>(reversedWindowDepth(zs[i], pl.n, pl.f));
      if (raw[i] <= 0.0f) {  // at the far plane: would be empty
        zs[i] = pl.n;
        raw[i] = 1.0f;
      }
    }
    const Out o = convert(raw, w, h, DepthMode::Float32Reversed, pl.n, pl.f);
    for (int gy = 0; gy < h; ++gy) {
      for (int x = 0; x < w; ++x) {
        const int y = h - 1 - gy;
        const int i = gy * w + x;
        const double z = zs[i];
        ASSERT_EQ(o.covered(x, y), 1);
        ASSERT_EQ(o.zPrime(x, y), (1.0 - static_cast<double>(raw[i])) * kZPrimeScale);
        ASSERT_LE(std::abs(o.zPrime(x, y) - zPrimeFromEyeZ(z, pl.n, pl.f)), 1.0)
            << "n " << pl.n << " f " << pl.f << " z " << z;
        ASSERT_LE(std::abs(o.eyeZ(x, y) - z), (1.0 + 1e-9) * kFloatEps * z)
            << "n " << pl.n << " f " << pl.f << " z " << z;
      }
    }
    EXPECT_NEAR(o.eyeZ(0, h - 1), pl.n, 0.5 * kFloatEps * pl.n);  // d = 1: near plane
  }
}

TEST(ConvertDepth, Float32ReversedClearAndOutOfRangeAreEmpty) {
  // Reversed clears to 0 (far). NaN, ±inf, negative and > 1 are not depths.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> raw = {0.0f, -0.0f, nan, inf, -inf, -0.5f, 1.5f, 1.0f, 0.25f};
  const double n = 0.1, f = 100.0;
  const Out o = convert(raw, 9, 1, DepthMode::Float32Reversed, n, f);
  for (int x = 0; x < 7; ++x) expectEmpty(o, x, 0);
  EXPECT_EQ(o.covered(7, 0), 1);
  EXPECT_EQ(o.zPrime(7, 0), 0.0);
  EXPECT_NEAR(o.eyeZ(7, 0), n, 1e-7);
  EXPECT_EQ(o.covered(8, 0), 1);
  EXPECT_NEAR(o.eyeZ(8, 0), n * f / ((f - n) * 0.25 + n), 1e-5);
  // The smallest positive (subnormal) float is geometry just inside far.
  const std::vector<float> tiny = {std::numeric_limits<float>::denorm_min()};
  // (Covered even though its z' rounds to S: coverage, not z', says empty.)
  const Out t = convert(tiny, 1, 1, DepthMode::Float32Reversed, n, f);
  EXPECT_EQ(t.covered(0, 0), 1);
  EXPECT_NEAR(t.eyeZ(0, 0), f, 1e-3);
  EXPECT_NEAR(t.zPrime(0, 0), kZPrimeScale, 1e-6);
}

TEST(ConvertDepth, ModesAgreeOnZPrime) {
  // The same surface drawn in each mode maps to the same z' within the
  // storage rounding (≤ 1 unit), so one threshold τ means the same thing in
  // all three (DESIGN.md "Depth z'").
  const double n = 0.1, f = 500.0;
  const int w = 50, h = 1;
  std::vector<std::uint32_t> raw24(w);
  std::vector<float> raw32(w), rawRev(w);
  for (int x = 0; x < w; ++x) {
    const double z = n * std::pow(0.999 * f / n, x / (w - 1.0));
    raw24[x] = static_cast<std::uint32_t>(std::round(standardWindowDepth(z, n, f) * kZPrimeScale))
               << 8;
    raw32[x] = static_cast<float>(standardWindowDepth(z, n, f));
    rawRev[x] = static_cast<float>(reversedWindowDepth(z, n, f));
  }
  const Out a = convert(raw24, w, h, DepthMode::Fixed24, n, f);
  const Out b = convert(raw32, w, h, DepthMode::Float32, n, f);
  const Out c = convert(rawRev, w, h, DepthMode::Float32Reversed, n, f);
  for (int x = 0; x < w; ++x) {
    ASSERT_EQ(a.covered(x, 0), 1);
    ASSERT_EQ(b.covered(x, 0), 1);
    ASSERT_EQ(c.covered(x, 0), 1);
    // Each is within half a unit of eq. (2): 24-bit rounding, or float
    // rounding of d (≤ 2^-25 for d in [0.5, 1], so ≤ S·2^-25 < 0.5).
    const double exact = zPrimeFromEyeZ(n * std::pow(0.999 * f / n, x / (w - 1.0)), n, f);
    EXPECT_LE(std::abs(a.zPrime(x, 0) - exact), 0.5 + 1e-6) << x;
    EXPECT_LE(std::abs(b.zPrime(x, 0) - exact), 0.5 + 1e-6) << x;
    EXPECT_LE(std::abs(c.zPrime(x, 0) - exact), 0.5 + 1e-6) << x;
    EXPECT_LE(std::abs(a.zPrime(x, 0) - b.zPrime(x, 0)), 1.0 + 1e-6) << x;
    EXPECT_LE(std::abs(a.zPrime(x, 0) - c.zPrime(x, 0)), 1.0 + 1e-6) << x;
    EXPECT_LE(std::abs(b.zPrime(x, 0) - c.zPrime(x, 0)), 1.0 + 1e-6) << x;
  }
}

TEST(ConvertDepth, RowsAreFlipped) {
  // GL row 0 is the bottom row: raw row gy lands in image row height−1−gy.
  // Each raw value encodes its own GL (x, gy), so any misplacement shows.
  const int w = 5, h = 4;
  std::vector<std::uint32_t> raw(w * h);
  for (int gy = 0; gy < h; ++gy)
    for (int x = 0; x < w; ++x) raw[gy * w + x] = static_cast<std::uint32_t>(1000 + 10 * gy + x) << 8;
  const Out o = convert(raw, w, h, DepthMode::Fixed24, 0.1, 100.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      EXPECT_EQ(o.zPrime(x, y), 1000.0 + 10.0 * (h - 1 - y) + x) << "(" << x << ", " << y << ")";

  // Same for the float modes, with one covered pixel: GL bottom-left is image
  // bottom-left.
  for (DepthMode mode : {DepthMode::Float32, DepthMode::Float32Reversed}) {
    const float clear = mode == DepthMode::Float32 ? 1.0f : 0.0f;
    std::vector<float> fr(w * h, clear);
    fr[0] = 0.5f;              // GL (0, 0): bottom-left
    fr[(h - 1) * w + 4] = 0.25f;  // GL (4, h−1): top-right
    const Out p = convert(fr, w, h, mode, 0.1, 100.0);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const bool expectCovered = (x == 0 && y == h - 1) || (x == 4 && y == 0);
        EXPECT_EQ(p.covered(x, y), expectCovered ? 1 : 0)
            << depthModeName(mode) << " (" << x << ", " << y << ")";
      }
    }
  }
}

TEST(ConvertDepth, OutputsResizedThenReusedWithoutReallocation) {
  const double n = 0.1, f = 100.0;
  Image<double> zPrime(3, 3, -7.0);  // wrong size, stale contents
  Image<float> eyeZ;                 // empty
  Image<std::uint8_t> covered(8, 2, 9);  // right pixel count, wrong shape
  const int w = 4, h = 4;
  std::vector<float> raw(w * h, 1.0f);  // all clear
  raw[3] = 0.5f;
  convertDepth(raw.data(), w, h, DepthMode::Float32, n, f, zPrime, eyeZ, covered);
  ASSERT_EQ(zPrime.width(), w);
  ASSERT_EQ(zPrime.height(), h);
  ASSERT_EQ(eyeZ.width(), w);
  ASSERT_EQ(eyeZ.height(), h);
  ASSERT_EQ(covered.width(), w);
  ASSERT_EQ(covered.height(), h);
  EXPECT_EQ(covered(3, h - 1), 1);

  // Second call, same size, stale contents: no reallocation, every pixel
  // rewritten.
  const double* zpData = zPrime.data();
  const float* ezData = eyeZ.data();
  const std::uint8_t* cvData = covered.data();
  zPrime.fill(-7.0);
  eyeZ.fill(-7.0f);
  covered.fill(9);
  std::vector<float> raw2(w * h, 1.0f);
  raw2[0] = 0.25f;
  convertDepth(raw2.data(), w, h, DepthMode::Float32, n, f, zPrime, eyeZ, covered);
  EXPECT_EQ(zPrime.data(), zpData);
  EXPECT_EQ(eyeZ.data(), ezData);
  EXPECT_EQ(covered.data(), cvData);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x == 0 && y == h - 1) {
        EXPECT_EQ(covered(x, y), 1);
        EXPECT_EQ(zPrime(x, y), 0.25 * kZPrimeScale);
        EXPECT_NEAR(eyeZ(x, y), eyeZFromZPrime(0.25 * kZPrimeScale, n, f), 1e-6);
      } else {
        expectEmpty(Out{zPrime, eyeZ, covered}, x, y);
      }
    }
  }
}

TEST(ConvertDepth, ZeroSizedInput) {
  Out o;
  o.zPrime.resize(2, 2);
  convertDepth(nullptr, 0, 0, DepthMode::Fixed24, 0.1, 10.0, o.zPrime, o.eyeZ, o.covered);
  EXPECT_TRUE(o.zPrime.empty());
  EXPECT_TRUE(o.eyeZ.empty());
  EXPECT_TRUE(o.covered.empty());
}

}  // namespace
}  // namespace hw
