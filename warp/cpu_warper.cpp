#include "warp/cpu_warper.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <immintrin.h>
#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "core/check.h"
#include "core/timer.h"
#include "warp/sky_rects.h"

namespace hw::warp {
namespace {

// Screen positions in 1/256 pixel (as GPUs and llvmpipe snap them): edge
// functions are exact integers, so neighbouring triangles share their edge
// pixels without gaps or double writes.
constexpr double kSubPixel = 256.0;
// Triangles are clipped to |x|, |y| <= kGuard·w (a guard band 64 viewports
// wide) and to the near plane, which keeps snapped positions within int64
// products.
constexpr double kGuard = 64.0;

class CpuWarpSource final : public WarpSource {
 public:
  const Camera& keyframeCamera() const override { return camera; }
  int quadCount() const override { return quads; }

  Camera camera;
  int quads = 0;
  int skyRects = 0;
  // Per vertex (4 per quad, quads first, then the sky rectangles): world
  // position x, y, z, w (w = 0: a direction at infinity) and the projective
  // texcoord (s·q, t·q, q), rounded to float as the GL warper's vertices are.
  std::vector<float> pos, tex;
  std::vector<std::uint8_t> large;  // per quad: a leaf larger than one cell
  Image<Rgba8> texture;
};

struct ClipVertex {
  double x, y, z, w;  // clip space
  double s, t, q;     // projective texcoord
};

// One triangle ready to rasterise: snapped edges, attribute planes (value
// at pixel (px, py) = a + ax·px + ay·py, pixel centres folded in).
struct Triangle {
  std::int64_t x[3], y[3];  // snapped image positions (row 0 = top)
  int minX, minY, maxX, maxY;  // inclusive pixel bounds, inside the target
  struct Plane {
    float a, ax, ay;
  } depth, p, q, r, invW;
  bool sky;
  bool large;
};

struct Pass {
  std::vector<Triangle> sky, quads;
};

Triangle::Plane plane(const double (&sx)[3], const double (&sy)[3], const double (&v)[3],
                      double area2) {
  const double ax = ((v[1] - v[0]) * (sy[2] - sy[0]) - (v[2] - v[0]) * (sy[1] - sy[0])) / area2;
  const double ay = ((v[2] - v[0]) * (sx[1] - sx[0]) - (v[1] - v[0]) * (sx[2] - sx[0])) / area2;
  const double a = v[0] - ax * (sx[0] - 0.5) - ay * (sy[0] - 0.5);
  return {static_cast<float>(a), static_cast<float>(ax), static_cast<float>(ay)};
}

// The clip planes: a vertex is inside plane p when clipDistance(v, p) >= 0.
constexpr int kClipPlanes = 6;
inline double clipDistance(const ClipVertex& v, int plane) {
  switch (plane) {
    case 0: return v.z + v.w;             // near (GL: z >= -w)
    case 1: return kGuard * v.w - v.x;
    case 2: return kGuard * v.w + v.x;
    case 3: return kGuard * v.w - v.y;
    case 4: return kGuard * v.w + v.y;
    default: return v.w - 1e-12;          // strictly in front of the eye
  }
}

// Bit p set: v is outside clip plane p.
inline unsigned clipOutcode(const ClipVertex& v) {
  unsigned code = 0;
  for (int p = 0; p < kClipPlanes; ++p) code |= (clipDistance(v, p) >= 0 ? 0u : 1u) << p;
  return code;
}

// Sutherland-Hodgman against d(v) >= 0 for each plane d; at most 3 + 6
// vertices come out of a triangle and six planes.
int clipPolygon(ClipVertex* poly, int n, ClipVertex* scratch) {
  ClipVertex* in = poly;
  ClipVertex* out = scratch;
  for (int plane = 0; plane < kClipPlanes && n > 0; ++plane) {
    bool allIn = true;
    for (int k = 0; k < n; ++k) allIn = allIn && clipDistance(in[k], plane) >= 0;
    if (allIn) continue;
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const ClipVertex& a = in[k];
      const ClipVertex& b = in[(k + 1) % n];
      const double da = clipDistance(a, plane), db = clipDistance(b, plane);
      if (da >= 0) out[m++] = a;
      if ((da >= 0) != (db >= 0)) {
        const double f = da / (da - db);
        out[m++] = {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z),
                    a.w + f * (b.w - a.w), a.s + f * (b.s - a.s), a.t + f * (b.t - a.t),
                    a.q + f * (b.q - a.q)};
      }
    }
    std::swap(in, out);
    n = m;
  }
  if (in != poly)
    for (int k = 0; k < n; ++k) poly[k] = in[k];
  return n;
}

// RGBA8 as one little-endian word (red in the low byte), and back.
std::uint32_t word(const Rgba8& c) {
  std::uint32_t w;
  std::memcpy(&w, &c, sizeof w);
  return w;
}

// For each 8-bit lane mask, a 64-bit word with 0xFF in the bytes of the set lanes.
struct ByteLanes {
  std::uint64_t mask[256];
  ByteLanes() {
    for (unsigned b = 0; b < 256; ++b) {
      mask[b] = 0;
      for (int k = 0; k < 8; ++k)
        if (b & (1u << k)) mask[b] |= 0xFFull << (8 * k);
    }
  }
};
const ByteLanes kByteLanes;

struct Raster;
// Texcoords of a run of up to 16 pixels of a span: u0 + k·du, v0 + k·dv,
// in 16.16 texels.
struct Run {
  std::int32_t u0, du, v0, dv;
};
// Pixels [i0, i0 + count) of a span, their texcoords in runs[(k / 16)],
// depth d0 + k·t.depth.ax, 1/eye z iw0 + k·t.invW.ax; 8 at a time.
void spanAvx2(const Raster& r, const Triangle& t, std::size_t i0, int count, const Run* runs,
              float d0, float iw0, std::uint8_t layer);

// Rasterises pass triangles into rows [row0, row1) of the target.
struct Raster {
  int width, height;
  const Image<Rgba8>* texture;
  Rgba8* colour;
  std::uint8_t* coverage;  // 0 empty, else the layer that wrote (stencil)
  std::uint8_t* large;     // nullable
  float* eyeZ;             // nullable
  float* depth;
  // The background's pass: each row's first and last empty pixel (-1: none);
  // spans are cut to them.
  const int* firstEmpty = nullptr;
  const int* lastEmpty = nullptr;
  bool avx2 = false;              // spans 8 pixels at a time (spanAvx2)

  void draw(const Triangle& t, int row0, int row1, std::uint8_t layer) const {
    const int y0 = std::max(t.minY, row0), y1 = std::min(t.maxY, row1 - 1);
    if (y0 > y1) return;
    // Edge k runs from vertex k to k+1; inside: E + bias >= 0 (bias 0 on
    // top-left edges, -1 elsewhere, so a pixel on a shared edge is drawn once).
    std::int64_t stepX[3], stepY[3], rowE[3];
    const std::int64_t cx = static_cast<std::int64_t>(t.minX) * 256 + 128;
    const std::int64_t cy = static_cast<std::int64_t>(y0) * 256 + 128;
    for (int k = 0; k < 3; ++k) {
      const int j = (k + 1) % 3;
      const std::int64_t dx = t.x[j] - t.x[k], dy = t.y[j] - t.y[k];
      stepX[k] = -dy * 256;
      stepY[k] = dx * 256;
      rowE[k] = dx * (cy - t.y[k]) - dy * (cx - t.x[k]) + ((dy < 0 || (dy == 0 && dx > 0)) ? 0 : -1);
    }
    for (int py = y0; py <= y1; ++py) {
      // The row's span: where every edge function is >= 0.
      int xa = t.minX, xb = t.maxX;
      if (firstEmpty) {
        xa = std::max(xa, firstEmpty[py]);
        xb = firstEmpty[py] < 0 ? -1 : std::min(xb, lastEmpty[py]);
      }
      for (int k = 0; k < 3 && xa <= xb; ++k) {
        const std::int64_t e = rowE[k], sx = stepX[k];
        if (sx > 0) {
          if (e < 0) xa = std::max<std::int64_t>(xa, t.minX + (-e + sx - 1) / sx);
        } else if (sx < 0) {
          if (e < 0) xb = -1;
          else xb = static_cast<int>(std::min<std::int64_t>(xb, t.minX + e / -sx));
        } else if (e < 0) {
          xb = -1;
        }
      }
      for (int k = 0; k < 3; ++k) rowE[k] += stepY[k];
      if (xa > xb) continue;
      span(t, py, xa, xb, layer);
    }
  }

  // Texcoords are exact (one division) at both ends of runs of up to
  // kRun pixels and linear in between, in 16.16 fixed point: off by well
  // under 1/256 texel at these quads' perspective (the bilinear weights'
  // resolution).
  static constexpr int kRun = 16;

  void span(const Triangle& t, int py, int xa, int xb, std::uint8_t layer) const {
    const double ftw = texture->width(), fth = texture->height();
    const std::size_t rowBase = static_cast<std::size_t>(py) * static_cast<std::size_t>(width);
    const double fy = py;
    auto texel = [&](double x, std::int64_t& u, std::int64_t& v) {
      const double r = double(t.r.a) + double(t.r.ax) * x + double(t.r.ay) * fy;
      const double inv = 1.0 / r;
      const double p = double(t.p.a) + double(t.p.ax) * x + double(t.p.ay) * fy;
      const double q = double(t.q.a) + double(t.q.ax) * x + double(t.q.ay) * fy;
      // Rounded to 1/65536 texel (floor after an offset keeps it a
      // truncation), kept within int32: far outside the texture, clamping
      // gives the edge texel anyway.
      constexpr double kOffset = 1u << 31;
      u = static_cast<std::int64_t>(std::clamp(p * inv * ftw - 0.5, -16384.0, 16384.0) * 65536.0 +
                                    kOffset + 0.5) - static_cast<std::int64_t>(kOffset);
      v = static_cast<std::int64_t>(std::clamp(q * inv * fth - 0.5, -16384.0, 16384.0) * 65536.0 +
                                    kOffset + 0.5) - static_cast<std::int64_t>(kOffset);
    };
    constexpr int kChunkRuns = 64;
    Run runs[kChunkRuns];
    float d = t.depth.a + t.depth.ax * static_cast<float>(xa) + t.depth.ay * static_cast<float>(fy);
    float iw = t.invW.a + t.invW.ax * static_cast<float>(xa) + t.invW.ay * static_cast<float>(fy);
    for (int c0 = xa; c0 <= xb; c0 += kChunkRuns * kRun) {
      const int c1 = std::min(xb, c0 + kChunkRuns * kRun - 1);
      // Exact texcoords at each run's first pixel and at the chunk's last.
      int nRuns = 0;
      std::int64_t u0, v0;
      texel(c0, u0, v0);
      for (int x0 = c0; x0 <= c1; x0 += kRun) {
        const int n = std::min(kRun, c1 - x0 + 1);
        const int next = x0 + n < c1 + 1 ? x0 + n : c1;  // the next run's first, or the last
        std::int64_t u1 = u0, v1 = v0;
        if (next > x0) texel(next, u1, v1);
        const int steps = std::max(1, next - x0);
        runs[nRuns++] = {static_cast<std::int32_t>(u0), static_cast<std::int32_t>((u1 - u0) / steps),
                         static_cast<std::int32_t>(v0), static_cast<std::int32_t>((v1 - v0) / steps)};
        u0 = u1;
        v0 = v1;
      }
      const std::size_t i0 = rowBase + static_cast<std::size_t>(c0);
      const int count = c1 - c0 + 1;
      if (avx2) {
        spanAvx2(*this, t, i0, count, runs, d, iw, layer);
        d += t.depth.ax * static_cast<float>(count);
        iw += t.invW.ax * static_cast<float>(count);
        continue;
      }
      for (int k = 0; k < count; ++k, d += t.depth.ax, iw += t.invW.ax) {
        const Run& run = runs[k / kRun];
        const int j = k % kRun;
        pixel(t, i0 + static_cast<std::size_t>(k), run.u0 + run.du * j, run.v0 + run.dv * j, d,
              iw, layer);
      }
    }
  }

  void pixel(const Triangle& t, std::size_t i, std::int64_t u, std::int64_t v, float d, float iw,
             std::uint8_t layer) const {
    const std::uint8_t cov = coverage[i];
    if (cov != 0 && cov != layer) return;  // the stencil: another layer's pixel
    if (!t.sky) {
      if (!(d < depth[i])) return;
      depth[i] = d;
    }
    // GL_LINEAR, clamped to the edge, with 8-bit weights.
    const int tw = texture->width(), th = texture->height();
    const int xi = static_cast<int>(u >> 16), yi = static_cast<int>(v >> 16);
    const std::uint32_t wx1 = static_cast<std::uint32_t>((u >> 8) & 255);
    const std::uint32_t wy1 = static_cast<std::uint32_t>((v >> 8) & 255);
    const int x0 = std::clamp(xi, 0, tw - 1), x1 = std::clamp(xi + 1, 0, tw - 1);
    const int ya = std::clamp(yi, 0, th - 1), yb = std::clamp(yi + 1, 0, th - 1);
    const Rgba8* tex = texture->data();
    const Rgba8* top = tex + static_cast<std::size_t>(ya) * static_cast<std::size_t>(tw);
    const Rgba8* bottom = tex + static_cast<std::size_t>(yb) * static_cast<std::size_t>(tw);
    // Two channels per multiply: red and blue in one word, green and alpha
    // in another.
    auto lerp = [](std::uint32_t p0, std::uint32_t p1, std::uint32_t w0, std::uint32_t w1) {
      const std::uint32_t rb =
          (((p0 & 0x00FF00FFu) * w0 + (p1 & 0x00FF00FFu) * w1 + 0x00800080u) >> 8) & 0x00FF00FFu;
      const std::uint32_t ga =
          (((p0 >> 8) & 0x00FF00FFu) * w0 + ((p1 >> 8) & 0x00FF00FFu) * w1 + 0x00800080u) &
          0xFF00FF00u;
      return rb | ga;
    };
    const std::uint32_t wx0 = 256u - wx1, wy0 = 256u - wy1;
    const std::uint32_t mixed = lerp(lerp(word(top[x0]), word(top[x1]), wx0, wx1),
                                     lerp(word(bottom[x0]), word(bottom[x1]), wx0, wx1), wy0, wy1);
    const std::uint32_t opaque = mixed | 0xFF000000u;
    std::memcpy(static_cast<void*>(&colour[i]), &opaque, sizeof opaque);
    coverage[i] = layer;
    if (large) large[i] = t.large;
    if (eyeZ) eyeZ[i] = t.sky ? kSkyEyeZ : 1.0f / iw;
  }
};

// x clamped to [0, hi], per 32-bit lane.
__attribute__((target("avx2"))) inline __m256i avx2Clamp(__m256i x, __m256i hi) {
  return _mm256_min_epi32(_mm256_max_epi32(x, _mm256_setzero_si256()), hi);
}

// a·w0 + b·w1 on 8-bit values in 16-bit lanes (w0 + w1 = 256), rounded
// back to 8 bits.
__attribute__((target("avx2"))) inline __m256i avx2Lerp(__m256i a, __m256i b, __m256i w0,
                                                        __m256i w1) {
  return _mm256_srli_epi16(
      _mm256_add_epi16(_mm256_add_epi16(_mm256_mullo_epi16(a, w0), _mm256_mullo_epi16(b, w1)),
                       _mm256_set1_epi16(0x80)),
      8);
}

// Texels p[idx] of each lane for lane indices 0..7 (`wide` false) or 0..15
// (p[0..15] loaded as two vectors, the lanes with idx > 7 (`high`) taking
// the second; vpermd reads the low 3 bits of an index, idx and idx - 8 alike).
__attribute__((target("avx2"), always_inline)) inline __m256i avx2Pick(const int* p, __m256i idx,
                                                                       __m256i high, bool wide) {
  using V = const __m256i*;
  const __m256i low = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<V>(p)), idx);
  if (!wide) return low;
  return _mm256_blendv_epi8(
      low, _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<V>(p + 8)), idx), high);
}

// 8 pixels from index i0 (the first m of them): texcoords u0 + k·du,
// v0 + k·dv, depth d0 + k·t.depth.ax, 1/eye z iw0 + k·t.invW.ax.
// `whole`: all 8 pixels lie in this row (then the stores are a load, a
// blend and a full store: masked stores are slow on some CPUs; the pixels
// past the span are this thread's and written back unchanged).
__attribute__((target("avx2"), always_inline)) inline void group8(
    const Raster& r, const Triangle& t, std::size_t i0, int m, bool whole, std::int32_t u0,
    std::int32_t du, std::int32_t v0, std::int32_t dv, float d0, float iw0, std::uint8_t layer) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i zero = _mm256_setzero_si256();
  std::uint64_t cov8 = 0;
  std::memcpy(&cov8, r.coverage + i0, static_cast<std::size_t>(m));
  const __m256i cov = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(cov8)));
  // Allowed: inside the span, and empty or this layer's (the stencil).
  __m256i mask = _mm256_and_si256(
      _mm256_cmpgt_epi32(_mm256_set1_epi32(m), lane),
      _mm256_or_si256(_mm256_cmpeq_epi32(cov, zero), _mm256_cmpeq_epi32(cov, _mm256_set1_epi32(layer))));
  if (_mm256_testz_si256(mask, mask)) return;
  const __m256 lanes = _mm256_cvtepi32_ps(lane);
  if (!t.sky) {
    const __m256 d = _mm256_add_ps(_mm256_set1_ps(d0), _mm256_mul_ps(lanes, _mm256_set1_ps(t.depth.ax)));
    const __m256 old = _mm256_maskload_ps(r.depth + i0, mask);
    mask = _mm256_and_si256(mask, _mm256_castps_si256(_mm256_cmp_ps(d, old, _CMP_LT_OQ)));
    if (_mm256_testz_si256(mask, mask)) return;
    if (whole)
      _mm256_storeu_ps(r.depth + i0, _mm256_blendv_ps(_mm256_loadu_ps(r.depth + i0), d,
                                                      _mm256_castsi256_ps(mask)));
    else
      _mm256_maskstore_ps(r.depth + i0, mask, d);
  }
  const int tw = r.texture->width(), th = r.texture->height();
  const __m256i u = _mm256_add_epi32(_mm256_set1_epi32(u0), _mm256_mullo_epi32(lane, _mm256_set1_epi32(du)));
  const __m256i v = _mm256_add_epi32(_mm256_set1_epi32(v0), _mm256_mullo_epi32(lane, _mm256_set1_epi32(dv)));
  const __m256i xi = _mm256_srai_epi32(u, 16), yi = _mm256_srai_epi32(v, 16);
  const __m256i one = _mm256_set1_epi32(1), xMax = _mm256_set1_epi32(tw - 1),
                yMax = _mm256_set1_epi32(th - 1);
  const __m256i x0 = avx2Clamp(xi, xMax), x1 = avx2Clamp(_mm256_add_epi32(xi, one), xMax);
  const __m256i stride = _mm256_set1_epi32(tw);
  const __m256i rowA = _mm256_mullo_epi32(avx2Clamp(yi, yMax), stride);
  const __m256i rowB = _mm256_mullo_epi32(avx2Clamp(_mm256_add_epi32(yi, one), yMax), stride);
  const int* tex = reinterpret_cast<const int*>(r.texture->data());
  __m256i t00, t01, t10, t11;
  // Texcoords are linear across the 8 pixels: when they stay within two
  // neighbouring texel rows and 16 texel columns inside the texture (the
  // usual case, a view near the keyframe's), loads and permutes stand in for
  // the gathers (slow on some CPUs). Per row, the texels at x (`at`) and
  // x + 1 (`next`) of each lane: one load each when the columns span at
  // most 8, else two and a blend by the lane's column. Rows yLo and yLo + 1
  // give the top texels, rows yLo + 1 and yLo + 2 the bottom ones, each lane
  // picking by its own row.
  const int xFirst = u0 >> 16, xLast = (u0 + 7 * du) >> 16;
  const int yFirst = v0 >> 16, yLast = (v0 + 7 * dv) >> 16;
  const int lo = std::min(xFirst, xLast), hi = std::max(xFirst, xLast);
  const int yLo = std::min(yFirst, yLast), yHi = std::max(yFirst, yLast);
  const bool wide = hi - lo > 7;
  if (yHi - yLo <= 1 && yLo >= 0 && yHi + 1 < th && lo >= 0 && hi - lo <= 15 &&
      lo + (wide ? 16 : 8) < tw) {
    const __m256i idx = _mm256_sub_epi32(xi, _mm256_set1_epi32(lo));
    const __m256i high = _mm256_cmpgt_epi32(idx, _mm256_set1_epi32(7));  // columns lo + 8 on
    const int* row0 = tex + static_cast<std::size_t>(yLo) * static_cast<std::size_t>(tw) + lo;
    const int* row1 = row0 + tw;
    const __m256i a0 = avx2Pick(row0, idx, high, wide), a1 = avx2Pick(row0 + 1, idx, high, wide);
    const __m256i b0 = avx2Pick(row1, idx, high, wide), b1 = avx2Pick(row1 + 1, idx, high, wide);
    if (yHi == yLo) {
      t00 = a0;
      t01 = a1;
      t10 = b0;
      t11 = b1;
    } else {
      const int* row2 = row1 + tw;
      const __m256i c0 = avx2Pick(row2, idx, high, wide), c1 = avx2Pick(row2 + 1, idx, high, wide);
      const __m256i down = _mm256_cmpgt_epi32(yi, _mm256_set1_epi32(yLo));  // this lane's top is row yLo + 1
      t00 = _mm256_blendv_epi8(a0, b0, down);
      t01 = _mm256_blendv_epi8(a1, b1, down);
      t10 = _mm256_blendv_epi8(b0, c0, down);
      t11 = _mm256_blendv_epi8(b1, c1, down);
    }
  } else {
    t00 = _mm256_i32gather_epi32(tex, _mm256_add_epi32(rowA, x0), 4);
    t01 = _mm256_i32gather_epi32(tex, _mm256_add_epi32(rowA, x1), 4);
    t10 = _mm256_i32gather_epi32(tex, _mm256_add_epi32(rowB, x0), 4);
    t11 = _mm256_i32gather_epi32(tex, _mm256_add_epi32(rowB, x1), 4);
  }
  // Weights (8 bits) in both 16-bit halves of each lane.
  const __m256i byte = _mm256_set1_epi32(255), full = _mm256_set1_epi32(0x01000100);
  __m256i wx = _mm256_and_si256(_mm256_srli_epi32(u, 8), byte);
  __m256i wy = _mm256_and_si256(_mm256_srli_epi32(v, 8), byte);
  wx = _mm256_or_si256(wx, _mm256_slli_epi32(wx, 16));
  wy = _mm256_or_si256(wy, _mm256_slli_epi32(wy, 16));
  const __m256i wx0 = _mm256_sub_epi16(full, wx), wy0 = _mm256_sub_epi16(full, wy);
  const __m256i low = _mm256_set1_epi32(0x00FF00FF);
  const __m256i e00 = _mm256_and_si256(t00, low), e01 = _mm256_and_si256(t01, low),
                e10 = _mm256_and_si256(t10, low), e11 = _mm256_and_si256(t11, low);
  const __m256i o00 = _mm256_srli_epi16(t00, 8), o01 = _mm256_srli_epi16(t01, 8),
                o10 = _mm256_srli_epi16(t10, 8), o11 = _mm256_srli_epi16(t11, 8);
  const __m256i rb = avx2Lerp(avx2Lerp(e00, e01, wx0, wx), avx2Lerp(e10, e11, wx0, wx), wy0, wy);
  const __m256i ga = avx2Lerp(avx2Lerp(o00, o01, wx0, wx), avx2Lerp(o10, o11, wx0, wx), wy0, wy);
  const __m256i rgba = _mm256_or_si256(_mm256_or_si256(rb, _mm256_slli_epi16(ga, 8)),
                                       _mm256_set1_epi32(static_cast<int>(0xFF000000u)));
  int* out = reinterpret_cast<int*>(r.colour + i0);
  if (whole) {
    const __m256i old = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(out));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_blendv_epi8(old, rgba, mask));
  } else {
    _mm256_maskstore_epi32(out, mask, rgba);
  }
  const unsigned bits = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(mask)));
  if (whole) {
    // The coverage and large-leaf bytes of the 8 pixels at once: 0xFF in
    // each byte whose lane was written.
    const std::uint64_t written = kByteLanes.mask[bits];
    std::uint64_t c8;
    std::memcpy(&c8, r.coverage + i0, 8);
    c8 = (c8 & ~written) | (written & (0x0101010101010101ull * layer));
    std::memcpy(r.coverage + i0, &c8, 8);
    if (r.large) {
      std::uint64_t l8;
      std::memcpy(&l8, r.large + i0, 8);
      l8 = (l8 & ~written) | (written & (0x0101010101010101ull * t.large));
      std::memcpy(r.large + i0, &l8, 8);
    }
  }
  for (unsigned left = bits; left;) {
    const int k = __builtin_ctz(left);
    left &= left - 1;
    const std::size_t i = i0 + static_cast<std::size_t>(k);
    if (!whole) {
      r.coverage[i] = layer;
      if (r.large) r.large[i] = t.large;
    }
    if (r.eyeZ) r.eyeZ[i] = t.sky ? kSkyEyeZ : 1.0f / (iw0 + t.invW.ax * static_cast<float>(k));
    else if (whole) break;
  }
}

__attribute__((target("avx2"))) void spanAvx2(const Raster& r, const Triangle& t,
                                               std::size_t i0, int count, const Run* runs,
                                               float d0, float iw0, std::uint8_t layer) {
  const std::size_t w = static_cast<std::size_t>(r.width);
  const std::size_t rowEnd = (i0 / w + 1) * w;
  for (int k = 0; k < count; k += 8) {
    const Run& run = runs[k / 16];
    const int j = k % 16;
    const std::size_t at = i0 + static_cast<std::size_t>(k);
    group8(r, t, at, std::min(8, count - k), at + 8 <= rowEnd, run.u0 + run.du * j,
           run.du, run.v0 + run.dv * j, run.dv, d0 + t.depth.ax * static_cast<float>(k),
           iw0 + t.invW.ax * static_cast<float>(k), layer);
  }
}

// A one-use barrier for the warper's threads: the last to arrive runs the
// completion, then all go on. Waiters spin briefly (the threads' set-up
// shares are even, so they arrive close together), then sleep on a
// condition variable. (libstdc++ 12's std::barrier was seen to wake a
// waiter about 1 ms late.)
class Rendezvous {
 public:
  explicit Rendezvous(int threads) : left_(threads) {}
  template <typename F>
  void arriveAndWait(F&& completion) {
    if (left_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      completion();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        done_.store(true, std::memory_order_release);
      }
      cv_.notify_all();
      return;
    }
    for (int spin = 0; spin < 20000; ++spin) {
      if (done_.load(std::memory_order_acquire)) return;
      _mm_pause();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [&] { return done_.load(std::memory_order_acquire); });
  }

 private:
  std::atomic<int> left_;
  std::atomic<bool> done_{false};
  std::mutex mutex_;
  std::condition_variable cv_;
};

// The warper's helper threads, started once: run(n, fn) calls fn(b) for b
// in [1, n) on helpers and fn(0) on the caller, and returns when all are
// done. Helpers sleep on a condition variable between calls.
class HelperThreads {
 public:
  // Error when a thread cannot be started (say, a process thread limit).
  static Result<std::unique_ptr<HelperThreads>> create(int helpers) {
    std::unique_ptr<HelperThreads> h(new HelperThreads);
    try {
      for (int k = 0; k < helpers; ++k) h->threads_.emplace_back([p = h.get(), k] { p->loop(k + 1); });
    } catch (const std::system_error& e) {
      return makeError("CPU warper: could not start thread " + std::to_string(h->threads_.size() + 2) +
                       " of " + std::to_string(helpers + 1) + " (" + e.what() +
                       "); use fewer --warper-threads");
    }
    return h;
  }
  ~HelperThreads() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  int helpers() const { return static_cast<int>(threads_.size()); }

  template <typename F>
  void run(int n, F& fn) {
    const int others = std::min(n - 1, helpers());
    if (others > 0) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        job_ = [&fn](int b) { fn(b); };
        active_ = others + 1;
        pending_ = others;
        ++generation_;
      }
      wake_.notify_all();
    }
    fn(0);
    if (others > 0) {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, [&] { return pending_ == 0; });
      job_ = nullptr;
    }
  }

 private:
  HelperThreads() = default;
  void loop(int b) {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (b >= active_) continue;
      lock.unlock();
      job_(b);
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void(int)> job_;
  std::uint64_t generation_ = 0;
  int active_ = 0, pending_ = 0;
  bool stop_ = false;
};

class CpuWarper final : public Warper {
 public:
  CpuWarper(const WarpOptions& options, int threads, bool simd,
            std::unique_ptr<HelperThreads> helpers)
      : options_(options),
        threads_(threads),
        avx2_(simd && __builtin_cpu_supports("avx2")),
        helpers_(std::move(helpers)) {}

  const WarpOptions& options() const override { return options_; }

  Result<std::unique_ptr<WarpSource>> upload(const keyframe::Keyframe& kf,
                                             const keyframe::QuadMesh& mesh,
                                             WarpStats* stats) override {
    if (kf.colour.width() != mesh.width || kf.colour.height() != mesh.height ||
        mesh.width < 1 || mesh.height < 1)
      return makeError("CPU warper: keyframe " + std::to_string(kf.colour.width()) + "x" +
                       std::to_string(kf.colour.height()) + " and its mesh " +
                       std::to_string(mesh.width) + "x" + std::to_string(mesh.height) +
                       ": expected one non-empty size");
    Stopwatch sw;
    auto src = std::make_unique<CpuWarpSource>();
    src->camera = kf.camera;
    src->texture = kf.colour;
    src->quads = static_cast<int>(mesh.quads.size());
    std::vector<keyframe::PixelRect> sky;
    if (options_.skyBackdrop) emptyRects(kf.covered, sky);
    src->skyRects = static_cast<int>(sky.size());
    const std::size_t vertices = (mesh.quads.size() + sky.size()) * 4;
    src->pos.reserve(vertices * 4);
    src->tex.reserve(vertices * 3);
    src->large.reserve(mesh.quads.size());
    const double invW = 1.0 / mesh.width, invH = 1.0 / mesh.height;
    const int cell = std::max(1, options_.subdivideCellPx);
    for (const keyframe::Quad& q : mesh.quads) {
      const int grid = ((q.rect.width() + cell - 1) / cell) * ((q.rect.height() + cell - 1) / cell);
      src->large.push_back(options_.markLargeQuads && grid > 1);
      for (int k = 0; k < 4; ++k) {
        for (int c = 0; c < 3; ++c) src->pos.push_back(static_cast<float>(q.world[k][c]));
        src->pos.push_back(1.0f);
        const double s = q.pixel[k].x * invW, t = q.pixel[k].y * invH, w = q.eyeZ[k];
        src->tex.push_back(static_cast<float>(s * w));
        src->tex.push_back(static_cast<float>(t * w));
        src->tex.push_back(static_cast<float>(w));
      }
    }
    // Sky: the direction through each corner at depth 1 along W (texcoord (s, t, 1)).
    for (const keyframe::PixelRect& r : sky) {
      const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
      const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3 d = kf.camera.unproject(us[k], vs[k], 1.0) - kf.camera.eye;
        for (int c = 0; c < 3; ++c) src->pos.push_back(static_cast<float>(d[c]));
        src->pos.push_back(0.0f);
        src->tex.push_back(static_cast<float>(us[k] * invW));
        src->tex.push_back(static_cast<float>(vs[k] * invH));
        src->tex.push_back(1.0f);
      }
    }
    if (stats) {
      *stats = WarpStats{};
      stats->uploadMs = sw.ms();
      stats->quads = src->quads;
      stats->drawnQuads = src->quads;
      stats->vertices = static_cast<int>(vertices);
    }
    return std::unique_ptr<WarpSource>(std::move(src));
  }

  Status warp(const WarpSource& source, const Camera& target, Layer& out,
              WarpStats* stats) override {
    HW_TRY(checkTarget(target));
    const auto& src = static_cast<const CpuWarpSource&>(source);
    Stopwatch sw;
    run(target, out, src, nullptr, false);
    if (stats) {
      *stats = WarpStats{};
      stats->drawMs = sw.ms();
      stats->quads = src.quads;
      stats->uncovered = foregroundUncovered_;
    }
    return {};
  }

  Status warpPair(const WarpSource& foreground, const WarpSource* background,
                  const Camera& target, Layer& out, bool skipBackgroundWhenCovered,
                  PairStats* stats) override {
    HW_TRY(checkTarget(target));
    const auto& fg = static_cast<const CpuWarpSource&>(foreground);
    const auto* bg = static_cast<const CpuWarpSource*>(background);
    Stopwatch sw;
    // Each band draws the foreground, then the background where its rows
    // kept empty pixels (the coverage is the stencil: the background writes
    // only where it is still 0).
    run(target, out, fg, bg, !skipBackgroundWhenCovered);
    const double ms = sw.ms();
    if (stats) {
      *stats = PairStats{};
      // Set-up and drawing run interleaved on the threads, the foreground's
      // and background's too: the time is split between the layers in
      // proportion to their quads.
      const double fgShare =
          bg ? double(fg.quads + 1) / double(fg.quads + bg->quads + 2) : 1.0;
      stats->foregroundMs = ms * fgShare;
      stats->backgroundMs = ms * (1.0 - fgShare);
      stats->readbackMs = 0;  // each band counts its own pixels of each layer
      stats->quadsForeground = fg.quads;
      stats->backgroundDrawn = bg && (foregroundUncovered_ > 0 || !skipBackgroundWhenCovered);
      stats->quadsBackground = stats->backgroundDrawn ? bg->quads : 0;
      stats->uncoveredByForeground = foregroundUncovered_;
      stats->fromBackground = fromBackground_;
      stats->uncovered = uncovered_;
    }
    return {};
  }

 private:
  Status checkTarget(const Camera& target) const {
    if (target.width < 1 || target.height < 1 || target.width > 16384 || target.height > 16384)
      return makeError("CPU warper: target " + std::to_string(target.width) + "x" +
                       std::to_string(target.height) + ": expected 1x1 to 16384x16384");
    return {};
  }

  // Sizes the layer's images (their pixels are cleared by the bands).
  void sizeTarget(const Camera& target, Layer& out) {
    const int w = target.width, h = target.height;
    if (out.colour.width() != w || out.colour.height() != h) {
      out.colour.resize(w, h);
      out.coverage.resize(w, h);
    }
    if (options_.markLargeQuads) {
      if (out.largeQuad.width() != w || out.largeQuad.height() != h) out.largeQuad.resize(w, h);
    } else {
      out.largeQuad.resize(0, 0);
    }
    if (options_.writeEyeZ) {
      if (out.eyeZ.width() != w || out.eyeZ.height() != h) out.eyeZ.resize(w, h);
    } else {
      out.eyeZ.resize(0, 0);
    }
    depth_.resize(out.colour.size());
  }

  // Clears rows [row0, row1) of the target.
  void clearRows(Layer& out, int row0, int row1) {
    const std::size_t w = static_cast<std::size_t>(out.colour.width());
    const std::size_t i0 = static_cast<std::size_t>(row0) * w, i1 = static_cast<std::size_t>(row1) * w;
    std::fill(out.coverage.data() + i0, out.coverage.data() + i1, 0);
    std::fill(out.colour.data() + i0, out.colour.data() + i1, Rgba8{0, 0, 0, 0});
    if (options_.markLargeQuads) std::fill(out.largeQuad.data() + i0, out.largeQuad.data() + i1, 0);
    if (options_.writeEyeZ) std::fill(out.eyeZ.data() + i0, out.eyeZ.data() + i1, 0.0f);
    std::fill(depth_.begin() + static_cast<std::ptrdiff_t>(i0),
              depth_.begin() + static_cast<std::ptrdiff_t>(i1), 1.0f);
  }

  // Rounds half away from zero, as std::llround, for |x| < 2^52 (the
  // snapped positions here stay far below). For 0.5 <= |x|, x ± 0.5 is
  // exact wherever the truncation could change (it stays in x's binade
  // there); below 0.5 it may round up to 1, so those are 0 outright.
  static std::int64_t roundHalfAway(double x) {
    if (std::fabs(x) < 0.5) return 0;
    return static_cast<std::int64_t>(x + std::copysign(0.5, x));
  }

  // Transforms, clips and snaps the quads and sky rectangles [k0, k1) of
  // `src` (quads first, then sky) seen through `vp`, appending to `pass`;
  // adds each triangle's work per row to rowWork (a difference array: +at
  // minY, -at maxY + 1): a fixed cost and its bounding box's width over
  // spanShare (the background's spans are cut to the pixels the foreground
  // left empty, which are few).
  void setUp(const CpuWarpSource& src, const Camera& target, const glm::mat4& vp, int k0, int k1,
             Pass& pass, std::int64_t* rowWork, int spanShare) const {
    const double w = target.width, h = target.height;
    for (int k = k0; k < k1; ++k) {
      ClipVertex v[4];
      unsigned code[4];
      // Outside one side of the view (every corner past the same clip
      // plane): no pixel to draw, and nothing to clip or snap.
      unsigned outside = 0xF;
      for (int c = 0; c < 4; ++c) {
        const std::size_t at = static_cast<std::size_t>(k) * 4 + static_cast<std::size_t>(c);
        const float* p = &src.pos[at * 4];
        const glm::vec4 clip = vp * glm::vec4(p[0], p[1], p[2], p[3]);
        const float* t = &src.tex[at * 3];
        v[c] = {clip.x, clip.y, clip.z, clip.w, t[0], t[1], t[2]};
        outside &= (v[c].x > v[c].w ? 1u : 0u) | (v[c].x < -v[c].w ? 2u : 0u) |
                   (v[c].y > v[c].w ? 4u : 0u) | (v[c].y < -v[c].w ? 8u : 0u);
        code[c] = clipOutcode(v[c]);
      }
      if (outside) continue;
      const bool sky = k >= src.quads;
      const bool large = !sky && src.large[static_cast<std::size_t>(k)];
      static constexpr int kTri[2][3] = {{0, 1, 2}, {0, 2, 3}};
      for (const auto& tri : kTri) {
        ClipVertex poly[12], scratch[12];
        for (int c = 0; c < 3; ++c) poly[c] = v[tri[c]];
        // Inside every clip plane (the usual case): nothing to clip.
        const bool clip = (code[tri[0]] | code[tri[1]] | code[tri[2]]) != 0;
        const int n = clip ? clipPolygon(poly, 3, scratch) : 3;
        for (int f = 1; f + 1 < n; ++f) {
          const ClipVertex* fan[3] = {&poly[0], &poly[f], &poly[f + 1]};
          Triangle t;
          double sx[3], sy[3], depth[3], ps[3], qs[3], rs[3], iw[3];
          for (int c = 0; c < 3; ++c) {
            const ClipVertex& cv = *fan[c];
            const double inv = 1.0 / cv.w;
            sx[c] = (cv.x * inv + 1.0) * 0.5 * w;
            sy[c] = (1.0 - cv.y * inv) * 0.5 * h;
            t.x[c] = roundHalfAway(sx[c] * kSubPixel);
            t.y[c] = roundHalfAway(sy[c] * kSubPixel);
            sx[c] = static_cast<double>(t.x[c]) / kSubPixel;
            sy[c] = static_cast<double>(t.y[c]) / kSubPixel;
            depth[c] = cv.z * inv * 0.5 + 0.5;
            ps[c] = cv.s * inv;
            qs[c] = cv.t * inv;
            rs[c] = cv.q * inv;
            iw[c] = inv;
          }
          std::int64_t area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) -
                              (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
          if (area == 0) continue;
          if (area < 0) {  // either facing: order the corners so the area is positive
            std::swap(t.x[1], t.x[2]);
            std::swap(t.y[1], t.y[2]);
            std::swap(sx[1], sx[2]);
            std::swap(sy[1], sy[2]);
            std::swap(depth[1], depth[2]);
            std::swap(ps[1], ps[2]);
            std::swap(qs[1], qs[2]);
            std::swap(rs[1], rs[2]);
            std::swap(iw[1], iw[2]);
            area = -area;
          }
          const std::int64_t loX = std::min({t.x[0], t.x[1], t.x[2]});
          const std::int64_t hiX = std::max({t.x[0], t.x[1], t.x[2]});
          const std::int64_t loY = std::min({t.y[0], t.y[1], t.y[2]});
          const std::int64_t hiY = std::max({t.y[0], t.y[1], t.y[2]});
          // Pixels whose centre (p·256 + 128) lies in [lo, hi].
          t.minX = static_cast<int>(std::max<std::int64_t>(0, (loX - 128 + 255) >> 8));
          t.maxX = static_cast<int>(std::min<std::int64_t>(target.width - 1, (hiX - 128) >> 8));
          t.minY = static_cast<int>(std::max<std::int64_t>(0, (loY - 128 + 255) >> 8));
          t.maxY = static_cast<int>(std::min<std::int64_t>(target.height - 1, (hiY - 128) >> 8));
          if (t.minX > t.maxX || t.minY > t.maxY) continue;
          const double area2 = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
          t.depth = plane(sx, sy, depth, area2);
          t.p = plane(sx, sy, ps, area2);
          t.q = plane(sx, sy, qs, area2);
          t.r = plane(sx, sy, rs, area2);
          t.invW = plane(sx, sy, iw, area2);
          t.sky = sky;
          t.large = large;
          (sky ? pass.sky : pass.quads).push_back(t);
          // A row's work: its span (the box's width, at most) and a fixed
          // cost for the row's edge set-up.
          const std::int64_t rowCost = (t.maxX - t.minX + 1) / spanShare + 16;
          rowWork[t.minY] += rowCost;
          rowWork[t.maxY + 1] -= rowCost;
        }
      }
    }
  }

  // Warps `fg` (coverage value 1), then `bg` (2) where the foreground left
  // pixels empty (always, with `bgAlways`, else only in rows it left some)
  // into `out`, on threads_ threads: each sets up its share of the quads of
  // both, then draws a band of rows, the bands cut so their estimated work
  // (the triangles' pixels per row) is about even. Pixels do not depend on
  // the number of threads: every band draws every triangle in the same order.
  void run(const Camera& target, Layer& out, const CpuWarpSource& fg, const CpuWarpSource* bg,
           bool bgAlways) {
    sizeTarget(target, out);
    const int threads = std::max(1, std::min(threads_, target.height));
    const std::size_t T = static_cast<std::size_t>(threads);
    const std::size_t rows = static_cast<std::size_t>(target.height);
    fgParts_.resize(T);
    bgParts_.resize(T);
    rowWork_.assign(T * (rows + 1), 0);
    bandUncovered_.assign(T, 0);
    bandFromBackground_.assign(T, 0);
    bandUncoveredAfter_.assign(T, 0);
    firstEmpty_.resize(rows);
    lastEmpty_.resize(rows);
    bandRows_.resize(T + 1);
    // As the GL warper: the product in double, rounded to float once.
    const glm::mat4 vp(target.projectionMatrix(DepthMode::Fixed24, options_.infiniteFar) *
                       target.viewMatrix());
    Raster r{target.width,
             target.height,
             nullptr,
             out.colour.data(),
             out.coverage.data(),
             options_.markLargeQuads ? out.largeQuad.data() : nullptr,
             options_.writeEyeZ ? out.eyeZ.data() : nullptr,
             depth_.data()};
    r.avx2 = avx2_;
    auto cutBands = [this, T, rows] {
      std::int64_t total = 0, perRow = 0;
      for (std::size_t y = 0; y < rows; ++y) {
        for (std::size_t k = 0; k < T; ++k) perRow += rowWork_[k * (rows + 1) + y];
        total += perRow;
      }
      bandRows_[0] = 0;
      std::size_t b = 1;
      std::int64_t sum = 0;
      perRow = 0;
      for (std::size_t y = 0; y < rows && b < T; ++y) {
        for (std::size_t k = 0; k < T; ++k) perRow += rowWork_[k * (rows + 1) + y];
        sum += perRow;
        // Row y ends band b - 1 once the work so far reaches its share.
        while (b < T && sum * static_cast<std::int64_t>(T) >= total * static_cast<std::int64_t>(b))
          bandRows_[b++] = static_cast<int>(y + 1);
      }
      for (; b <= T; ++b) bandRows_[b] = static_cast<int>(rows);
    };
    Rendezvous sync(threads);
    auto work = [&](int b) {
      const std::size_t bi = static_cast<std::size_t>(b);
      std::int64_t* rowWork = &rowWork_[bi * (rows + 1)];
      for (const auto& [src, parts] :
           {std::pair{&fg, &fgParts_}, std::pair{bg, &bgParts_}}) {
        Pass& part = (*parts)[bi];
        part.sky.clear();
        part.quads.clear();
        if (!src) continue;
        const int n = src->quads + src->skyRects;
        setUp(*src, target, vp, n * b / threads, n * (b + 1) / threads, part, rowWork,
              src == &fg ? 1 : 4);
      }
      sync.arriveAndWait(cutBands);
      const int row0 = bandRows_[bi], row1 = bandRows_[bi + 1];
      clearRows(out, row0, row1);
      Raster rb = r;
      rb.texture = &fg.texture;
      for (const Pass& p : fgParts_)
        for (const Triangle& t : p.sky) rb.draw(t, row0, row1, 1);
      for (const Pass& p : fgParts_)
        for (const Triangle& t : p.quads) rb.draw(t, row0, row1, 1);
      int empty = 0;
      const std::size_t w = static_cast<std::size_t>(target.width);
      for (int y = row0; y < row1; ++y) {
        const std::uint8_t* c = rb.coverage + static_cast<std::size_t>(y) * w;
        int n = 0, lo = -1, hi = -1;
        std::size_t x = 0;
        for (; x + 8 <= w; x += 8) {
          std::uint64_t word8;
          std::memcpy(&word8, c + x, 8);
          // No zero byte in the word: nothing empty here.
          if (((word8 - 0x0101010101010101ull) & ~word8 & 0x8080808080808080ull) == 0) continue;
          for (std::size_t k = x; k < x + 8; ++k)
            if (c[k] == 0) {
              ++n;
              if (lo < 0) lo = static_cast<int>(k);
              hi = static_cast<int>(k);
            }
        }
        for (; x < w; ++x)
          if (c[x] == 0) {
            ++n;
            if (lo < 0) lo = static_cast<int>(x);
            hi = static_cast<int>(x);
          }
        firstEmpty_[static_cast<std::size_t>(y)] = lo;
        lastEmpty_[static_cast<std::size_t>(y)] = hi;
        empty += n;
      }
      bandUncovered_[bi] = empty;
      bandUncoveredAfter_[bi] = empty;
      if (!bg || (empty == 0 && !bgAlways)) return;
      // The background's own depth test: the pixels it may write still hold
      // the cleared depth (the foreground wrote depth only where it wrote).
      rb.firstEmpty = firstEmpty_.data();
      rb.lastEmpty = lastEmpty_.data();
      rb.texture = &bg->texture;
      for (const Pass& p : bgParts_)
        for (const Triangle& t : p.sky) rb.draw(t, row0, row1, 2);
      for (const Pass& p : bgParts_)
        for (const Triangle& t : p.quads) rb.draw(t, row0, row1, 2);
      // What the background gave and what is still empty, in this band's rows.
      int fromBg = 0, still = 0;
      for (int y = row0; y < row1; ++y) {
        if (firstEmpty_[static_cast<std::size_t>(y)] < 0) continue;
        const std::uint8_t* c = rb.coverage + static_cast<std::size_t>(y) * w;
        for (int x = firstEmpty_[static_cast<std::size_t>(y)]; x <= lastEmpty_[static_cast<std::size_t>(y)]; ++x) {
          fromBg += c[x] == 2;
          still += c[x] == 0;
        }
      }
      bandFromBackground_[bi] = fromBg;
      bandUncoveredAfter_[bi] = still;
    };
    helpers_->run(threads, work);
    foregroundUncovered_ = fromBackground_ = uncovered_ = 0;
    for (std::size_t b = 0; b < T; ++b) {
      foregroundUncovered_ += bandUncovered_[b];
      fromBackground_ += bandFromBackground_[b];
      uncovered_ += bandUncoveredAfter_[b];
    }
  }

  WarpOptions options_;
  int threads_;
  bool avx2_;
  std::vector<Pass> fgParts_, bgParts_;  // per thread
  std::vector<float> depth_;
  std::vector<std::int64_t> rowWork_;    // per thread, rows + 1
  std::vector<int> bandRows_;
  std::vector<int> bandUncovered_, bandFromBackground_, bandUncoveredAfter_;
  std::vector<int> firstEmpty_, lastEmpty_;
  std::unique_ptr<HelperThreads> helpers_;  // threads_ - 1 of them
  int foregroundUncovered_ = 0, fromBackground_ = 0, uncovered_ = 0;
};

}  // namespace

const char* warperChoiceName(WarperChoice c) {
  switch (c) {
    case WarperChoice::Auto: return "auto";
    case WarperChoice::Gl: return "gl";
    case WarperChoice::Cpu: return "cpu";
  }
  return "?";
}

bool isSoftwareRasteriser(const std::string& glRenderer) {
  for (const char* name :
       {"llvmpipe", "softpipe", "swrast", "Software Rasterizer", "Mesa OffScreen", "SWR"})
    if (glRenderer.find(name) != std::string::npos) return true;
  return false;
}

std::string cpuWarperUnsupported(const WarpOptions& o) {
  if (o.subdivision != Subdivision::None) return "--subdivide other than none";
  if (o.texcoords != TexcoordMode::Projective) return "--texcoords affine";
  if (o.primitives == Primitives::Points) return "--primitives points";
  if (o.cullBackground) return "--cull-background";
  return {};
}

Result<std::unique_ptr<Warper>> createCpuWarper(const WarpOptions& options, int threads,
                                                bool simd) {
  const std::string why = cpuWarperUnsupported(options);
  if (!why.empty()) return makeError("the CPU warper does not support " + why);
  if (threads < 1) return makeError("CPU warper: " + std::to_string(threads) + " threads: expected at least 1");
  auto helpers = HelperThreads::create(threads - 1);
  if (!helpers) return helpers.error();
  return std::unique_ptr<Warper>(new CpuWarper(options, threads, simd, std::move(*helpers)));
}

}  // namespace hw::warp
