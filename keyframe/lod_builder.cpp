#include "keyframe/lod_builder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/check.h"
#include "core/short_number.h"
#include "core/timer.h"

namespace hw::keyframe {

namespace {

bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string sizeStr(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

Status validateCamera(const Camera& c) {
  if (!finite3(c.eye) || !finite3(c.right) || !finite3(c.up) || !finite3(c.forward)) {
    return makeError("LOD builder: camera pose is not finite");
  }
  if (!(c.fovYRadians > 0.0 && c.fovYRadians < 3.141592653589793)) {
    return makeError("LOD builder: camera fovYRadians must be in (0, pi), got " +
                     shortNumber(c.fovYRadians));
  }
  if (!(c.nearPlane > 0.0 && c.farPlane > c.nearPlane && std::isfinite(c.farPlane))) {
    return makeError("LOD builder: camera needs 0 < near < far < inf, got near " +
                     shortNumber(c.nearPlane) + ", far " + shortNumber(c.farPlane));
  }
  return {};
}

// Eye depth bounds for the corners of one leaf (DESIGN.md: horizon corners).
// The fit is evaluated half a pixel beyond the outermost pixel centres, which
// on a surface seen edge-on (the horizon) can reach z' ≥ S·f/(f−n), i.e. a
// depth at or past infinity. Depth may not fall below half, nor rise above
// twice, what the leaf's own corner pixels hold, nor leave [n/2, 100·f]. For a
// plane, 1/z is affine in pixels, so doubling z within half a pixel only
// happens within one pixel of the plane's horizon line.
struct DepthBounds {
  double lo, hi;
};
DepthBounds cornerBounds(double zObsMin, double zObsMax, double n, double f) {
  const double hardLo = 0.5 * n, hardHi = 100.0 * f;
  double lo = 0.5 * zObsMin;
  if (!(lo >= hardLo)) lo = hardLo;  // also catches NaN
  if (!(lo <= hardHi)) lo = hardHi;
  double hi = 2.0 * zObsMax;
  if (!(hi <= hardHi)) hi = hardHi;
  if (!(hi >= lo)) hi = lo;
  return {lo, hi};
}

// NaN goes to the lower bound.
double clampDepth(double z, const DepthBounds& b) {
  if (!(z >= b.lo)) return b.lo;
  if (!(z <= b.hi)) return b.hi;
  return z;
}

}  // namespace

const char* planarityName(Planarity p) {
  switch (p) {
    case Planarity::Stencil:
      return "stencil";
    case Planarity::RegionLocal:
      return "region-local";
  }
  return "?";
}

bool parsePlanarity(const char* s, Planarity* out) {
  if (s == nullptr) return false;
  for (Planarity p : {Planarity::Stencil, Planarity::RegionLocal}) {
    if (std::strcmp(s, planarityName(p)) == 0) {
      *out = p;
      return true;
    }
  }
  return false;
}

namespace {

constexpr double kGradNone = std::numeric_limits<double>::infinity();

// One pixel of computeDepthGradient (borders; any neighbour may be missing):
// per axis the smaller one-sided difference, 0 without a valid neighbour.
inline float gradientAt(const double* zr, const double* zu, const double* zd,
                        const std::uint8_t* vr, const std::uint8_t* vu, const std::uint8_t* vd,
                        int x, int w) {
  if (vr[x] == 0) return 0.0f;
  const bool hl = x > 0 && vr[x - 1] != 0, hr = x + 1 < w && vr[x + 1] != 0;
  const bool hu = vu != nullptr && vu[x] != 0, hd = vd != nullptr && vd[x] != 0;
  const double l = hl ? std::fabs(zr[x] - zr[x - 1]) : kGradNone;
  const double r = hr ? std::fabs(zr[x + 1] - zr[x]) : kGradNone;
  const double u = hu ? std::fabs(zr[x] - zu[x]) : kGradNone;
  const double d = hd ? std::fabs(zd[x] - zr[x]) : kGradNone;
  const double gx = hl || hr ? std::min(l, r) : 0.0, gy = hu || hd ? std::min(u, d) : 0.0;
  return static_cast<float>(std::min(std::max(gx, gy), double(std::numeric_limits<float>::max())));
}

// Interior columns of an interior row: the same result as gradientAt,
// branch-free so that -O3 vectorises it. The validity selects are bit masks
// (GCC does not if-convert floating-point compares that may trap), the
// mins/maxes the plain `a < b ? a : b` pattern it turns into minpd/maxpd.
inline double bitsToDouble(std::uint64_t u) {
  double d;
  std::memcpy(&d, &u, sizeof d);
  return d;
}
inline std::uint64_t doubleToBits(double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}
void gradientRowInterior(const double* __restrict zr, const double* __restrict zu,
                         const double* __restrict zd, const std::uint8_t* __restrict vr,
                         const std::uint8_t* __restrict vu, const std::uint8_t* __restrict vd,
                         float* __restrict g, int w) {
  const double cap = std::numeric_limits<float>::max();
  const std::uint64_t none = doubleToBits(kGradNone);
  auto mask = [](std::uint8_t v) { return std::uint64_t{0} - static_cast<std::uint64_t>(v != 0); };
  auto pick = [none](double d, std::uint64_t m) {
    return bitsToDouble((doubleToBits(d) & m) | (none & ~m));
  };
  for (int x = 1; x + 1 < w; ++x) {
    const double c = zr[x];
    const std::uint64_t ml = mask(vr[x - 1]), mr = mask(vr[x + 1]);
    const std::uint64_t mu = mask(vu[x]), md = mask(vd[x]);
    const double l = pick(std::fabs(c - zr[x - 1]), ml), r = pick(std::fabs(zr[x + 1] - c), mr);
    const double u = pick(std::fabs(c - zu[x]), mu), d = pick(std::fabs(zd[x] - c), md);
    const double mx = l < r ? l : r, my = u < d ? u : d;
    const double gx = bitsToDouble(doubleToBits(mx) & (ml | mr));  // no side: 0
    const double gy = bitsToDouble(doubleToBits(my) & (mu | md));
    const double m = gx > gy ? gx : gy;
    const double v = m < cap ? m : cap;
    g[x] = static_cast<float>(bitsToDouble(doubleToBits(v) & mask(vr[x])));
  }
}

}  // namespace

void computeDepthGradient(ImageView<const double> zPrime, ImageView<const std::uint8_t> valid,
                          Image<float>* out) {
  HW_CHECK(out != nullptr);
  HW_CHECK_EQ(zPrime.width, valid.width);
  HW_CHECK_EQ(zPrime.height, valid.height);
  const int w = zPrime.width, h = zPrime.height;
  if (out->width() != w || out->height() != h) out->resize(w, h);
  for (int y = 0; y < h; ++y) {
    const double* zr = zPrime.row(y);
    const double* zu = y > 0 ? zPrime.row(y - 1) : nullptr;
    const double* zd = y + 1 < h ? zPrime.row(y + 1) : nullptr;
    const std::uint8_t* vr = valid.row(y);
    const std::uint8_t* vu = y > 0 ? valid.row(y - 1) : nullptr;
    const std::uint8_t* vd = y + 1 < h ? valid.row(y + 1) : nullptr;
    float* g = out->view().row(y);
    if (zu != nullptr && zd != nullptr && w > 2) {
      gradientRowInterior(zr, zu, zd, vr, vu, vd, g, w);
      g[0] = gradientAt(zr, zu, zd, vr, vu, vd, 0, w);
      g[w - 1] = gradientAt(zr, zu, zd, vr, vu, vd, w - 1, w);
    } else {
      for (int x = 0; x < w; ++x) g[x] = gradientAt(zr, zu, zd, vr, vu, vd, x, w);
    }
  }
}

// The grazing floors of tests/gl/keyframe_lod_gl_test.cpp (24-bit depth)
// need at most 0.0016 to be clean at τ = 2: 0.005 leaves a 3× margin. Read
// as a relative slope change: neighbouring pixels whose depth slopes differ
// by up to 0.5 % (plus τ) count as one plane.
double suggestedTauGradient() { return 0.005; }

double tauFromParallax(double parallaxPx, const Camera& camera) {
  const double n = camera.nearPlane, f = camera.farPlane;
  return parallaxPx * kZPrimeScale * f * n / (camera.fx() * (f - n));
}

Status LodBuilder::prepare(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                           const Camera& camera, const LodOptions& options) {
  prepared_ = false;
  const int w = zPrime.width, h = zPrime.height;
  if (covered.width != w || covered.height != h) {
    return makeError("LOD builder: depth is " + sizeStr(w, h) + " but coverage mask is " +
                     sizeStr(covered.width, covered.height));
  }
  if (camera.width != w || camera.height != h) {
    return makeError("LOD builder: depth is " + sizeStr(w, h) + " but camera is " +
                     sizeStr(camera.width, camera.height));
  }
  if (w <= 0 || h <= 0 || zPrime.data == nullptr || covered.data == nullptr) {
    return makeError("LOD builder: empty depth buffer (" + sizeStr(w, h) + ")");
  }
  if (static_cast<long long>(w + 1) * (h + 1) > (1LL << 30)) {
    return makeError("LOD builder: depth buffer " + sizeStr(w, h) + " exceeds 2^30 pixels");
  }
  HW_TRY(validateCamera(camera));
  if (!(options.tau >= 0.0 && std::isfinite(options.tau))) {
    return makeError("LOD builder: tau must be finite and >= 0, got " + shortNumber(options.tau));
  }
  if (!(options.tauParallaxPx >= 0.0 && std::isfinite(options.tauParallaxPx))) {
    return makeError("LOD builder: tauParallaxPx must be finite and >= 0, got " +
                     shortNumber(options.tauParallaxPx));
  }
  if (!(options.mergeToleranceZPrime >= 0.0 && std::isfinite(options.mergeToleranceZPrime))) {
    return makeError("LOD builder: mergeToleranceZPrime must be finite and >= 0, got " +
                     shortNumber(options.mergeToleranceZPrime));
  }
  if (!(options.misfitToleranceZPrime >= 0.0 && std::isfinite(options.misfitToleranceZPrime))) {
    return makeError("LOD builder: misfitToleranceZPrime must be finite and >= 0, got " +
                     shortNumber(options.misfitToleranceZPrime));
  }
  if (!(options.tauGradient >= 0.0 && std::isfinite(options.tauGradient))) {
    return makeError("LOD builder: tauGradient must be finite and >= 0, got " +
                     shortNumber(options.tauGradient));
  }
  if (options.planarity != Planarity::Stencil && options.planarity != Planarity::RegionLocal) {
    return makeError("LOD builder: unknown planarity " +
                     std::to_string(static_cast<int>(options.planarity)));
  }
  if (options.criterion != DeltaCriterion::FivePoint &&
      options.criterion != DeltaCriterion::PerAxisMax) {
    return makeError("LOD builder: unknown Δ criterion " +
                     std::to_string(static_cast<int>(options.criterion)));
  }

  Stopwatch sw;
  zPrime_ = zPrime;
  camera_ = camera;
  options_ = options;
  tauZPrime_ =
      options.tauParallaxPx > 0.0 ? tauFromParallax(options.tauParallaxPx, camera) : options.tau;

  // Valid = drawn and finite: a NaN/inf z' is treated as empty.
  if (valid_.width() != w || valid_.height() != h) valid_.resize(w, h);
  long long validCount = 0;
  for (int y = 0; y < h; ++y) {
    const double* __restrict zr = zPrime.row(y);
    const std::uint8_t* __restrict cr = covered.row(y);
    std::uint8_t* __restrict vr = valid_.view().row(y);
    // Three simple loops: written as one, GCC 12 kept a flag on the stack
    // and stalled on every pixel (1.8 against 0.6 ms for prepare at 512²).
    for (int x = 0; x < w; ++x)
      vr[x] = static_cast<std::uint8_t>(std::fabs(zr[x]) <= std::numeric_limits<double>::max());
    for (int x = 0; x < w; ++x) vr[x] &= static_cast<std::uint8_t>(cr[x] != 0);
    int rowCount = 0;
    for (int x = 0; x < w; ++x) rowCount += vr[x];
    validCount += rowCount;
  }
  emptyPixels_ = static_cast<long long>(w) * h - validCount;

  computeDeltaBuffer(zPrime, valid_.view(), options.criterion, &delta_);
  if (options.tauGradient > 0.0) computeDepthGradient(zPrime, valid_.view(), &grad_);
  deltaMs_ = sw.ms();
  prepared_ = true;
  return {};
}

template <class Clean>
int LodBuilder::findCut(const Region& r, bool cutX, Clean regionClean) const {
  const int lo = cutX ? r.x0 : r.y0;
  const int len = cutX ? r.x1 - r.x0 : r.y1 - r.y0;
  HW_CHECK_GE(len, 2);
  // Clean lines [lo, lo+k) resp. [hi−k, hi): O(1) each from the tables.
  auto cleanFromStart = [&](int k) {
    return cutX ? regionClean(r.x0, r.y0, r.x0 + k, r.y1) : regionClean(r.x0, r.y0, r.x1, r.y0 + k);
  };
  auto cleanFromEnd = [&](int k) {
    return cutX ? regionClean(r.x1 - k, r.y0, r.x1, r.y1) : regionClean(r.x0, r.y1 - k, r.x1, r.y1);
  };
  // The paper scans line by line; with Stencil, "k clean lines from one end"
  // is monotone in k, so the first dirty line is found by bisection with the
  // same result. RegionLocal with FivePoint is not strictly monotone (when
  // the part grows, its border pixel's single-axis term becomes the 5-point
  // sum, which can cancel); bisection still returns a k whose part is clean
  // and whose (k+1)-line part is not, which is all the cut needs.
  // Enough = at least 1/4 of the region: 4k >= len.
  const int quarter = (len + 3) / 4;
  auto longestClean = [&](auto clean) {
    int good = quarter, bad = len;  // clean(len) is false: the region is dirty
    while (bad - good > 1) {
      const int mid = good + (bad - good) / 2;
      (clean(mid) ? good : bad) = mid;
    }
    return good;
  };
  if (cleanFromStart(quarter)) return lo + longestClean(cleanFromStart);
  if (cleanFromEnd(quarter)) return lo + len - longestClean(cleanFromEnd);
  return lo + len / 2;
}

double LodBuilder::subdivide() {
  HW_CHECK(prepared_);
  Stopwatch sw;
  const int w = delta_.width(), h = delta_.height();
  satStride_ = w + 1;
  mergeTol_ = options_.mergeToleranceZPrime > 0.0 ? options_.mergeToleranceZPrime
                                                  : std::max(0.25 * tauZPrime_, kMergeNoiseFloor);
  misfitTol_ = options_.misfitToleranceZPrime > 0.0
                   ? options_.misfitToleranceZPrime
                   : std::max(tauZPrime_ / kMisfitTauDivisor, kMergeNoiseFloor);
  if (options_.planarity == Planarity::RegionLocal) {
    buildLocalTables();
    subdivideRegions<true>();
  } else {
    // The largest float <= τ: for a float Δ, Δ > tau ⇔ Δ > τ exactly. Capped
    // at FLT_MAX so that kDeltaDiscontinuity (+inf) stays dirty for any τ.
    float tau = static_cast<float>(std::min(tauZPrime_, double(std::numeric_limits<float>::max())));
    if (static_cast<double>(tau) > tauZPrime_) tau = std::nextafter(tau, 0.0f);

    // Summed-area table of the dirty mask (|Δ²| > τ; kDeltaEmpty never is).
    sat_.resize(static_cast<std::size_t>(w + 1) * (h + 1));
    std::fill(sat_.begin(), sat_.begin() + satStride_, 0);
    for (int y = 0; y < h; ++y) {
      const float* __restrict d = delta_.view().row(y);
      const std::int32_t* __restrict prev =
          sat_.data() + static_cast<std::ptrdiff_t>(y) * satStride_;
      std::int32_t* __restrict cur = sat_.data() + static_cast<std::ptrdiff_t>(y + 1) * satStride_;
      cur[0] = 0;
      if (options_.tauGradient > 0.0) {
        // Per-pixel τ + A·g, capped like τ so that +inf stays dirty.
        const float* __restrict g = grad_.view().row(y);
        const double t0 = tauZPrime_, a = options_.tauGradient;
        const double cap = std::numeric_limits<float>::max();
        for (int x = 0; x < w; ++x) {
          const double t = std::min(t0 + a * static_cast<double>(g[x]), cap);
          cur[x + 1] = static_cast<std::int32_t>(static_cast<double>(d[x]) > t);
        }
      } else {
        for (int x = 0; x < w; ++x) cur[x + 1] = static_cast<std::int32_t>(d[x] > tau);
      }
      for (int x = 0; x < w; ++x) cur[x + 1] += cur[x];  // row prefix (serial)
      for (int x = 1; x <= w; ++x) cur[x] += prev[x];
    }
    subdivideRegions<false>();
  }
  leavesBeforeMerge_ = static_cast<int>(leaves_.size());
  if (options_.mergeStrips) mergeLeaves();
  return sw.ms();
}

template <bool kLocal>
void LodBuilder::subdivideRegions() {
  const int w = delta_.width(), h = delta_.height();
  leaves_.clear();
  stack_.clear();
  misfitSplits_ = 0;
  stack_.push_back(Region{0, 0, w, h, true});
  const std::uint8_t* valid = valid_.data();
  auto stencilClean = [this](int x0, int y0, int x1, int y1) {
    return dirtyCount(x0, y0, x1, y1) == 0;
  };
  auto localClean = [this](int x0, int y0, int x1, int y1) { return cleanLocal(x0, y0, x1, y1); };
  while (!stack_.empty()) {
    const Region r = stack_.back();
    stack_.pop_back();
    bool leaf;
    if constexpr (kLocal) {
      // Clean implies all covered or all empty; 1×1 is always clean.
      leaf = cleanLocal(r.x0, r.y0, r.x1, r.y1);
    } else {
      const bool dirty = dirtyCount(r.x0, r.y0, r.x1, r.y1) != 0;
      const bool onePixel = r.x1 - r.x0 == 1 && r.y1 - r.y0 == 1;
      // Clean: all covered or all empty (see the header); a dirty 1×1 is
      // always covered, since empty pixels are never dirty.
      leaf = !dirty || onePixel;
    }
    // A clean, covered region whose plane does not fit it (or reaches past
    // its depth bounds at its outer edges, as a plane through two pixels
    // across a step does) is cut in the middle.
    bool misfitCut = false;
    if (leaf) {
      if (valid[static_cast<std::ptrdiff_t>(r.y0) * w + r.x0] == 0) continue;
      const PixelRect rect{r.x0, r.y0, r.x1, r.y1};
      if (!(options_.splitMisfit && rect.area() > 1 && misfit(rect))) {
        leaves_.push_back(rect);
        continue;
      }
      misfitCut = true;
      ++misfitSplits_;
    }
    bool cutX = r.cutX;
    if (cutX && r.x1 - r.x0 == 1) cutX = false;
    if (!cutX && r.y1 - r.y0 == 1) cutX = true;
    int c;
    if (misfitCut) {
      c = cutX ? r.x0 + (r.x1 - r.x0) / 2 : r.y0 + (r.y1 - r.y0) / 2;
    } else {
      c = kLocal ? findCut(r, cutX, localClean) : findCut(r, cutX, stencilClean);
    }
    // Push the far part first so the near (left/top) part is processed first.
    if (cutX) {
      HW_CHECK(c > r.x0 && c < r.x1);
      stack_.push_back(Region{c, r.y0, r.x1, r.y1, false});
      stack_.push_back(Region{r.x0, r.y0, c, r.y1, false});
    } else {
      HW_CHECK(c > r.y0 && c < r.y1);
      stack_.push_back(Region{r.x0, c, r.x1, r.y1, true});
      stack_.push_back(Region{r.x0, r.y0, r.x1, c, true});
    }
  }
}

namespace {

// Per-axis stencil state of a covered pixel (RegionLocal): clean, dirty
// (|Δ²| > τ, or not finite: overflowing z'), or missing (the stencil leaves
// the image or touches an empty pixel).
constexpr std::int8_t kStencilClean = 0, kStencilDirty = 1, kStencilMissing = 2;
inline std::int8_t stencilState(double d2, double tau) {
  return std::fabs(d2) <= tau ? kStencilClean : kStencilDirty;
}
inline bool stencilDirty(std::int8_t s) { return s == kStencilDirty; }
// Two neighbours whose full stencils (reaching outside any 2-wide region
// that holds them) are both dirty: a step, a crease or a 2-pixel-thin object
// between them; the data inside the pair cannot tell which (any two values
// fit a line). A missing stencil (image border, empty neighbour) is no
// evidence.
inline bool bothDirty(std::int8_t a, std::int8_t b) { return stencilDirty(a) && stencilDirty(b); }

}  // namespace

void LodBuilder::buildLocalTables() {
  const int w = valid_.width(), h = valid_.height();
  const bool gradTol = options_.tauGradient > 0.0;
  const bool fivePoint = options_.criterion == DeltaCriterion::FivePoint;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  stateX_.resize(n);
  stateY_.resize(n);
  innerDirty_.resize(n);
  // Pass 1: per-pixel stencil states along x and y, and the interior test.
  // A stencil exists when its three pixels are inside the image and covered.
  for (int y = 0; y < h; ++y) {
    const double* zr = zPrime_.row(y);
    const double* zu = y > 0 ? zPrime_.row(y - 1) : nullptr;
    const double* zd = y + 1 < h ? zPrime_.row(y + 1) : nullptr;
    const std::uint8_t* vr = valid_.view().row(y);
    const std::uint8_t* vu = y > 0 ? valid_.view().row(y - 1) : nullptr;
    const std::uint8_t* vd = y + 1 < h ? valid_.view().row(y + 1) : nullptr;
    std::int8_t* sx = stateX_.data() + static_cast<std::ptrdiff_t>(y) * w;
    std::int8_t* sy = stateY_.data() + static_cast<std::ptrdiff_t>(y) * w;
    std::uint8_t* in = innerDirty_.data() + static_cast<std::ptrdiff_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      sx[x] = sy[x] = kStencilMissing;
      in[x] = 0;
      if (vr[x] == 0) continue;
      // τ, or τ + A·g(p) (capped so that an overflowing stencil stays dirty).
      const double tau = gradTol ? std::min(tauAt(static_cast<std::ptrdiff_t>(y) * w + x),
                                            std::numeric_limits<double>::max())
                                 : tauZPrime_;
      const bool hasX = x > 0 && x + 1 < w && vr[x - 1] != 0 && vr[x + 1] != 0;
      const bool hasY = zu != nullptr && zd != nullptr && vu[x] != 0 && vd[x] != 0;
      const double dx = hasX ? 2.0 * zr[x] - zr[x - 1] - zr[x + 1] : 0.0;
      const double dy = hasY ? 2.0 * zr[x] - zu[x] - zd[x] : 0.0;
      if (hasX) sx[x] = stencilState(dx, tau);
      if (hasY) sy[x] = stencilState(dy, tau);
      // Only read for pixels inside a covered region's interior, where both
      // stencils exist.
      if (fivePoint) {
        in[x] = hasX && hasY && !(std::fabs(dx + dy) <= tau);
      } else {
        in[x] = (hasX && !(std::fabs(dx) <= tau)) || (hasY && !(std::fabs(dy) <= tau));
      }
    }
  }
  // Pass 2: the six summed-area tables.
  for (auto& t : local_) {
    t.resize(static_cast<std::size_t>(w + 1) * (h + 1));
    std::fill(t.begin(), t.begin() + satStride_, 0);
  }
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* vr = valid_.view().row(y);
    const std::uint8_t* vd = y + 1 < h ? valid_.view().row(y + 1) : nullptr;
    const std::int8_t* sx = stateX_.data() + static_cast<std::ptrdiff_t>(y) * w;
    const std::int8_t* sy = stateY_.data() + static_cast<std::ptrdiff_t>(y) * w;
    const std::int8_t* syd = vd ? sy + w : nullptr;
    const std::uint8_t* in = innerDirty_.data() + static_cast<std::ptrdiff_t>(y) * w;
    std::int32_t* cur[kLocalTables];
    const std::int32_t* prev[kLocalTables];
    for (int t = 0; t < kLocalTables; ++t) {
      cur[t] = local_[t].data() + static_cast<std::ptrdiff_t>(y + 1) * satStride_;
      prev[t] = local_[t].data() + static_cast<std::ptrdiff_t>(y) * satStride_;
      cur[t][0] = 0;
    }
    for (int x = 0; x < w; ++x) {
      const bool v = vr[x] != 0;
      cur[kValid][x + 1] = v;
      cur[kInner][x + 1] = v && in[x] != 0;
      cur[kOnlyX][x + 1] = v && stencilDirty(sx[x]);
      cur[kOnlyY][x + 1] = v && stencilDirty(sy[x]);
      cur[kStepX][x + 1] = v && x + 1 < w && vr[x + 1] && bothDirty(sx[x], sx[x + 1]);
      cur[kStepY][x + 1] = v && vd && vd[x] && bothDirty(sy[x], syd[x]);
    }
    for (int t = 0; t < kLocalTables; ++t) {
      std::int32_t* __restrict c = cur[t];
      const std::int32_t* __restrict p = prev[t];
      for (int x = 0; x < w; ++x) c[x + 1] += c[x];
      for (int x = 1; x <= w; ++x) c[x] += p[x];
    }
  }
}

bool LodBuilder::cleanLocal(int x0, int y0, int x1, int y1) const {
  const long long area = static_cast<long long>(x1 - x0) * (y1 - y0);
  const std::int32_t v = localCount(kValid, x0, y0, x1, y1);
  if (v == 0) return true;      // all empty: dropped
  if (v != area) return false;  // mixed coverage is never a leaf
  // Interior: both stencils inside. Border rows: only Δ²ₓ; border columns:
  // only Δ²ᵧ; the four corner pixels have neither.
  if (localCount(kInner, x0 + 1, y0 + 1, x1 - 1, y1 - 1) != 0) return false;
  if (localCount(kOnlyX, x0 + 1, y0, x1 - 1, y0 + 1) != 0) return false;
  if (localCount(kOnlyX, x0 + 1, y1 - 1, x1 - 1, y1) != 0) return false;
  if (localCount(kOnlyY, x0, y0 + 1, x0 + 1, y1 - 1) != 0) return false;
  if (localCount(kOnlyY, x1 - 1, y0 + 1, x1, y1 - 1) != 0) return false;
  if (x1 - x0 == 2 && localCount(kStepX, x0, y0, x0 + 1, y1) != 0) return false;
  if (y1 - y0 == 2 && localCount(kStepY, x0, y0, x1, y0 + 1) != 0) return false;
  return true;
}

namespace {

// Σ(u − ū)² over a w×h grid of pixel centres (u along the w side).
inline double gridSuu(int w, int h) {
  return h * (static_cast<double>(w) * (static_cast<double>(w) * w - 1.0) / 12.0);
}

}  // namespace

bool LodBuilder::cornersClamp(const PixelRect& r, double a, double b, double c) const {
  // The plane at the outer pixel edges, half the leaf's size from its centre
  // either way, against recoverCorners' bounds.
  const double n = camera_.nearPlane, f = camera_.farPlane;
  const double z00 = zPrime_(r.x0, r.y0), z10 = zPrime_(r.x1 - 1, r.y0);
  const double z01 = zPrime_(r.x0, r.y1 - 1), z11 = zPrime_(r.x1 - 1, r.y1 - 1);
  const DepthBounds bounds =
      cornerBounds(eyeZFromZPrime(std::min(std::min(z00, z10), std::min(z01, z11)), n, f),
                   eyeZFromZPrime(std::max(std::max(z00, z10), std::max(z01, z11)), n, f), n, f);
  const double hu = 0.5 * r.width(), hv = 0.5 * r.height();
  for (const double su : {-hu, hu})
    for (const double sv : {-hv, hv}) {
      const double z = eyeZFromZPrime(a + b * su + c * sv, n, f);
      if (clampDepth(z, bounds) != z) return true;
    }
  return false;
}

// The least-squares z' plane of r's pixels, z' = a + b·(x − cx) + c·(y − cy)
// with (cx, cy) r's centre in pixel indices (the normal equations decouple on
// a full grid, as in recoverCorners).
LodBuilder::Plane LodBuilder::fitPlane(const PixelRect& r) const {
  const double icx = 0.5 * (r.x0 + r.x1 - 1), icy = 0.5 * (r.y0 + r.y1 - 1);
  const double zRef = zPrime_(r.x0, r.y0);
  double sum = 0, sumU = 0, sumV = 0;
  for (int y = r.y0; y < r.y1; ++y) {
    const double* z = zPrime_.row(y);
    double rs = 0, ru = 0;
    for (int x = r.x0; x < r.x1; ++x) {
      const double d = z[x] - zRef;
      rs += d;
      ru += d * (x - icx);
    }
    sum += rs;
    sumU += ru;
    sumV += rs * (y - icy);
  }
  const double suu = gridSuu(r.width(), r.height()), svv = gridSuu(r.height(), r.width());
  return {zRef + sum / static_cast<double>(r.area()), suu > 0 ? sumU / suu : 0.0,
          svv > 0 ? sumV / svv : 0.0};
}

// The largest |z' − plane| over r's pixels; stops at the first one above a
// finite `stopAbove` and returns it (a NaN depth counts as above, returned as
// +inf). With stopAbove = +inf every pixel is scanned and NaNs are skipped.
double LodBuilder::maxResidual(const PixelRect& r, const Plane& p, double stopAbove) const {
  const double icx = 0.5 * (r.x0 + r.x1 - 1), icy = 0.5 * (r.y0 + r.y1 - 1);
  double resid = 0;
  for (int y = r.y0; y < r.y1; ++y) {
    const double* z = zPrime_.row(y);
    const double rowPlane = p.a + p.c * (y - icy);
    for (int x = r.x0; x < r.x1; ++x) {
      const double d = std::fabs(z[x] - (rowPlane + p.b * (x - icx)));
      if (d > stopAbove) return d;
      if (std::isnan(d)) {
        if (stopAbove < std::numeric_limits<double>::infinity())
          return std::numeric_limits<double>::infinity();
        continue;
      }
      resid = std::max(resid, d);
    }
  }
  return resid;
}

bool LodBuilder::misfit(const PixelRect& r) const {
  const Plane p = fitPlane(r);
  if (cornersClamp(r, p.a, p.b, p.c)) return true;
  return maxResidual(r, p, misfitTol_) > misfitTol_;
}

void LodBuilder::mergeLeaves() {
  // Least-squares plane and max residual of every leaf.
  merge_.resize(leaves_.size());
  for (std::size_t k = 0; k < leaves_.size(); ++k) {
    const PixelRect& r = leaves_[k];
    const Plane p = fitPlane(r);
    MergeLeaf& m = merge_[k];
    m.r = r;
    m.a = p.a;
    m.b = p.b;
    m.c = p.c;
    m.resid = maxResidual(r, p, std::numeric_limits<double>::infinity());
  }

  // Union of the contiguous run m[0..count) (identical spans): its plane from
  // the members' planes — each member's residual is orthogonal to 1, u, v
  // over the member, so Σz, Σz·(u − U), Σz·(v − V) follow exactly from
  // (a, b, c) and the grid moments — and a bound on its max residual:
  // |P_union − z| ≤ |P_union − P_k| + resid_k on member k, and the first
  // term is affine, so its max is at the member's corner pixel centres.
  const bool splitMisfit = options_.splitMisfit;
  const double tol = splitMisfit ? std::min(mergeTol_, misfitTol_) : mergeTol_;
  auto unionOf = [this, tol, splitMisfit](const MergeLeaf* m, int count, MergeLeaf* out) {
    PixelRect u = m[0].r;
    for (int k = 1; k < count; ++k) {
      u.x0 = std::min(u.x0, m[k].r.x0);
      u.y0 = std::min(u.y0, m[k].r.y0);
      u.x1 = std::max(u.x1, m[k].r.x1);
      u.y1 = std::max(u.y1, m[k].r.y1);
    }
    const double ucx = 0.5 * (u.x0 + u.x1 - 1), ucy = 0.5 * (u.y0 + u.y1 - 1);
    const double aRef = m[0].a;
    double sz = 0, szu = 0, szv = 0;
    for (int k = 0; k < count; ++k) {
      const PixelRect& r = m[k].r;
      const double nk = static_cast<double>(r.area()), da = m[k].a - aRef;
      const double cx = 0.5 * (r.x0 + r.x1 - 1), cy = 0.5 * (r.y0 + r.y1 - 1);
      sz += nk * da;
      szu += nk * da * (cx - ucx) + m[k].b * gridSuu(r.width(), r.height());
      szv += nk * da * (cy - ucy) + m[k].c * gridSuu(r.height(), r.width());
    }
    const double suu = gridSuu(u.width(), u.height()), svv = gridSuu(u.height(), u.width());
    const double a = aRef + sz / static_cast<double>(u.area());
    const double b = suu > 0 ? szu / suu : 0.0;
    const double c = svv > 0 ? szv / svv : 0.0;
    double bound = 0;
    for (int k = 0; k < count; ++k) {
      const PixelRect& r = m[k].r;
      const double cx = 0.5 * (r.x0 + r.x1 - 1), cy = 0.5 * (r.y0 + r.y1 - 1);
      for (const int px : {r.x0, r.x1 - 1})
        for (const int py : {r.y0, r.y1 - 1}) {
          const double pu = a + b * (px - ucx) + c * (py - ucy);
          const double pk = m[k].a + m[k].b * (px - cx) + m[k].c * (py - cy);
          bound = std::max(bound, std::fabs(pu - pk) + m[k].resid);
        }
      if (!(bound <= tol)) return false;
    }
    if (splitMisfit && cornersClamp(u, a, b, c)) return false;
    *out = MergeLeaf{u, a, b, c, bound};
    return true;
  };

  // Any two lines fit a plane exactly along the direction that crosses them,
  // so a union exactly 2 pixels along the merge direction would pass across
  // a depth step (a rubber sheet). The same guard as RegionLocal's 2-wide
  // regions: refused where, in some line, both pixels' full second
  // differences along that direction exceed τ (missing stencils: no
  // evidence).
  const int w = valid_.width(), h = valid_.height();
  const bool gradTol = options_.tauGradient > 0.0;
  auto dirtyAt = [&](int x, int y, bool alongY) {
    const double tau = gradTol ? std::min(tauAt(static_cast<std::ptrdiff_t>(y) * w + x),
                                          std::numeric_limits<double>::max())
                               : tauZPrime_;
    const int dx = alongY ? 0 : 1, dy = alongY ? 1 : 0;
    const int xa = x - dx, ya = y - dy, xb = x + dx, yb = y + dy;
    if (xa < 0 || ya < 0 || xb >= w || yb >= h) return false;
    if (valid_(xa, ya) == 0 || valid_(xb, yb) == 0) return false;
    const double d2 = 2.0 * zPrime_(x, y) - zPrime_(xa, ya) - zPrime_(xb, yb);
    return !(std::fabs(d2) <= tau);
  };
  auto twoLineStep = [&](const PixelRect& u, bool alongY) {
    if ((alongY ? u.height() : u.width()) != 2) return false;
    if (alongY) {
      for (int x = u.x0; x < u.x1; ++x)
        if (dirtyAt(x, u.y0, true) && dirtyAt(x, u.y0 + 1, true)) return true;
    } else {
      for (int y = u.y0; y < u.y1; ++y)
        if (dirtyAt(u.x0, y, false) && dirtyAt(u.x0 + 1, y, false)) return true;
    }
    return false;
  };

  // Greedy runs: along y (same x span, stacked), then along x, alternating
  // until two passes in a row merge nothing.
  int idle = 0;
  for (int pass = 0; pass < 4 && idle < 2; ++pass) {
    const bool alongY = pass % 2 == 0;
    auto key = [alongY](const MergeLeaf& m) {
      return alongY ? std::array<int, 3>{m.r.x0, m.r.x1, m.r.y0}
                    : std::array<int, 3>{m.r.y0, m.r.y1, m.r.x0};
    };
    std::sort(merge_.begin(), merge_.end(),
              [&](const MergeLeaf& p, const MergeLeaf& q) { return key(p) < key(q); });
    auto follows = [alongY](const MergeLeaf& p, const MergeLeaf& q) {
      return alongY ? p.r.x0 == q.r.x0 && p.r.x1 == q.r.x1 && p.r.y1 == q.r.y0
                    : p.r.y0 == q.r.y0 && p.r.y1 == q.r.y1 && p.r.x1 == q.r.x0;
    };
    mergeOut_.clear();
    bool any = false;
    const int n = static_cast<int>(merge_.size());
    for (int i = 0; i < n;) {
      MergeLeaf acc = merge_[i];
      int j = i + 1;
      MergeLeaf cand;
      while (j < n && j - i < kMaxMergeRun && follows(merge_[j - 1], merge_[j]) &&
             unionOf(merge_.data() + i, j - i + 1, &cand) && !twoLineStep(cand.r, alongY)) {
        acc = cand;
        ++j;
      }
      any |= j - i > 1;
      mergeOut_.push_back(acc);
      i = j;
    }
    merge_.swap(mergeOut_);
    idle = any ? 0 : idle + 1;
  }
  leaves_.resize(merge_.size());
  for (std::size_t k = 0; k < merge_.size(); ++k) leaves_[k] = merge_[k].r;
}

namespace {

// Camera::unproject with the intrinsics hoisted: fy() costs a tan() per call,
// which was a third of the corner step. Same expression, so bit-identical
// (tested against Camera::unproject).
struct Unprojector {
  explicit Unprojector(const Camera& c) : cam(c), fx(c.fx()), fy(c.fy()), cx(c.cx()), cy(c.cy()) {}
  glm::dvec3 operator()(double u, double v, double zEye) const {
    const double x = (u - cx) / fx;
    const double y = (cy - v) / fy;
    return cam.eye + zEye * (cam.forward + x * cam.right + y * cam.up);
  }
  const Camera& cam;
  double fx, fy, cx, cy;
};

// Sums over one row segment of the leaf fit: Σz, Σz·(x − icx), with z taken
// relative to zRef; and max |Δ²|. FP sums do not auto-vectorise without
// reassociation, so they use two-lane vector accumulators (GCC/Clang vector
// extensions: SSE2 on x86-64, NEON on ARM). Δ ≥ 0 inside a leaf (never
// kDeltaEmpty), so its float bits order like int32: an integer max, which
// does vectorise.
using V2 = double __attribute__((vector_size(16)));
struct RowSums {
  double sum, sumU;
  std::int32_t maxBits;
};
inline RowSums rowSums(const double* __restrict z, const float* __restrict d, int x0, int x1,
                       double zRef, double icx) {
  const V2 ref = {zRef, zRef}, four = {4.0, 4.0};
  V2 s0 = {0, 0}, s1 = {0, 0}, u0 = {0, 0}, u1 = {0, 0};
  V2 xa = {x0 - icx, x0 + 1 - icx}, xb = {x0 + 2 - icx, x0 + 3 - icx};
  int x = x0;
  for (; x + 3 < x1; x += 4) {
    V2 a, b;
    std::memcpy(&a, z + x, sizeof a);
    std::memcpy(&b, z + x + 2, sizeof b);
    a -= ref;
    b -= ref;
    s0 += a;
    s1 += b;
    u0 += a * xa;
    u1 += b * xb;
    xa += four;
    xb += four;
  }
  const V2 s = s0 + s1, u = u0 + u1;
  double sum = s[0] + s[1], sumU = u[0] + u[1];
  for (; x < x1; ++x) {
    const double zk = z[x] - zRef;
    sum += zk;
    sumU += zk * (x - icx);
  }
  std::int32_t m = 0;
  for (int i = x0; i < x1; ++i) {
    std::int32_t bits;
    std::memcpy(&bits, &d[i], sizeof bits);
    m = bits > m ? bits : m;
  }
  return {sum, sumU, m};
}

}  // namespace

double LodBuilder::recoverCorners(QuadMesh* out) {
  HW_CHECK(prepared_);
  HW_CHECK(out != nullptr);
  Stopwatch sw;
  const int w = delta_.width(), h = delta_.height();
  const double n = camera_.nearPlane, f = camera_.farPlane;
  const Unprojector unproject(camera_);
  out->width = w;
  out->height = h;
  out->quads.resize(leaves_.size());
  QuadMeshStats& st = out->stats;
  st = QuadMeshStats{};
  st.quads = static_cast<int>(leaves_.size());
  st.emptyPixels = emptyPixels_;
  st.criterion = options_.criterion;
  st.tauZPrime = tauZPrime_;
  st.tauParallaxPx = options_.tauParallaxPx;

  for (std::size_t k = 0; k < leaves_.size(); ++k) {
    const PixelRect& r = leaves_[k];
    Quad& q = out->quads[k];
    q.rect = r;
    const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
    const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
    for (int i = 0; i < 4; ++i) q.pixel[i] = glm::dvec2(us[i], vs[i]);
    const int lw = r.width(), lh = r.height();

    if (lw == 1 && lh == 1) {
      // One pixel: constant z'; the bounds below contain it unless it is
      // itself out of [n/2, 100·f] (e.g. at or past infinity).
      ++st.onePixelLeaves;
      q.maxDelta = delta_(r.x0, r.y0);
      const double z = eyeZFromZPrime(zPrime_(r.x0, r.y0), n, f);
      const DepthBounds b = cornerBounds(z, z, n, f);
      const double zc = clampDepth(z, b);
      if (zc != z) st.clampedCorners += 4;
      for (int i = 0; i < 4; ++i) {
        q.eyeZ[i] = zc;
        q.world[i] = unproject(us[i], vs[i], zc);
      }
      continue;
    }

    // Least squares z' = a + b·(u − uc) + c·(v − vc) over the leaf's pixel
    // centres, (uc, vc) the rectangle centre. A leaf is fully covered, so on
    // the full grid of centred coordinates Σu = Σv = Σuv = 0 and the normal
    // equations decouple: a = mean, b = Σz·u / Σu², c = Σz·v / Σv². A width
    // (height) of 1 gives Σu² = 0: no slope along that axis (1×N leaves).
    // z' is taken relative to the first pixel to keep the sums small.
    const double zRef = zPrime_(r.x0, r.y0);
    const double icx = 0.5 * (r.x0 + r.x1 - 1);  // centre in pixel indices
    const double icy = 0.5 * (r.y0 + r.y1 - 1);
    double sum = 0, sumU = 0, sumV = 0;
    std::int32_t maxBits = 0;
    for (int y = r.y0; y < r.y1; ++y) {
      const RowSums rs = rowSums(zPrime_.row(y), delta_.view().row(y), r.x0, r.x1, zRef, icx);
      sum += rs.sum;
      sumU += rs.sumU;
      sumV += rs.sum * (y - icy);
      maxBits = std::max(maxBits, rs.maxBits);
    }
    std::memcpy(&q.maxDelta, &maxBits, sizeof maxBits);
    const double cnt = static_cast<double>(lw) * lh;
    const double suu = lh * (static_cast<double>(lw) * (static_cast<double>(lw) * lw - 1.0) / 12.0);
    const double svv = lw * (static_cast<double>(lh) * (static_cast<double>(lh) * lh - 1.0) / 12.0);
    const double a = zRef + sum / cnt;
    const double b = suu > 0 ? sumU / suu : 0.0;
    const double c = svv > 0 ? sumV / svv : 0.0;

    // Depth bounds from the data at the leaf's four corner pixels (eye depth
    // grows with z', so the extreme z' give the extreme depths).
    const double z00 = zPrime_(r.x0, r.y0), z10 = zPrime_(r.x1 - 1, r.y0);
    const double z01 = zPrime_(r.x0, r.y1 - 1), z11 = zPrime_(r.x1 - 1, r.y1 - 1);
    const DepthBounds bounds =
        cornerBounds(eyeZFromZPrime(std::min(std::min(z00, z10), std::min(z01, z11)), n, f),
                     eyeZFromZPrime(std::max(std::max(z00, z10), std::max(z01, z11)), n, f), n, f);

    const double uc = 0.5 * (r.x0 + r.x1), vc = 0.5 * (r.y0 + r.y1);
    for (int i = 0; i < 4; ++i) {
      const double zp = a + b * (us[i] - uc) + c * (vs[i] - vc);
      const double z = eyeZFromZPrime(zp, n, f);  // +inf at or past infinity
      const double ze = clampDepth(z, bounds);
      if (ze != z) ++st.clampedCorners;
      q.eyeZ[i] = ze;
      q.world[i] = unproject(us[i], vs[i], ze);
    }
  }
  return sw.ms();
}

Status LodBuilder::build(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                         const Camera& camera, const LodOptions& options, QuadMesh* out) {
  HW_CHECK(out != nullptr);
  out->quads.clear();
  out->stats = QuadMeshStats{};
  out->width = out->height = 0;
  HW_TRY(prepare(zPrime, covered, camera, options));
  const double subdivideMs = subdivide();
  const double cornersMs = recoverCorners(out);
  out->stats.deltaMs = deltaMs_;
  out->stats.subdivideMs = subdivideMs;
  out->stats.cornersMs = cornersMs;
  return {};
}

namespace {

// The keyframe-level checks of build(keyframe) (the image-level ones are in
// prepare()).
Status validateKeyframeImages(const Keyframe& kf) {
  const int w = kf.zPrime.width(), h = kf.zPrime.height();
  if (kf.colour.width() != w || kf.colour.height() != h) {
    return makeError("LOD builder: keyframe depth is " + sizeStr(w, h) + " but colour is " +
                     sizeStr(kf.colour.width(), kf.colour.height()));
  }
  if (!kf.eyeZ.empty() && (kf.eyeZ.width() != w || kf.eyeZ.height() != h)) {
    return makeError("LOD builder: keyframe depth is " + sizeStr(w, h) + " but eyeZ is " +
                     sizeStr(kf.eyeZ.width(), kf.eyeZ.height()));
  }
  return {};
}

// Appends rather than `"[" + std::to_string(...)`, which trips GCC 12's
// -Wrestrict false positive at -O3.
std::string rectStr(const PixelRect& r) {
  std::string s = "[";
  s += std::to_string(r.x0);
  s += ", ";
  s += std::to_string(r.x1);
  s += ") x [";
  s += std::to_string(r.y0);
  s += ", ";
  s += std::to_string(r.y1);
  s += ")";
  return s;
}

}  // namespace

Status LodBuilder::build(const Keyframe& kf, const LodOptions& options, QuadMesh* out) {
  HW_CHECK(out != nullptr);
  if (Status st = validateKeyframeImages(kf); !st.ok()) {
    out->quads.clear();
    out->stats = QuadMeshStats{};
    return st;
  }
  return build(kf.zPrime.view(), kf.covered.view(), kf.camera, options, out);
}

Status LodBuilder::buildFromRects(const Keyframe& kf, std::span<const PixelRect> rects,
                                  const LodOptions& options, QuadMesh* out) {
  HW_CHECK(out != nullptr);
  out->quads.clear();
  out->stats = QuadMeshStats{};
  out->width = out->height = 0;
  HW_TRY(validateKeyframeImages(kf));
  HW_TRY(prepare(kf.zPrime.view(), kf.covered.view(), kf.camera, options));
  const int w = valid_.width(), h = valid_.height();
  // recoverCorners() relies on every rectangle being fully valid (the fit
  // assumes the full grid; maxDelta assumes Δ >= 0). Scanning the rectangles
  // costs the same order as the fit itself.
  for (std::size_t k = 0; k < rects.size(); ++k) {
    const PixelRect& r = rects[k];
    if (!(r.x0 >= 0 && r.y0 >= 0 && r.x0 < r.x1 && r.y0 < r.y1 && r.x1 <= w && r.y1 <= h)) {
      prepared_ = false;
      return makeError("LOD builder: rectangle " + std::to_string(k) + " " + rectStr(r) +
                       " is empty or not inside the " + sizeStr(w, h) + " image");
    }
    for (int y = r.y0; y < r.y1; ++y) {
      const std::uint8_t* row = valid_.view().row(y);
      const void* hole = std::memchr(row + r.x0, 0, static_cast<std::size_t>(r.width()));
      if (hole != nullptr) {
        prepared_ = false;
        const int x = static_cast<int>(static_cast<const std::uint8_t*>(hole) - row);
        return makeError("LOD builder: rectangle " + std::to_string(k) + " " + rectStr(r) +
                         " holds the empty pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                         "); every pixel must be covered with finite z'");
      }
    }
  }
  leaves_.assign(rects.begin(), rects.end());
  const double cornersMs = recoverCorners(out);
  out->stats.deltaMs = deltaMs_;
  out->stats.subdivideMs = 0.0;
  out->stats.cornersMs = cornersMs;
  return {};
}

Result<QuadMesh> buildQuadMesh(const Keyframe& keyframe, const LodOptions& options) {
  LodBuilder builder;
  QuadMesh mesh;
  HW_TRY(builder.build(keyframe, options, &mesh));
  return mesh;
}

Result<QuadMesh> buildQuadMesh(ImageView<const double> zPrime,
                               ImageView<const std::uint8_t> covered, const Camera& camera,
                               const LodOptions& options) {
  LodBuilder builder;
  QuadMesh mesh;
  HW_TRY(builder.build(zPrime, covered, camera, options, &mesh));
  return mesh;
}

}  // namespace hw::keyframe
