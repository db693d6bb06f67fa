#include "core/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/check.h"

namespace hw {
namespace {

template <class A, class B>
void checkSameSize(const Image<A>& a, const Image<B>& b) {
  HW_CHECK_EQ(a.width(), b.width());
  HW_CHECK_EQ(a.height(), b.height());
}

struct SquaredSums {
  std::uint64_t r = 0, g = 0, b = 0, count = 0;
};

ChannelMse toMse(const SquaredSums& s) {
  if (s.count == 0) return ChannelMse{};
  const double n = static_cast<double>(s.count);
  return ChannelMse{static_cast<double>(s.r) / n, static_cast<double>(s.g) / n,
                    static_cast<double>(s.b) / n};
}

// Exact integer sums of squared differences; weight 0/1 per pixel from the
// mask (or 1 everywhere), branch-free so the row loop vectorises.
template <bool kMasked>
SquaredSums squaredSums(const Image<Rgba8>& a, const Image<Rgba8>& b, const std::uint8_t* mask) {
  SquaredSums s;
  const Rgba8* pa = a.data();
  const Rgba8* pb = b.data();
  const std::size_t n = a.size();
  std::uint64_t sr = 0, sg = 0, sb = 0, cnt = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t w = kMasked ? static_cast<std::uint32_t>(mask[i] != 0) : 1u;
    const int dr = int(pa[i].r) - int(pb[i].r);
    const int dg = int(pa[i].g) - int(pb[i].g);
    const int db = int(pa[i].b) - int(pb[i].b);
    sr += w * static_cast<std::uint32_t>(dr * dr);
    sg += w * static_cast<std::uint32_t>(dg * dg);
    sb += w * static_cast<std::uint32_t>(db * db);
    cnt += w;
  }
  s.r = sr;
  s.g = sg;
  s.b = sb;
  s.count = cnt;
  return s;
}

// Rec.601 luma minus `centre`, one row.
void centredLumaRow(const Rgba8* __restrict px, int n, float centre, float* __restrict out) {
  static_assert(sizeof(Rgba8) == 4);
  const auto* p = reinterpret_cast<const unsigned char*>(px);  // R, G, B, A bytes
  for (int x = 0; x < n; ++x) {
    out[x] = 0.299f * p[4 * x] + 0.587f * p[4 * x + 1] + 0.114f * p[4 * x + 2] - centre;
  }
}

ChannelMse nanMse() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return ChannelMse{nan, nan, nan};
}

}  // namespace

ChannelMse channelMse(const Image<Rgba8>& a, const Image<Rgba8>& b) {
  checkSameSize(a, b);
  return toMse(squaredSums<false>(a, b, nullptr));
}

ChannelMse channelMse(const Image<Rgba8>& a, const Image<Rgba8>& b,
                      const Image<std::uint8_t>& mask) {
  checkSameSize(a, b);
  checkSameSize(a, mask);
  const SquaredSums s = squaredSums<true>(a, b, mask.data());
  if (s.count == 0) return nanMse();
  return toMse(s);
}

double mse(const Image<Rgba8>& a, const Image<Rgba8>& b) { return channelMse(a, b).mean(); }

double mse(const Image<Rgba8>& a, const Image<Rgba8>& b, const Image<std::uint8_t>& mask) {
  return channelMse(a, b, mask).mean();
}

double psnrFromMse(double mseValue) {
  if (std::isnan(mseValue)) return mseValue;
  if (mseValue <= 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(kPsnrPeak * kPsnrPeak / mseValue);
}

double psnr(const Image<Rgba8>& a, const Image<Rgba8>& b) { return psnrFromMse(mse(a, b)); }

double psnr(const Image<Rgba8>& a, const Image<Rgba8>& b, const Image<std::uint8_t>& mask) {
  return psnrFromMse(mse(a, b, mask));
}

double psnrCapped(const Image<Rgba8>& a, const Image<Rgba8>& b, double capDb) {
  const double p = psnr(a, b);
  return std::isnan(p) ? p : std::min(p, capDb);
}

double psnrCapped(const Image<Rgba8>& a, const Image<Rgba8>& b, const Image<std::uint8_t>& mask,
                  double capDb) {
  const double p = psnr(a, b, mask);
  return std::isnan(p) ? p : std::min(p, capDb);
}

double ssim(const Image<Rgba8>& a, const Image<Rgba8>& b) {
  checkSameSize(a, b);
  HW_CHECK_GE(a.width(), kSsimWindow);
  HW_CHECK_GE(a.height(), kSsimWindow);
  constexpr int kR = kSsimWindow / 2;
  constexpr int kQ = 5;  // filtered quantities: x, y, x², y², xy
  const int w = a.width();
  const int h = a.height();
  const int outW = w - 2 * kR;
  const int outH = h - 2 * kR;

  float g[kSsimWindow];
  {
    double wsum = 0.0, wd[kSsimWindow];
    for (int k = 0; k < kSsimWindow; ++k) {
      const double d = k - kR;
      wd[k] = std::exp(-d * d / (2.0 * kSsimSigma * kSsimSigma));
      wsum += wd[k];
    }
    // The 2-D window is the outer product of this 1-D one, so it sums to 1 too.
    for (int k = 0; k < kSsimWindow; ++k) g[k] = static_cast<float>(wd[k] / wsum);
  }
  const float c1 = static_cast<float>((0.01 * 255.0) * (0.01 * 255.0));
  const float c2 = static_cast<float>((0.03 * 255.0) * (0.03 * 255.0));
  // Luma is centred on 128 before squaring so E[x²] − μ² keeps float precision
  // (variances are shift-invariant; the mean is shifted back for the
  // luminance term).
  constexpr float kCentre = 128.0f;

  // All buffers once per call; the loops below do not allocate.
  std::vector<float> src(static_cast<std::size_t>(kQ) * w);
  std::vector<float> ring(static_cast<std::size_t>(kQ) * kSsimWindow * outW);
  std::vector<float> acc(static_cast<std::size_t>(kQ) * outW);
  std::vector<float> map(static_cast<std::size_t>(outW));
  auto ringRow = [&](int q, int slot) {
    return ring.data() + (static_cast<std::size_t>(slot) * kQ + q) * outW;
  };

  double total = 0.0;
  for (int y = 0; y < h; ++y) {
    float* sx = src.data();
    float* sy = sx + w;
    float* sxx = sy + w;
    float* syy = sxx + w;
    float* sxy = syy + w;
    const Rgba8* ra = a.data() + static_cast<std::size_t>(y) * w;
    const Rgba8* rb = b.data() + static_cast<std::size_t>(y) * w;
    centredLumaRow(ra, w, kCentre, sx);
    centredLumaRow(rb, w, kCentre, sy);
    for (int x = 0; x < w; ++x) {
      sxx[x] = sx[x] * sx[x];
      syy[x] = sy[x] * sy[x];
      sxy[x] = sx[x] * sy[x];
    }
    const int slot = y % kSsimWindow;
    for (int q = 0; q < kQ; ++q) {
      const float* in = src.data() + static_cast<std::size_t>(q) * w;
      float* out = ringRow(q, slot);
      // The window is symmetric: fold tap pairs k, 10 − k.
      for (int x = 0; x < outW; ++x) out[x] = g[kR] * in[x + kR];
      for (int k = 0; k < kR; ++k) {
        const float gk = g[k];
        const float* lo = in + k;
        const float* hi = in + (2 * kR - k);
        for (int x = 0; x < outW; ++x) out[x] += gk * (lo[x] + hi[x]);
      }
    }
    if (y < 2 * kR) continue;

    const int oy = y - 2 * kR;  // window rows oy .. y
    for (int q = 0; q < kQ; ++q) {
      float* out = acc.data() + static_cast<std::size_t>(q) * outW;
      const float* mid = ringRow(q, (oy + kR) % kSsimWindow);
      for (int x = 0; x < outW; ++x) out[x] = g[kR] * mid[x];
      for (int k = 0; k < kR; ++k) {
        const float gk = g[k];
        const float* lo = ringRow(q, (oy + k) % kSsimWindow);
        const float* hi = ringRow(q, (oy + 2 * kR - k) % kSsimWindow);
        for (int x = 0; x < outW; ++x) out[x] += gk * (lo[x] + hi[x]);
      }
    }
    const float* mx = acc.data();
    const float* my = mx + outW;
    const float* exx = my + outW;
    const float* eyy = exx + outW;
    const float* exy = eyy + outW;
    float* m = map.data();
    for (int x = 0; x < outW; ++x) {
      const float vx = exx[x] - mx[x] * mx[x];
      const float vy = eyy[x] - my[x] * my[x];
      const float cxy = exy[x] - mx[x] * my[x];
      const float ux = mx[x] + kCentre;
      const float uy = my[x] + kCentre;
      // Wang et al. 2004 eq. (13).
      m[x] =
          ((2.0f * ux * uy + c1) * (2.0f * cxy + c2)) / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
    }
    double rowSum = 0.0;
    for (int x = 0; x < outW; ++x) rowSum += m[x];
    total += rowSum;
  }
  return total / (static_cast<double>(outW) * static_cast<double>(outH));
}

double holeFraction(const Image<std::uint8_t>& mask) {
  if (mask.empty()) return 0.0;
  const std::uint8_t* p = mask.data();
  const std::size_t n = mask.size();
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += (p[i] != 0);
  return static_cast<double>(count) / static_cast<double>(n);
}

Image<Rgba8> diffImage(const Image<Rgba8>& a, const Image<Rgba8>& b, int gain) {
  checkSameSize(a, b);
  HW_CHECK_GE(gain, 0);
  Image<Rgba8> out(a.width(), a.height());
  const Rgba8* pa = a.data();
  const Rgba8* pb = b.data();
  Rgba8* po = out.data();
  auto amp = [gain](std::uint8_t u, std::uint8_t v) {
    return static_cast<std::uint8_t>(std::min(255, std::abs(int(u) - int(v)) * gain));
  };
  for (std::size_t i = 0; i < out.size(); ++i) {
    po[i] = Rgba8{amp(pa[i].r, pb[i].r), amp(pa[i].g, pb[i].g), amp(pa[i].b, pb[i].b), 255};
  }
  return out;
}

Image<Rgba8> hstack(const std::vector<const Image<Rgba8>*>& images, int gapPx, Rgba8 gapColour) {
  HW_CHECK(!images.empty());
  HW_CHECK_GE(gapPx, 0);
  HW_CHECK(images.front() != nullptr);
  const int h = images.front()->height();
  int totalW = gapPx * static_cast<int>(images.size() - 1);
  for (const Image<Rgba8>* im : images) {
    HW_CHECK(im != nullptr);
    HW_CHECK_EQ(im->height(), h);
    totalW += im->width();
  }
  Image<Rgba8> out(totalW, h, gapColour);
  int x0 = 0;
  for (const Image<Rgba8>* im : images) {
    for (int y = 0; y < h; ++y) {
      const Rgba8* src = im->data() + static_cast<std::size_t>(y) * im->width();
      std::copy(src, src + im->width(), out.data() + static_cast<std::size_t>(y) * totalW + x0);
    }
    x0 += im->width() + gapPx;
  }
  return out;
}

Image<Rgba8> maskToImage(const Image<std::uint8_t>& mask, Rgba8 on, Rgba8 off) {
  Image<Rgba8> out(mask.width(), mask.height());
  const std::uint8_t* pm = mask.data();
  Rgba8* po = out.data();
  for (std::size_t i = 0; i < out.size(); ++i) po[i] = pm[i] != 0 ? on : off;
  return out;
}

}  // namespace hw
