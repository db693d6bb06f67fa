#include "keyframe/lod_builder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/check.h"
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
                     std::to_string(c.fovYRadians));
  }
  if (!(c.nearPlane > 0.0 && c.farPlane > c.nearPlane && std::isfinite(c.farPlane))) {
    return makeError("LOD builder: camera needs 0 < near < far < inf, got near " +
                     std::to_string(c.nearPlane) + ", far " + std::to_string(c.farPlane));
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
    return makeError("LOD builder: tau must be finite and >= 0, got " +
                     std::to_string(options.tau));
  }
  if (!(options.tauParallaxPx >= 0.0 && std::isfinite(options.tauParallaxPx))) {
    return makeError("LOD builder: tauParallaxPx must be finite and >= 0, got " +
                     std::to_string(options.tauParallaxPx));
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
    int rowCount = 0;
    for (int x = 0; x < w; ++x) {
      const std::uint8_t v =
          (cr[x] != 0) & (std::fabs(zr[x]) <= std::numeric_limits<double>::max());
      vr[x] = v;
      rowCount += v;
    }
    validCount += rowCount;
  }
  emptyPixels_ = static_cast<long long>(w) * h - validCount;

  computeDeltaBuffer(zPrime, valid_.view(), options.criterion, &delta_);
  deltaMs_ = sw.ms();
  prepared_ = true;
  return {};
}

int LodBuilder::findCut(const Region& r, bool cutX) const {
  const int lo = cutX ? r.x0 : r.y0;
  const int len = cutX ? r.x1 - r.x0 : r.y1 - r.y0;
  HW_CHECK_GE(len, 2);
  // Clean lines [lo, lo+k) resp. [hi−k, hi): O(1) each from the table.
  auto cleanFromStart = [&](int k) {
    return cutX ? dirtyCount(r.x0, r.y0, r.x0 + k, r.y1) == 0
                : dirtyCount(r.x0, r.y0, r.x1, r.y0 + k) == 0;
  };
  auto cleanFromEnd = [&](int k) {
    return cutX ? dirtyCount(r.x1 - k, r.y0, r.x1, r.y1) == 0
                : dirtyCount(r.x0, r.y1 - k, r.x1, r.y1) == 0;
  };
  // The paper scans line by line; "k clean lines from one end" is monotone in
  // k, so the first dirty line is found by bisection with the same result.
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
  // The largest float <= τ: for a float Δ, Δ > tau ⇔ Δ > τ exactly. Capped at
  // FLT_MAX so that kDeltaDiscontinuity (+inf) stays dirty for any τ.
  float tau = static_cast<float>(std::min(tauZPrime_, double(std::numeric_limits<float>::max())));
  if (static_cast<double>(tau) > tauZPrime_) tau = std::nextafter(tau, 0.0f);

  // Summed-area table of the dirty mask (|Δ²| > τ; kDeltaEmpty never is).
  satStride_ = w + 1;
  sat_.resize(static_cast<std::size_t>(w + 1) * (h + 1));
  std::fill(sat_.begin(), sat_.begin() + satStride_, 0);
  for (int y = 0; y < h; ++y) {
    const float* __restrict d = delta_.view().row(y);
    const std::int32_t* __restrict prev = sat_.data() + static_cast<std::ptrdiff_t>(y) * satStride_;
    std::int32_t* __restrict cur = sat_.data() + static_cast<std::ptrdiff_t>(y + 1) * satStride_;
    cur[0] = 0;
    for (int x = 0; x < w; ++x) cur[x + 1] = static_cast<std::int32_t>(d[x] > tau);
    for (int x = 0; x < w; ++x) cur[x + 1] += cur[x];  // row prefix (serial)
    for (int x = 1; x <= w; ++x) cur[x] += prev[x];
  }

  leaves_.clear();
  stack_.clear();
  stack_.push_back(Region{0, 0, w, h, true});
  const std::uint8_t* valid = valid_.data();
  while (!stack_.empty()) {
    const Region r = stack_.back();
    stack_.pop_back();
    const bool dirty = dirtyCount(r.x0, r.y0, r.x1, r.y1) != 0;
    const bool onePixel = r.x1 - r.x0 == 1 && r.y1 - r.y0 == 1;
    if (!dirty || onePixel) {
      // Clean: all covered or all empty (see the header); a dirty 1×1 is
      // always covered, since empty pixels are never dirty.
      if (valid[static_cast<std::ptrdiff_t>(r.y0) * w + r.x0] != 0) {
        leaves_.push_back(PixelRect{r.x0, r.y0, r.x1, r.y1});
      }
      continue;
    }
    bool cutX = r.cutX;
    if (cutX && r.x1 - r.x0 == 1) cutX = false;
    if (!cutX && r.y1 - r.y0 == 1) cutX = true;
    const int c = findCut(r, cutX);
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
  return sw.ms();
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
