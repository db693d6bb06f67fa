#include "keyframe/delta_buffer.h"

#include <cmath>
#include <cstring>

#include "core/check.h"

namespace hw::keyframe {

const char* deltaCriterionName(DeltaCriterion c) {
  switch (c) {
    case DeltaCriterion::FivePoint:
      return "five-point";
    case DeltaCriterion::PerAxisMax:
      return "per-axis-max";
  }
  return "?";
}

bool parseDeltaCriterion(const char* s, DeltaCriterion* out) {
  if (s == nullptr) return false;
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    if (std::strcmp(s, deltaCriterionName(c)) == 0) {
      *out = c;
      return true;
    }
  }
  return false;
}

namespace {

template <DeltaCriterion C>
inline float combine(double dx, double dy) {
  if constexpr (C == DeltaCriterion::FivePoint) {
    return static_cast<float>(std::fabs(dx + dy));
  } else {
    // A plain select (fmax does not vectorise) may drop a NaN operand; the
    // 0·(dx + dy) term puts it back, so that a non-finite z' is still caught
    // as a discontinuity.
    const double ax = std::fabs(dx), ay = std::fabs(dy);
    return static_cast<float>((ax > ay ? ax : ay) + 0.0 * (dx + dy));
  }
}

// One row of |Δ²| ignoring coverage. `up`/`dn` are null on the first/last
// row: Δ²ᵧ = 0 there (linear extrapolation); likewise Δ²ₓ in the first/last
// column. Those zeros are written as (c − c), not 0, so that a non-finite z'
// still yields NaN and is caught as a discontinuity. Straight-line loops over
// restrict pointers so that -O3 vectorises them (NOTES-GL.md).
template <DeltaCriterion C>
void rowValues(const double* __restrict c, const double* __restrict up, const double* __restrict dn,
               float* __restrict out, int w) {
  if (w == 1) {
    const double dy = up && dn ? 2.0 * c[0] - up[0] - dn[0] : c[0] - c[0];
    out[0] = combine<C>(c[0] - c[0], dy);
    return;
  }
  if (up && dn) {
    out[0] = combine<C>(c[0] - c[0], 2.0 * c[0] - up[0] - dn[0]);
    for (int x = 1; x < w - 1; ++x) {
      const double dx = 2.0 * c[x] - c[x - 1] - c[x + 1];
      const double dy = 2.0 * c[x] - up[x] - dn[x];
      out[x] = combine<C>(dx, dy);
    }
    out[w - 1] = combine<C>(c[w - 1] - c[w - 1], 2.0 * c[w - 1] - up[w - 1] - dn[w - 1]);
  } else {
    out[0] = combine<C>(c[0] - c[0], c[0] - c[0]);
    for (int x = 1; x < w - 1; ++x) {
      const double dx = 2.0 * c[x] - c[x - 1] - c[x + 1];
      out[x] = combine<C>(dx, c[x] - c[x]);
    }
    out[w - 1] = combine<C>(c[w - 1] - c[w - 1], c[w - 1] - c[w - 1]);
  }
}

inline bool allNonZero(const std::uint8_t* __restrict p, int n) {
  std::uint8_t m = 0xff;
  for (int x = 0; x < n; ++x) m &= static_cast<std::uint8_t>(p[x] != 0 ? 0xff : 0);
  return m != 0;
}

inline bool allFinite(const float* __restrict p, int n) {
  // |v| <= FLT_MAX is false for NaN and ±inf; the bitwise and keeps it
  // branch-free so that it vectorises.
  int ok = 1;
  for (int x = 0; x < n; ++x) ok &= static_cast<int>(std::fabs(p[x]) <= 3.4028234663852886e38f);
  return ok != 0;
}

// Applies the coverage rules to one row (kDeltaEmpty / kDeltaDiscontinuity).
// `cu`/`cd` are null outside the image (treated as covered: extrapolated).
void rowCoverage(const std::uint8_t* __restrict cc, const std::uint8_t* __restrict cu,
                 const std::uint8_t* __restrict cd, float* __restrict out, int w) {
  // Fast path: the whole 3-row neighbourhood is covered and every value finite.
  if (allNonZero(cc, w) && (!cu || allNonZero(cu, w)) && (!cd || allNonZero(cd, w)) &&
      allFinite(out, w)) {
    return;
  }
  for (int x = 0; x < w; ++x) {
    if (cc[x] == 0) {
      out[x] = kDeltaEmpty;
      continue;
    }
    const bool nb = (x == 0 || cc[x - 1] != 0) && (x == w - 1 || cc[x + 1] != 0) &&
                    (!cu || cu[x] != 0) && (!cd || cd[x] != 0);
    if (!nb || !(std::fabs(out[x]) <= 3.4028234663852886e38f)) out[x] = kDeltaDiscontinuity;
  }
}

template <DeltaCriterion C>
void computeImpl(ImageView<const double> z, ImageView<const std::uint8_t> cov,
                 ImageView<float> out) {
  const int w = z.width, h = z.height;
  for (int y = 0; y < h; ++y) {
    const bool interior = y > 0 && y < h - 1;
    rowValues<C>(z.row(y), interior ? z.row(y - 1) : nullptr, interior ? z.row(y + 1) : nullptr,
                 out.row(y), w);
    rowCoverage(cov.row(y), y > 0 ? cov.row(y - 1) : nullptr, y < h - 1 ? cov.row(y + 1) : nullptr,
                out.row(y), w);
  }
}

}  // namespace

void computeDeltaBuffer(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                        DeltaCriterion criterion, ImageView<float> out) {
  HW_CHECK_EQ(zPrime.width, covered.width);
  HW_CHECK_EQ(zPrime.height, covered.height);
  HW_CHECK_EQ(zPrime.width, out.width);
  HW_CHECK_EQ(zPrime.height, out.height);
  if (zPrime.empty()) return;
  switch (criterion) {
    case DeltaCriterion::FivePoint:
      computeImpl<DeltaCriterion::FivePoint>(zPrime, covered, out);
      break;
    case DeltaCriterion::PerAxisMax:
      computeImpl<DeltaCriterion::PerAxisMax>(zPrime, covered, out);
      break;
  }
}

void computeDeltaBuffer(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                        DeltaCriterion criterion, Image<float>* out) {
  HW_CHECK(out != nullptr);
  if (out->width() != zPrime.width || out->height() != zPrime.height) {
    out->resize(zPrime.width, zPrime.height);
  }
  computeDeltaBuffer(zPrime, covered, criterion, out->view());
}

}  // namespace hw::keyframe
