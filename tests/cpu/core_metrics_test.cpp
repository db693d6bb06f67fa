// Metrics (core/metrics.h): MSE/PSNR against hand-computed values, SSIM
// properties from Wang et al. 2004, and the report-strip helpers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>

#include "core/metrics.h"

namespace hw {
namespace {

Image<Rgba8> randomImage(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> d(0, 255);
  Image<Rgba8> im(w, h);
  for (Rgba8& p : im.pixels()) {
    p = Rgba8{static_cast<std::uint8_t>(d(rng)), static_cast<std::uint8_t>(d(rng)),
              static_cast<std::uint8_t>(d(rng)), 255};
  }
  return im;
}

// A smooth, structured image (gradients plus a few edges), so SSIM has
// structure to lose.
Image<Rgba8> structuredImage(int w, int h) {
  Image<Rgba8> im(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int checker = ((x / 16) + (y / 16)) % 2 ? 60 : 0;
      const double s = 0.5 + 0.5 * std::sin(0.07 * x) * std::cos(0.05 * y);
      im(x, y) = Rgba8{static_cast<std::uint8_t>(40 + checker + 100 * s),
                       static_cast<std::uint8_t>(30 + 150 * x / w + checker / 2),
                       static_cast<std::uint8_t>(200 - 120 * y / h), 255};
    }
  }
  return im;
}

std::uint8_t clampByte(int v) { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); }

Image<Rgba8> addNoise(const Image<Rgba8>& im, double sigma, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> d(0.0, sigma);
  Image<Rgba8> out = im;
  for (Rgba8& p : out.pixels()) {
    p.r = clampByte(int(std::lround(p.r + d(rng))));
    p.g = clampByte(int(std::lround(p.g + d(rng))));
    p.b = clampByte(int(std::lround(p.b + d(rng))));
  }
  return out;
}

TEST(Metrics, IdenticalImagesHaveZeroMseInfinitePsnrAndCap) {
  const Image<Rgba8> a = randomImage(32, 20, 1);
  EXPECT_EQ(mse(a, a), 0.0);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
  EXPECT_GT(psnr(a, a), 0.0);
  EXPECT_EQ(psnrCapped(a, a), 99.0);
  EXPECT_EQ(psnrCapped(a, a, 60.0), 60.0);
}

TEST(Metrics, OnePixelOffByTenInOneChannel) {
  // 4×4 image, one pixel's green off by 10: squared error 100 over 16 pixels.
  Image<Rgba8> a(4, 4, Rgba8{50, 60, 70, 255});
  Image<Rgba8> b = a;
  b(2, 1).g = 70;
  const ChannelMse m = channelMse(a, b);
  EXPECT_DOUBLE_EQ(m.r, 0.0);
  EXPECT_DOUBLE_EQ(m.g, 100.0 / 16.0);
  EXPECT_DOUBLE_EQ(m.b, 0.0);
  EXPECT_DOUBLE_EQ(mse(a, b), 100.0 / 48.0);
  EXPECT_DOUBLE_EQ(psnr(a, b), 10.0 * std::log10(255.0 * 255.0 / (100.0 / 48.0)));
  // Alpha is ignored.
  b(0, 0).a = 0;
  EXPECT_DOUBLE_EQ(mse(a, b), 100.0 / 48.0);
}

TEST(Metrics, PerChannelMseAndPsnrFormula) {
  Image<Rgba8> a(8, 2, Rgba8{100, 100, 100, 255});
  Image<Rgba8> b(8, 2, Rgba8{103, 96, 100, 255});  // errors 3, 4, 0 everywhere
  const ChannelMse m = channelMse(a, b);
  EXPECT_DOUBLE_EQ(m.r, 9.0);
  EXPECT_DOUBLE_EQ(m.g, 16.0);
  EXPECT_DOUBLE_EQ(m.b, 0.0);
  EXPECT_DOUBLE_EQ(m.mean(), 25.0 / 3.0);
  EXPECT_DOUBLE_EQ(psnr(a, b), 20.0 * std::log10(255.0) - 10.0 * std::log10(25.0 / 3.0));
  // Every channel off by the peak: MSE 255², PSNR 0 dB.
  const Image<Rgba8> black(3, 3, Rgba8{0, 0, 0, 255});
  const Image<Rgba8> white(3, 3, Rgba8{255, 255, 255, 255});
  EXPECT_NEAR(psnr(black, white), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(psnrFromMse(255.0 * 255.0 / 100.0), 20.0);
}

TEST(Metrics, MaskedMsePsnrUseOnlyMaskedPixels) {
  Image<Rgba8> a(4, 4, Rgba8{10, 10, 10, 255});
  Image<Rgba8> b = a;
  b(0, 0) = Rgba8{255, 255, 255, 255};  // a huge error outside the mask
  b(3, 3).r = 16;                       // error 6 in red inside the mask
  Image<std::uint8_t> mask(4, 4, 0);
  mask(3, 3) = 1;
  mask(2, 3) = 7;  // any non-zero value selects
  const ChannelMse m = channelMse(a, b, mask);
  EXPECT_DOUBLE_EQ(m.r, 36.0 / 2.0);
  EXPECT_DOUBLE_EQ(m.g, 0.0);
  EXPECT_DOUBLE_EQ(mse(a, b, mask), 36.0 / 6.0);
  EXPECT_DOUBLE_EQ(psnr(a, b, mask), psnrFromMse(6.0));
  EXPECT_LT(psnr(a, b), psnr(a, b, mask));

  // All-ones mask = unmasked.
  const Image<std::uint8_t> all(4, 4, 1);
  EXPECT_DOUBLE_EQ(psnr(a, b, all), psnr(a, b));
  // Identical pixels under the mask: inf, capped on request.
  mask.fill(0);
  mask(1, 1) = 1;
  EXPECT_TRUE(std::isinf(psnr(a, b, mask)));
  EXPECT_EQ(psnrCapped(a, b, mask), 99.0);
  // Empty mask: undefined, NaN.
  mask.fill(0);
  EXPECT_TRUE(std::isnan(mse(a, b, mask)));
  EXPECT_TRUE(std::isnan(psnr(a, b, mask)));
  EXPECT_TRUE(std::isnan(psnrCapped(a, b, mask)));
}

TEST(Metrics, SsimOfIdenticalImagesIsOne) {
  const Image<Rgba8> a = structuredImage(64, 48);
  EXPECT_EQ(ssim(a, a), 1.0);
  const Image<Rgba8> r = randomImage(11, 11, 3);  // smallest size: one window
  EXPECT_EQ(ssim(r, r), 1.0);
}

TEST(Metrics, SsimIsSymmetricAndBounded) {
  const Image<Rgba8> a = structuredImage(64, 48);
  const Image<Rgba8> b = addNoise(a, 20.0, 5);
  EXPECT_NEAR(ssim(a, b), ssim(b, a), 1e-6);
  EXPECT_LE(ssim(a, b), 1.0);
  EXPECT_GE(ssim(a, b), -1.0);
}

TEST(Metrics, SsimDecreasesMonotonicallyWithNoise) {
  const Image<Rgba8> a = structuredImage(96, 80);
  double last = ssim(a, a);
  for (double sigma : {2.0, 5.0, 10.0, 20.0, 40.0, 80.0}) {
    const double s = ssim(a, addNoise(a, sigma, 11));
    EXPECT_LT(s, last) << "sigma " << sigma;
    last = s;
  }
  EXPECT_LT(last, 0.5);
}

TEST(Metrics, SsimOfConstantShiftIsHighButBelowOne) {
  // A brightness shift leaves structure and contrast intact; only the
  // luminance term drops a little.
  const Image<Rgba8> a = structuredImage(64, 64);
  Image<Rgba8> b = a;
  for (Rgba8& p : b.pixels()) {
    p.r = clampByte(p.r + 10);
    p.g = clampByte(p.g + 10);
    p.b = clampByte(p.b + 10);
  }
  const double s = ssim(a, b);
  EXPECT_GT(s, 0.95);
  EXPECT_LT(s, 1.0);
}

TEST(Metrics, SsimOfUnrelatedRandomImagesIsNearZero) {
  const double s = ssim(randomImage(128, 128, 21), randomImage(128, 128, 22));
  EXPECT_NEAR(s, 0.0, 0.05);
}

// Direct evaluation of Wang et al. 2004 eq. (13) in double: the 2-D Gaussian
// window at every valid position, then the mean.
double ssimDirect(const Image<Rgba8>& a, const Image<Rgba8>& b) {
  double g[11], gs = 0;
  for (int k = 0; k < 11; ++k) gs += g[k] = std::exp(-(k - 5) * (k - 5) / (2 * 1.5 * 1.5));
  auto luma = [](Rgba8 p) { return 0.299 * p.r + 0.587 * p.g + 0.114 * p.b; };
  const double c1 = 6.5025, c2 = 58.5225;  // (0.01·255)², (0.03·255)²
  double total = 0;
  int count = 0;
  for (int y0 = 0; y0 + 11 <= a.height(); ++y0) {
    for (int x0 = 0; x0 + 11 <= a.width(); ++x0) {
      double mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
      for (int y = 0; y < 11; ++y) {
        for (int x = 0; x < 11; ++x) {
          const double w = g[x] * g[y] / (gs * gs);
          const double lx = luma(a(x0 + x, y0 + y)), ly = luma(b(x0 + x, y0 + y));
          mx += w * lx;
          my += w * ly;
          exx += w * lx * lx;
          eyy += w * ly * ly;
          exy += w * lx * ly;
        }
      }
      const double vx = exx - mx * mx, vy = eyy - my * my, cxy = exy - mx * my;
      total += (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++count;
    }
  }
  return total / count;
}

TEST(Metrics, SsimMatchesDirectComputation) {
  // One window (11×11), and a non-square image whose row count exceeds the
  // 11-row ring buffer several times.
  for (auto [w, h] : {std::pair{11, 11}, std::pair{19, 40}, std::pair{37, 23}}) {
    const Image<Rgba8> a = randomImage(w, h, 31);
    const Image<Rgba8> b = addNoise(a, 30.0, 32);
    EXPECT_NEAR(ssim(a, b), ssimDirect(a, b), 1e-4) << w << "x" << h;
    const Image<Rgba8> s = structuredImage(w, h);
    const Image<Rgba8> sn = addNoise(s, 8.0, 33);
    EXPECT_NEAR(ssim(s, sn), ssimDirect(s, sn), 1e-4) << w << "x" << h;
  }
}

TEST(Metrics, HoleFraction) {
  Image<std::uint8_t> m(10, 4, 0);
  EXPECT_EQ(holeFraction(m), 0.0);
  m(0, 0) = 1;
  m(9, 3) = 255;
  m(5, 2) = 1;
  EXPECT_DOUBLE_EQ(holeFraction(m), 3.0 / 40.0);
  m.fill(1);
  EXPECT_EQ(holeFraction(m), 1.0);
  EXPECT_EQ(holeFraction(Image<std::uint8_t>()), 0.0);
}

TEST(Metrics, DiffImageScalesAndClamps) {
  Image<Rgba8> a(2, 1, Rgba8{100, 100, 100, 7});
  Image<Rgba8> b(2, 1, Rgba8{100, 100, 100, 9});
  b(0, 0) = Rgba8{110, 90, 0, 0};
  const Image<Rgba8> d = diffImage(a, b, 4);
  EXPECT_EQ(d(0, 0), (Rgba8{40, 40, 255, 255}));
  EXPECT_EQ(d(1, 0), (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(diffImage(a, b, 1)(0, 0), (Rgba8{10, 10, 100, 255}));
}

TEST(Metrics, HstackPlacesImagesWithGaps) {
  const Image<Rgba8> a(3, 2, Rgba8{1, 1, 1, 255});
  const Image<Rgba8> b(5, 2, Rgba8{2, 2, 2, 255});
  const Image<Rgba8> c(1, 2, Rgba8{3, 3, 3, 255});
  const Rgba8 gap{9, 9, 9, 255};
  const Image<Rgba8> s = hstack({&a, &b, &c}, 4, gap);
  EXPECT_EQ(s.width(), 3 + 4 + 5 + 4 + 1);
  EXPECT_EQ(s.height(), 2);
  for (int y = 0; y < 2; ++y) {
    EXPECT_EQ(s(0, y), a(0, 0));
    EXPECT_EQ(s(2, y), a(0, 0));
    EXPECT_EQ(s(3, y), gap);
    EXPECT_EQ(s(6, y), gap);
    EXPECT_EQ(s(7, y), b(0, 0));
    EXPECT_EQ(s(11, y), b(0, 0));
    EXPECT_EQ(s(12, y), gap);
    EXPECT_EQ(s(16, y), c(0, 0));
  }
  const Image<Rgba8> one = hstack({&a}, 10);
  EXPECT_EQ(one.width(), 3);
  EXPECT_EQ(one.pixels(), a.pixels());
  EXPECT_EQ(hstack({&a, &b}, 0).width(), 8);
}

TEST(Metrics, MaskToImage) {
  Image<std::uint8_t> m(3, 1, 0);
  m(1, 0) = 1;
  const Rgba8 on{255, 0, 0, 255}, off{0, 0, 0, 255};
  const Image<Rgba8> im = maskToImage(m, on, off);
  EXPECT_EQ(im(0, 0), off);
  EXPECT_EQ(im(1, 0), on);
  EXPECT_EQ(im(2, 0), off);
}

using MetricsDeathTest = ::testing::Test;

TEST_F(MetricsDeathTest, MismatchedSizesAreAPreconditionFailure) {
  const Image<Rgba8> a(4, 4), b(4, 5);
  EXPECT_DEATH((void)mse(a, b), "CHECK failed");
  EXPECT_DEATH((void)psnr(a, a, Image<std::uint8_t>(3, 4)), "CHECK failed");
  EXPECT_DEATH((void)ssim(Image<Rgba8>(20, 20), Image<Rgba8>(20, 21)), "CHECK failed");
  EXPECT_DEATH((void)ssim(Image<Rgba8>(10, 20), Image<Rgba8>(10, 20)), "CHECK failed");
  EXPECT_DEATH((void)diffImage(a, b), "CHECK failed");
  EXPECT_DEATH((void)hstack({&a, &b}, 2), "CHECK failed");
}

}  // namespace
}  // namespace hw
