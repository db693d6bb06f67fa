#include "keyframe/keyframe_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <glm/glm.hpp>
#include <limits>
#include <numeric>
#include <string>

#include "core/check.h"
#include "core/timer.h"
#include "keyframe/keyframe.h"

namespace hw::keyframe {

// ---- schedule ---------------------------------------------------------------

const char* planCriterionName(PlanCriterion c) {
  switch (c) {
    case PlanCriterion::WorstFrame:
      return "worst";
    case PlanCriterion::SegmentMean:
      return "mean";
    case PlanCriterion::SegmentMedian:
      return "median";
    case PlanCriterion::WalkMedian:
      return "walk-median";
  }
  return "?";
}

bool parsePlanCriterion(const char* s, PlanCriterion* out) {
  if (std::strcmp(s, "worst") == 0) return *out = PlanCriterion::WorstFrame, true;
  if (std::strcmp(s, "mean") == 0) return *out = PlanCriterion::SegmentMean, true;
  if (std::strcmp(s, "median") == 0) return *out = PlanCriterion::SegmentMedian, true;
  if (std::strcmp(s, "walk-median") == 0) return *out = PlanCriterion::WalkMedian, true;
  return false;
}

std::vector<int> planKeyframes(int frames, double targetPsnrDb, int minGap, int maxGap,
                               const FramePredictor& predict, long* evaluations,
                               PlanCriterion criterion) {
  PlanSearch search;
  search.minGap = minGap;
  search.maxGap = maxGap;
  search.criterion = criterion;
  return planKeyframes(frames, targetPsnrDb, search, predict, evaluations);
}

void PredictionError::setResiduals(std::vector<double> r) {
  r.erase(std::remove_if(r.begin(), r.end(), [](double v) { return !std::isfinite(v); }), r.end());
  std::sort(r.begin(), r.end());
  residualsDb = std::move(r);
}

double PredictionError::probabilityAtLeast(double predictedDb, double targetPsnrDb) const {
  if (std::isnan(predictedDb)) return 0;  // NaN counts as below
  if (!residualsDb.empty()) {
    // Fraction of residuals e with predicted + e ≥ target.
    const double need = targetPsnrDb - predictedDb;
    const auto it = std::lower_bound(residualsDb.begin(), residualsDb.end(), need);
    return static_cast<double>(residualsDb.end() - it) / static_cast<double>(residualsDb.size());
  }
  if (!(sigmaDb > 0)) return predictedDb >= targetPsnrDb ? 1 : 0;
  // Φ((predicted − target) / σ) = erfc(−z / √2) / 2.
  return 0.5 * std::erfc(-(predictedDb - targetPsnrDb) / (sigmaDb * std::sqrt(2.0)));
}

std::vector<int> fewestKeyframesForMedian(int frames, double targetPsnrDb, int minGap, int maxGap,
                                          const FramePredictor& predict, long* evaluations,
                                          int* good, const PredictionError* error) {
  const PredictionError plain;
  const PredictionError& err = error ? *error : plain;
  HW_CHECK(std::isfinite(err.sigmaDb) && err.sigmaDb >= 0);
  long evals = 0;
  double g = 0;
  // With an uncertainty the expected number reaching the target; whole
  // numbers without one, so the DP's sums are exact.
  std::vector<int> keys = fewestKeyframesForMedian(
      frames, minGap, maxGap,
      [&](int k0, int k1) {
        double n = 0;
        for (int f = k0 + 1; f < k1; ++f) {
          ++evals;
          n += err.probabilityAtLeast(predict(k0, k1, f), targetPsnrDb);
        }
        return n;
      },
      &g);
  if (evaluations) *evaluations = evals;
  if (good && !keys.empty()) *good = static_cast<int>(std::floor(g));
  return keys;
}

std::vector<int> fewestKeyframesForMedian(int frames, int minGap, int maxGap,
                                          const SegmentGood& segmentGood, double* good,
                                          int minKeyframes) {
  HW_CHECK_GE(frames, 1);
  HW_CHECK_GE(minGap, 1);
  HW_CHECK_GE(maxGap, minGap);
  if (frames < 3) return {};
  const auto un = static_cast<std::size_t>(frames), ug = static_cast<std::size_t>(maxGap);
  // goodAt[k0·maxGap + g−1]: segmentGood(k0, k0+g).
  std::vector<double> goodAt(un * ug, 0);
  for (int k0 = 0; k0 < frames; ++k0)
    for (int g = 2; g <= maxGap && k0 + g < frames; ++g)
      goodAt[static_cast<std::size_t>(k0) * ug + static_cast<std::size_t>(g - 1)] =
          segmentGood(k0, k0 + g);
  // prev/cur[k]: most good frames in [0, k] with c keyframes, the last at k
  // (−1: impossible); parent[(c−1)·frames + k]: the keyframe before k.
  std::vector<double> prev(un, -1), cur(un, -1);
  std::vector<int> parent(un * un, -1);
  prev[0] = 0;
  const int last = frames - 1;
  for (int c = 2; c <= frames; ++c) {
    std::fill(cur.begin(), cur.end(), -1);
    for (int k1 = 1; k1 < frames; ++k1) {
      double bestV = -1;
      int bestK = -1;
      const int gFrom = k1 == last ? 1 : minGap;
      for (int g = gFrom; g <= maxGap && g <= k1; ++g) {
        const int k0 = k1 - g;
        const double p = prev[static_cast<std::size_t>(k0)];
        if (p < 0) continue;
        const double v = p + (g >= 2 ? goodAt[static_cast<std::size_t>(k0) * ug + static_cast<std::size_t>(g - 1)] : 0);
        if (v > bestV) bestV = v, bestK = k0;
      }
      cur[static_cast<std::size_t>(k1)] = bestV;
      parent[static_cast<std::size_t>(c - 1) * un + static_cast<std::size_t>(k1)] = bestK;
    }
    const int inBetween = frames - c;
    const double gl = cur[un - 1];
    if (inBetween >= 1 && 2 * gl > inBetween && c >= minKeyframes) {
      std::vector<int> keys(static_cast<std::size_t>(c), 0);
      int k = last;
      for (int i = c; i >= 1; --i) {
        keys[static_cast<std::size_t>(i - 1)] = k;
        if (i > 1) k = parent[static_cast<std::size_t>(i - 1) * un + static_cast<std::size_t>(k)];
      }
      HW_CHECK_EQ(keys.front(), 0);
      if (good) *good = gl;
      return keys;
    }
    std::swap(prev, cur);
  }
  return {};
}

namespace {

// The densest schedule allowed: keyframes every minGap frames and the last.
std::vector<int> densestSchedule(int frames, int minGap) {
  std::vector<int> keys;
  for (int k = 0; k < frames - 1; k += minGap) keys.push_back(k);
  keys.push_back(frames - 1);
  return keys;
}

}  // namespace

std::vector<int> planKeyframes(int frames, double targetPsnrDb, const PlanSearch& search,
                               const FramePredictor& predict, long* evaluations) {
  HW_CHECK_GE(frames, 1);
  HW_CHECK_GE(search.minGap, 1);
  HW_CHECK_GE(search.maxGap, search.minGap);
  HW_CHECK_GE(search.candidateStride, 1);
  HW_CHECK_GE(search.framesPerSegment, 0);
  if (search.criterion == PlanCriterion::WalkMedian) {
    std::vector<int> keys = fewestKeyframesForMedian(frames, targetPsnrDb, search.minGap,
                                                     search.maxGap, predict, evaluations, nullptr,
                                                     &search.error);
    if (!keys.empty()) return keys;
    return densestSchedule(frames, search.minGap);  // unreachable
  }
  std::vector<int> keys{0};
  long evals = 0;
  const int last = frames - 1;
  std::vector<int> tested;
  std::vector<double> values;
  tested.reserve(static_cast<std::size_t>(search.maxGap));
  values.reserve(static_cast<std::size_t>(search.maxGap));
  int k = 0;
  while (k < last) {
    const int first = std::min(k + search.minGap, last);
    const int stop = std::min(k + search.maxGap, last);
    int best = first;  // the minimum gap is taken even if it fails
    for (int b = first; b <= stop;) {
      // The in-between frames tested: all, or framesPerSegment evenly spaced.
      tested.clear();
      const int inner = b - k - 1;
      if (search.framesPerSegment == 0 || inner <= search.framesPerSegment) {
        for (int i = k + 1; i < b; ++i) tested.push_back(i);
      } else {
        for (int j = 1; j <= search.framesPerSegment; ++j)
          tested.push_back(k + static_cast<int>(std::lround(static_cast<double>(j) * (b - k) /
                                                            (search.framesPerSegment + 1))));
      }
      bool ok = true;
      values.clear();
      for (int i : tested) {
        ++evals;
        const double v = predict(k, b, i);
        values.push_back(std::isnan(v) ? -std::numeric_limits<double>::infinity() : v);
        if (search.criterion == PlanCriterion::WorstFrame && !(v >= targetPsnrDb)) {
          ok = false;  // NaN fails
          break;
        }
      }
      if (ok && !values.empty() && search.criterion == PlanCriterion::SegmentMean) {
        double sum = 0;
        for (double v : values) sum += v;
        ok = sum / static_cast<double>(values.size()) >= targetPsnrDb;
      } else if (ok && !values.empty() && search.criterion == PlanCriterion::SegmentMedian) {
        // Sorted descending, element ⌊(n−1)/2⌋: at least half of the frames
        // are ≥ the value tested.
        const auto mid = values.begin() + static_cast<std::ptrdiff_t>((values.size() - 1) / 2);
        std::nth_element(values.begin(), mid, values.end(), std::greater<double>());
        ok = *mid >= targetPsnrDb;
      }
      if (!ok) break;
      best = b;
      if (b == stop) break;
      b = std::min(b + search.candidateStride, stop);
    }
    keys.push_back(best);
    k = best;
  }
  if (evaluations) *evaluations = evals;
  return keys;
}

// ---- predictor names, regressors, fits --------------------------------------

const char* predictorName(Predictor p) {
  switch (p) {
    case Predictor::Distance:
      return "distance";
    case Predictor::Angle:
      return "angle";
    case Predictor::Holes:
      return "holes";
    case Predictor::Stretch:
      return "stretch";
    case Predictor::Disagreement:
      return "disagreement";
    case Predictor::HolesDistance:
      return "holes+distance";
    case Predictor::ProbePsnr:
      return "probe-psnr";
    case Predictor::ProbePsnrDistance:
      return "probe-psnr+distance";
    case Predictor::ProbePsnrFeatures:
      return "probe-psnr+features";
  }
  return "?";
}

bool parsePredictor(const char* s, Predictor* out) {
  for (Predictor p : kAllPredictors)
    if (std::strcmp(s, predictorName(p)) == 0) {
      *out = p;
      return true;
    }
  for (Predictor p : kProbePredictors)
    if (std::strcmp(s, predictorName(p)) == 0) {
      *out = p;
      return true;
    }
  return false;
}

double probePsnrDb(double mse) {
  if (std::isnan(mse)) return mse;
  if (!(mse > 0)) return kProbePsnrCap;
  return std::min(kProbePsnrCap, 10.0 * std::log10(255.0 * 255.0 / mse));
}

double predictorValue(const FrameFeatures& f, Predictor p) {
  switch (p) {
    case Predictor::Distance:
      return std::log10(f.relDistance + 1e-3);
    case Predictor::Angle:
      return std::log10(f.angleDeg + 1e-2);
    case Predictor::Holes:
      return std::log10(f.holeFraction + 1e-5);
    case Predictor::Stretch:
      return std::log10(f.stretch + 1e-3);
    case Predictor::Disagreement:
      return std::log10(f.disagreementMse + 1e-2);
    case Predictor::HolesDistance:
      return std::log10(f.holeFraction + 1e-5);
    case Predictor::ProbePsnr:
    case Predictor::ProbePsnrDistance:
    case Predictor::ProbePsnrFeatures:
      return std::log10(f.probeMse + 1e-2);
  }
  return std::nan("");
}

double predictorValue2(const FrameFeatures& f, Predictor p) {
  return p == Predictor::HolesDistance || p == Predictor::ProbePsnrDistance ||
                 p == Predictor::ProbePsnrFeatures
             ? std::log10(f.relDistance + 1e-3)
             : 0.0;
}

std::vector<double> predictorValuesMore(const FrameFeatures& f, Predictor p) {
  if (p != Predictor::ProbePsnrFeatures) return {};
  return {predictorValue(f, Predictor::Holes), predictorValue(f, Predictor::Stretch),
          predictorValue(f, Predictor::Disagreement), predictorValue(f, Predictor::Angle)};
}

int predictorRegressors(Predictor p) {
  switch (p) {
    case Predictor::HolesDistance:
    case Predictor::ProbePsnrDistance:
      return 2;
    case Predictor::ProbePsnrFeatures:
      return 6;
    default:
      return 1;
  }
}

bool PsnrFit::finite() const {
  if (!(std::isfinite(intercept) && std::isfinite(slope) && std::isfinite(slope2))) return false;
  for (double m : more)
    if (!std::isfinite(m)) return false;
  return true;
}

double predictPsnr(const PsnrFit& fit, const FrameFeatures& f, Predictor p) {
  double v = fit.predict(predictorValue(f, p), predictorValue2(f, p));
  if (p == Predictor::ProbePsnrFeatures) {
    const std::vector<double> x = predictorValuesMore(f, p);
    if (fit.more.size() != x.size()) return std::nan("");
    for (std::size_t i = 0; i < x.size(); ++i) v += fit.more[i] * x[i];
  }
  return v;
}

namespace {

// Least squares with k regressors (rows of x, k each) and an intercept:
// the centred normal equations solved by Gaussian elimination with partial
// pivoting. coef[0] = intercept, coef[1..k] = slopes. A regressor constant
// over the data (no variance) gets slope 0 (its level is in the intercept);
// empty when the others are collinear or n ≤ k.
std::vector<double> leastSquares(const std::vector<std::vector<double>>& x, const std::vector<double>& y) {
  const std::size_t n = y.size();
  if (n == 0) return {};
  const std::size_t k = x[0].size();
  if (n <= k) return {};
  std::vector<double> mx(k, 0.0);
  double my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < k; ++j) mx[j] += x[i][j];
    my += y[i];
  }
  for (double& m : mx) m /= static_cast<double>(n);
  my /= static_cast<double>(n);
  // Augmented k × (k+1) system: Σ (x−mx)(x−mx)ᵀ β = Σ (x−mx)(y−my).
  std::vector<std::vector<double>> a(k, std::vector<double>(k + 1, 0.0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t r = 0; r < k; ++r) {
      const double dr = x[i][r] - mx[r];
      for (std::size_t c = 0; c < k; ++c) a[r][c] += dr * (x[i][c] - mx[c]);
      a[r][k] += dr * (y[i] - my);
    }
  double scale = 0;
  for (std::size_t r = 0; r < k; ++r) scale = std::max(scale, std::abs(a[r][r]));
  // Constant regressors: slope 0, i.e. row and column replaced by the identity.
  for (std::size_t r = 0; r < k; ++r)
    if (!(a[r][r] > 1e-12 * std::max(1.0, scale))) {
      for (std::size_t c = 0; c < k; ++c) a[r][c] = 0, a[c][r] = 0;
      a[r][r] = 1;
      a[r][k] = 0;
    }
  for (std::size_t col = 0; col < k; ++col) {
    std::size_t piv = col;
    for (std::size_t r = col + 1; r < k; ++r)
      if (std::abs(a[r][col]) > std::abs(a[piv][col])) piv = r;
    if (!(std::abs(a[piv][col]) > 1e-12 * std::max(1.0, scale))) return {};
    std::swap(a[piv], a[col]);
    for (std::size_t r = 0; r < k; ++r) {
      if (r == col) continue;
      const double m = a[r][col] / a[col][col];
      for (std::size_t c = col; c <= k; ++c) a[r][c] -= m * a[col][c];
    }
  }
  std::vector<double> coef(k + 1);
  double icpt = my;
  for (std::size_t j = 0; j < k; ++j) {
    coef[j + 1] = a[j][k] / a[j][j];
    icpt -= coef[j + 1] * mx[j];
  }
  coef[0] = icpt;
  return coef;
}

}  // namespace

PsnrFit fitPredictor(const std::vector<FrameFeatures>& f, const std::vector<double>& psnr,
                     Predictor p) {
  HW_CHECK_EQ(f.size(), psnr.size());
  std::vector<double> x, x2, y;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double a = predictorValue(f[i], p), b = predictorValue2(f[i], p);
    if (std::isfinite(a) && std::isfinite(b) && std::isfinite(psnr[i]))
      x.push_back(a), x2.push_back(b), y.push_back(psnr[i]);
  }
  if (p == Predictor::ProbePsnrFeatures) {
    std::vector<std::vector<double>> rows;
    std::vector<double> ys;
    for (std::size_t i = 0; i < f.size(); ++i) {
      std::vector<double> r{predictorValue(f[i], p), predictorValue2(f[i], p)};
      for (double v : predictorValuesMore(f[i], p)) r.push_back(v);
      bool ok = std::isfinite(psnr[i]);
      for (double v : r) ok = ok && std::isfinite(v);
      if (ok) rows.push_back(std::move(r)), ys.push_back(psnr[i]);
    }
    const std::vector<double> c = leastSquares(rows, ys);
    PsnrFit r{std::nan(""), std::nan(""), std::nan(""), {}};
    if (c.size() != 7) {
      r.more.assign(4, std::nan(""));
      return r;
    }
    r.intercept = c[0], r.slope = c[1], r.slope2 = c[2];
    r.more.assign(c.begin() + 3, c.end());
    return r;
  }
  if (p != Predictor::HolesDistance && p != Predictor::ProbePsnrDistance) return fitLine(x, y);
  // Two regressors: solve the centred 2×2 normal equations.
  const double n = static_cast<double>(x.size());
  const PsnrFit bad{std::nan(""), std::nan(""), std::nan("")};
  if (n < 3) return bad;
  double mx = 0, m2 = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], m2 += x2[i], my += y[i];
  mx /= n, m2 /= n, my /= n;
  double sxx = 0, s22 = 0, sx2 = 0, sxy = 0, s2y = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double a = x[i] - mx, b = x2[i] - m2, c = y[i] - my;
    sxx += a * a, s22 += b * b, sx2 += a * b, sxy += a * c, s2y += b * c;
  }
  const double det = sxx * s22 - sx2 * sx2;
  if (!(std::abs(det) > 1e-12 * std::max(1.0, sxx * s22))) return bad;
  PsnrFit r;
  r.slope = (sxy * s22 - s2y * sx2) / det;
  r.slope2 = (s2y * sxx - sxy * sx2) / det;
  r.intercept = my - r.slope * mx - r.slope2 * m2;
  return r;
}

PsnrFit defaultFit(Predictor p) {
  // Least-squares fits over the in-between frames of the fixed walks (every
  // 4..20 frames) on the built-in indoor path (see header); Spearman ρ with
  // the measured PSNR there: holes −0.90, angle −0.61, distance −0.52,
  // stretch −0.34, disagreement +0.23 (wrong sign: not a usable predictor;
  // its nominal fit only keeps the planner's direction). For a target derived
  // from the same fit only the slope's sign changes a plan.
  switch (p) {
    case Predictor::Distance:
      return {20.0, -10.8};
    case Predictor::Angle:
      return {30.5, -5.6};
    case Predictor::Holes:
      return {20.4, -3.08};
    case Predictor::Stretch:
      return {27.9, -0.085};
    case Predictor::Disagreement:
      return {40.0, -4.0};
    case Predictor::HolesDistance:
      return {18.43, -2.79, -3.70};
    // The probe predictors (64-px probes rendered at 2x, blur radius 1,
    // previous-frame fill): fitted on every (k0, k1, frame) up to 20 apart on
    // the indoor path at 256² (schedule-oracle's table, 22,800 entries);
    // Spearman 0.96 there and, out of sample, 0.97 on q3:oa_dm5.
    case Predictor::ProbePsnr:
      return {41.93, -8.41};
    case Predictor::ProbePsnrDistance:
      return {40.99, -8.23, -0.96};
    // The same table, six regressors (probe MSE, distance, holes, stretch,
    // disagreement, angle): residual sd 1.49 dB there. Meant to be refitted
    // on the scene (walk --calibrate-spacing).
    case Predictor::ProbePsnrFeatures:
      return {38.565, -7.332, -0.485, {-0.536, -0.125, -0.026, -0.148}};
  }
  return {};
}

PsnrFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  HW_CHECK_EQ(x.size(), y.size());
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    n += 1;
    sx += x[i];
    sy += y[i];
  }
  if (n < 2) return {std::nan(""), std::nan("")};
  const double mx = sx / n, my = sy / n;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (!(sxx > 0)) return {std::nan(""), std::nan("")};
  const double slope = sxy / sxx;
  return {my - slope * mx, slope};
}

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  HW_CHECK_EQ(x.size(), y.size());
  std::vector<double> a, b;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::isfinite(x[i]) && std::isfinite(y[i])) a.push_back(x[i]), b.push_back(y[i]);
  if (a.size() < 2) return std::nan("");
  const double n = static_cast<double>(a.size());
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n;
  const double mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  if (!(saa > 0) || !(sbb > 0)) return std::nan("");
  return sab / std::sqrt(saa * sbb);
}

namespace {
// Ranks with ties averaged (1-based).
std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
    const double avg = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t t = i; t <= j; ++t) r[idx[t]] = avg;
    i = j + 1;
  }
  return r;
}
}  // namespace

double spearman(const std::vector<double>& x, const std::vector<double>& y) {
  HW_CHECK_EQ(x.size(), y.size());
  std::vector<double> a, b;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::isfinite(x[i]) && std::isfinite(y[i])) a.push_back(x[i]), b.push_back(y[i]);
  return pearson(ranks(a), ranks(b));
}

// ---- probes and forward splats ------------------------------------------------

struct KeyframeProbe::Probe {
  Camera camera;
  Image<Rgba8> colour;
  Image<float> eyeZ;
  Image<std::uint8_t> covered;
  // World point of a covered pixel's centre; unit view direction of an empty one.
  std::vector<glm::dvec3> point;
  double medianDepth = 1;
};

namespace {

constexpr std::uint8_t kNone = 0, kSky = 1, kSurface = 2;

// One keyframe probe forward-splatted into a frame camera.
struct SplatLayer {
  std::vector<float> depth;
  std::vector<Rgba8> colour;
  std::vector<std::uint8_t> state;
  void reset(std::size_t n) {
    depth.assign(n, std::numeric_limits<float>::infinity());
    colour.assign(n, Rgba8{});
    state.assign(n, kNone);
  }
};

// Forward splat of `src` into `target` (same probe size): each covered pixel
// becomes a rectangle covering its projected footprint (from the projected
// neighbours, continuous depth only; clamped to 8 probe pixels per side),
// z-tested; empty pixels become a backdrop at infinity, like the GL warp's
// sky rectangles. Returns the mean |log2 area ratio| of the pixels that land
// in the frame (stretch).
double splat(const KeyframeProbe::Probe& src, const Camera& target, SplatLayer& out) {
  const int w = target.width, h = target.height;
  out.reset(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  const Camera& sc = src.camera;
  const int sw = sc.width, sh = sc.height;
  double stretchSum = 0;
  long stretchN = 0;
  auto fill = [&](double u, double v, double hx, double hy, float z, Rgba8 c, bool sky) {
    const int x0 = std::max(0, static_cast<int>(std::ceil(u - hx - 0.5)));
    const int x1 = std::min(w - 1, static_cast<int>(std::floor(u + hx - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(v - hy - 0.5)));
    const int y1 = std::min(h - 1, static_cast<int>(std::floor(v + hy - 0.5)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t t = static_cast<std::size_t>(y) * w + x;
        if (sky) {
          if (out.state[t] == kNone) out.state[t] = kSky, out.colour[t] = c;
        } else if (z < out.depth[t]) {
          out.depth[t] = z, out.colour[t] = c, out.state[t] = kSurface;
        }
      }
  };
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x) {
      const std::size_t s = static_cast<std::size_t>(y) * sw + x;
      const Rgba8 c = src.colour(x, y);
      if (!src.covered(x, y)) {
        const ProjectedPoint p = target.project(target.eye + src.point[s]);
        if (p.zEye <= 1e-9 || !std::isfinite(p.u) || !std::isfinite(p.v)) continue;
        fill(p.u, p.v, 0.75, 0.75, 0, c, true);
        continue;
      }
      const double z = src.eyeZ(x, y);
      const ProjectedPoint p = target.project(src.point[s]);
      if (p.zEye <= target.nearPlane) continue;
      if (p.u < -8 || p.v < -8 || p.u > w + 8 || p.v > h + 8) continue;
      // A neighbour on the same surface: depth within 25 % (one probe pixel
      // spans several frame pixels, so grazing floors change fast); else the
      // one on the other side, mirrored; else a point at the same depth.
      auto continuous = [&](int xn, int yn) {
        return xn >= 0 && yn >= 0 && xn < sw && yn < sh && src.covered(xn, yn) &&
               std::abs(src.eyeZ(xn, yn) - z) < 0.25 * z;
      };
      auto step = [&](int dx, int dy, double* du, double* dv) {
        ProjectedPoint q;
        double sign = 1;
        if (continuous(x + dx, y + dy)) {
          q = target.project(src.point[static_cast<std::size_t>(y + dy) * sw + (x + dx)]);
        } else if (continuous(x - dx, y - dy)) {
          q = target.project(src.point[static_cast<std::size_t>(y - dy) * sw + (x - dx)]);
          sign = -1;
        } else {
          q = target.project(sc.unproject(x + dx + 0.5, y + dy + 0.5, z));
        }
        *du = sign * (q.u - p.u);
        *dv = sign * (q.v - p.v);
        return q.zEye > target.nearPlane;
      };
      double dux = 0, dvx = 0, duy = 0, dvy = 0;
      double hx = 0.5, hy = 0.5;
      if (step(1, 0, &dux, &dvx) && step(0, 1, &duy, &dvy)) {
        hx = std::clamp(0.5 * (std::abs(dux) + std::abs(duy)), 0.5, 8.0);
        hy = std::clamp(0.5 * (std::abs(dvx) + std::abs(dvy)), 0.5, 8.0);
        if (p.u >= 0 && p.v >= 0 && p.u < w && p.v < h) {
          const double area = std::abs(dux * dvy - duy * dvx);
          stretchSum += std::abs(std::log2(std::max(area, 1e-4)));
          ++stretchN;
        }
      }
      fill(p.u, p.v, hx, hy, static_cast<float>(p.zEye), c, false);
    }
  return stretchN ? stretchSum / static_cast<double>(stretchN) : 0.0;
}

}  // namespace

struct KeyframeProbe::Scratch {
  SplatLayer a, b;
  // probeError: the composed probe (hole = 1) and per-pixel sums for the blur.
  std::vector<Rgba8> composed;
  std::vector<std::uint8_t> hole;
  std::vector<std::int32_t> sat;
};

struct KeyframeProbe::Warped {
  SplatLayer layer;
  long lastUse = 0;
};

KeyframeProbe::KeyframeProbe(GeometryRenderer& renderer, std::function<Camera(int)> cameraOf,
                             int probeSize, ProbeErrorOptions error)
    : renderer_(renderer),
      cameraOf_(std::move(cameraOf)),
      probeSize_(probeSize),
      error_(error),
      scratch_(std::make_unique<Scratch>()) {
  HW_CHECK_GE(probeSize, 4);
  HW_CHECK_GE(error.supersample, 1);
  HW_CHECK_GE(error.blurRadius, 0);
  HW_CHECK_GE(error.shiftTolerance, 0);
}

KeyframeProbe::~KeyframeProbe() = default;

Camera KeyframeProbe::probeCamera(int frame) const {
  Camera c = cameraOf_(frame);
  const int longer = std::max(c.width, c.height);
  const double s = static_cast<double>(std::min(probeSize_, longer)) / longer;
  c.width = std::max(1, static_cast<int>(std::lround(c.width * s)));
  c.height = std::max(1, static_cast<int>(std::lround(c.height * s)));
  return c;
}

Result<const KeyframeProbe::Probe*> KeyframeProbe::probe(int frame) {
  auto it = probes_.find(frame);
  if (it != probes_.end()) return it->second.get();
  auto p = std::make_unique<Probe>();
  p->camera = probeCamera(frame);
  const int w = p->camera.width, h = p->camera.height;
  const int ss = error_.supersample;
  Camera rc = p->camera;
  rc.width = w * ss;
  rc.height = h * ss;
  Keyframe kf;
  RenderStats rs;
  HW_TRY(renderer_.renderKeyframe(rc, kf, &rs));
  renderMs_ += rs.drawMs + rs.readbackMs;
  ++probesRendered_;
  if (ss == 1) {
    p->colour = std::move(kf.colour);
    p->eyeZ = std::move(kf.eyeZ);
    p->covered = std::move(kf.covered);
  } else {
    // Box-filtered colour; a pixel is covered when most of its samples are,
    // at its nearest sample's depth (a depth average would float between
    // surfaces).
    p->colour = Image<Rgba8>(w, h);
    p->eyeZ = Image<float>(w, h);
    p->covered = Image<std::uint8_t>(w, h);
    const int n = ss * ss;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        int r = 0, g = 0, b = 0, a = 0, cov = 0;
        float zmin = std::numeric_limits<float>::infinity();
        for (int j = 0; j < ss; ++j)
          for (int i = 0; i < ss; ++i) {
            const Rgba8 c = kf.colour(x * ss + i, y * ss + j);
            r += c.r, g += c.g, b += c.b, a += c.a;
            if (kf.covered(x * ss + i, y * ss + j)) {
              ++cov;
              zmin = std::min(zmin, kf.eyeZ(x * ss + i, y * ss + j));
            }
          }
        auto avg = [&](int v) { return static_cast<std::uint8_t>((v + n / 2) / n); };
        p->colour(x, y) = Rgba8{avg(r), avg(g), avg(b), avg(a)};
        const bool c = 2 * cov > n;
        p->covered(x, y) = c ? 1 : 0;
        p->eyeZ(x, y) = c ? zmin : 0.0f;
      }
  }
  p->point.resize(static_cast<std::size_t>(w) * h);
  std::vector<double> depths;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t s = static_cast<std::size_t>(y) * w + x;
      if (p->covered(x, y)) {
        p->point[s] = p->camera.unproject(x + 0.5, y + 0.5, p->eyeZ(x, y));
        depths.push_back(p->eyeZ(x, y));
      } else {
        p->point[s] = glm::normalize(p->camera.unproject(x + 0.5, y + 0.5, 1.0) - p->camera.eye);
      }
    }
  // All sky: parallax is nil, any depth works; use the far plane.
  p->medianDepth = depths.empty() ? p->camera.farPlane : std::max(median(depths), 1e-6);
  const Probe* raw = p.get();
  probes_.emplace(frame, std::move(p));
  return raw;
}

namespace {
// FrameFeatures::relDistance: the eye's translation from the nearer keyframe
// relative to that keyframe's median scene depth.
double relativeDistance(const glm::dvec3& eye, const KeyframeProbe::Probe& a,
                        const KeyframeProbe::Probe& b) {
  return std::min(glm::length(eye - a.camera.eye) / a.medianDepth,
                  glm::length(eye - b.camera.eye) / b.medianDepth);
}
}  // namespace

Result<FrameFeatures> KeyframeProbe::features(int k0, int k1, int frame) {
  const auto key = std::make_tuple(k0, k1, frame);
  if (auto it = memo_.find(key); it != memo_.end()) return it->second;
  auto ra = probe(k0);
  if (!ra) return ra.error();
  auto rb = probe(k1);
  if (!rb) return rb.error();
  const Probe* pa = *ra;
  const Probe* pb = *rb;
  Stopwatch sw;
  const Camera t = probeCamera(frame);
  const double da = glm::length(t.eye - pa->camera.eye), db = glm::length(t.eye - pb->camera.eye);
  const Probe* fg = da <= db ? pa : pb;  // nearer eye in front, ties to the earlier keyframe
  const Probe* bg = fg == pa ? pb : pa;
  FrameFeatures f;
  f.relDistance = relativeDistance(t.eye, *pa, *pb);
  f.angleDeg =
      glm::degrees(std::acos(std::clamp(glm::dot(t.forward, fg->camera.forward), -1.0, 1.0)));
  SplatLayer& la = scratch_->a;
  SplatLayer& lb = scratch_->b;
  f.stretch = splat(*fg, t, la);
  splat(*bg, t, lb);
  long holes = 0, both = 0;
  double sq = 0;
  const int w = t.width, h = t.height;
  auto hole = [&](int x, int y) {
    const std::size_t i = static_cast<std::size_t>(y) * w + x;
    return la.state[i] == kNone && lb.state[i] == kNone;
  };
  for (std::size_t i = 0; i < la.state.size(); ++i) {
    const std::uint8_t sa = la.state[i], sb = lb.state[i];
    if (sa == kNone && sb == kNone) {
      // A one-pixel crack between covered pixels is splatting's, not a
      // disocclusion: the warp's quads close it.
      const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
      const bool crackX = x > 0 && x + 1 < w && !hole(x - 1, y) && !hole(x + 1, y);
      const bool crackY = y > 0 && y + 1 < h && !hole(x, y - 1) && !hole(x, y + 1);
      if (!crackX && !crackY) ++holes;
    }
    const bool same =
        (sa == kSky && sb == kSky) ||
        (sa == kSurface && sb == kSurface &&
         std::abs(la.depth[i] - lb.depth[i]) < 0.05f * std::min(la.depth[i], lb.depth[i]));
    if (!same) continue;
    ++both;
    const Rgba8 ca = la.colour[i], cb = lb.colour[i];
    const double dr = ca.r - cb.r, dg = ca.g - cb.g, dbl = ca.b - cb.b;
    sq += (dr * dr + dg * dg + dbl * dbl) / 3.0;
  }
  f.holeFraction = static_cast<double>(holes) / static_cast<double>(la.state.size());
  f.disagreementMse = both ? sq / static_cast<double>(both) : 0.0;
  splatMs_ += sw.ms();
  memo_.emplace(key, f);
  return f;
}

Result<const KeyframeProbe::Warped*> KeyframeProbe::warped(int key, int frame) {
  const auto id = std::make_pair(key, frame);
  if (auto it = warpCache_.find(id); it != warpCache_.end()) {
    it->second->lastUse = ++warpTick_;
    return static_cast<const Warped*>(it->second.get());
  }
  auto rk = probe(key);
  if (!rk) return rk.error();
  const Camera t = probeCamera(frame);
  const std::size_t pixels = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  // ~64 MB of layers (9 bytes a pixel); the planners sweep k0 forward, so the
  // warps of the last few k0 are what is reused.
  const std::size_t cap = std::max<std::size_t>(16, (64u << 20) / (9 * pixels));
  if (warpCache_.size() >= cap) {
    std::vector<long> uses;
    uses.reserve(warpCache_.size());
    for (const auto& [k, w] : warpCache_) uses.push_back(w->lastUse);
    const auto mid = uses.begin() + static_cast<std::ptrdiff_t>(uses.size() / 2);
    std::nth_element(uses.begin(), mid, uses.end());
    const long cut = *mid;
    for (auto it = warpCache_.begin(); it != warpCache_.end();)
      it = it->second->lastUse < cut ? warpCache_.erase(it) : std::next(it);
  }
  auto w = std::make_unique<Warped>();
  Stopwatch sw;
  splat(**rk, t, w->layer);
  splatMs_ += sw.ms();
  w->lastUse = ++warpTick_;
  const Warped* raw = w.get();
  warpCache_.emplace(id, std::move(w));
  return raw;
}

Result<double> KeyframeProbe::relDistance(int k0, int k1, int frame) {
  const auto key = std::make_tuple(k0, k1, frame);
  if (auto it = distanceMemo_.find(key); it != distanceMemo_.end()) return it->second;
  auto ra = probe(k0);
  if (!ra) return ra.error();
  auto rb = probe(k1);
  if (!rb) return rb.error();
  const glm::dvec3 eye = cameraOf_(frame).eye;  // a path camera: not free, hence the memo
  const double d = relativeDistance(eye, **ra, **rb);
  distanceMemo_.emplace(key, d);
  return d;
}

Result<double> KeyframeProbe::probeError(int k0, int k1, int frame) {
  const auto key = std::make_tuple(k0, k1, frame);
  if (auto it = errorMemo_.find(key); it != errorMemo_.end()) return it->second;
  if (!error_.previousFill || frame <= k0 || frame >= k1) {
    auto e = composeAndCompare(k0, k1, frame, nullptr);
    if (!e) return e.error();
    errorMemo_.emplace(key, *e);
    return *e;
  }
  // The walk's chain: frame k0 shows keyframe k0, and each later frame takes
  // its holes from the one before. Continue the segment's chain, or start it
  // again from keyframe k0.
  if (chains_.size() > 512) chains_.clear();  // the planners sweep k0 forward
  Chain& ch = chains_[std::make_pair(k0, k1)];
  int start = ch.frame + 1;
  if (!(ch.frame > k0 && ch.frame < frame)) {
    auto rk = probe(k0);
    if (!rk) return rk.error();
    ch.image = (*rk)->colour.pixels();
    start = k0 + 1;
  }
  for (int g = start; g <= frame; ++g) {
    auto e = composeAndCompare(k0, k1, g, &ch.image);
    if (!e) return e.error();
    ch.image = scratch_->composed;
    ch.frame = g;
    errorMemo_.emplace(std::make_tuple(k0, k1, g), *e);
  }
  return errorMemo_.at(key);
}

Result<double> KeyframeProbe::composeAndCompare(int k0, int k1, int frame,
                                                const std::vector<Rgba8>* previous) {
  auto ra = probe(k0);
  if (!ra) return ra.error();
  auto rb = probe(k1);
  if (!rb) return rb.error();
  auto rf = probe(frame);
  if (!rf) return rf.error();
  const Probe& ref = **rf;
  const Camera t = probeCamera(frame);
  const double da = glm::length(t.eye - (*ra)->camera.eye);
  const double db = glm::length(t.eye - (*rb)->camera.eye);
  const int fgKey = da <= db ? k0 : k1;  // nearer eye in front, ties to the earlier keyframe
  const int bgKey = fgKey == k0 ? k1 : k0;
  auto rfg = warped(fgKey, frame);
  if (!rfg) return rfg.error();
  auto rbg = warped(bgKey, frame);  // touches fg's layer first: it survives the eviction
  if (!rbg) return rbg.error();
  Stopwatch sw;
  const SplatLayer& la = (*rfg)->layer;
  const SplatLayer& lb = (*rbg)->layer;
  const int w = t.width, h = t.height;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<Rgba8>& comp = scratch_->composed;
  std::vector<std::uint8_t>& hole = scratch_->hole;
  comp.resize(n);
  hole.resize(n);
  // The paper's overlay rule: the foreground where it covers (its sky
  // backdrop included), else the background, else a hole.
  // With `previous`, holes take the previous frame's pixel, as in the walk.
  for (std::size_t i = 0; i < n; ++i) {
    hole[i] = 0;
    if (la.state[i] != kNone) comp[i] = la.colour[i];
    else if (lb.state[i] != kNone) comp[i] = lb.colour[i];
    else if (previous && previous->size() == n) comp[i] = (*previous)[i];
    else hole[i] = 1, comp[i] = Rgba8{};
  }
  const int r = error_.blurRadius;
  double sum = 0;
  const int tol = error_.shiftTolerance;
  if (r == 0) {
    // Each composed pixel against the best-matching reference pixel within
    // `tol` (0: the same pixel).
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (hole[i]) {
          sum += error_.holeMse;
          continue;
        }
        const Rgba8 c = comp[i];
        double best = std::numeric_limits<double>::infinity();
        for (int yy = std::max(0, y - tol); yy <= std::min(h - 1, y + tol); ++yy)
          for (int xx = std::max(0, x - tol); xx <= std::min(w - 1, x + tol); ++xx) {
            const Rgba8 q = ref.colour(xx, yy);
            const double er = c.r - q.r, eg = c.g - q.g, eb = c.b - q.b;
            best = std::min(best, (er * er + eg * eg + eb * eb) / 3.0);
          }
        sum += best;
      }
  } else {
    // Box means of the composed and the reference probe over the same
    // non-hole pixels of each window, from summed-area tables (7 channels:
    // composed RGB, reference RGB, count).
    const std::size_t sw1 = static_cast<std::size_t>(w) + 1;
    std::vector<std::int32_t>& sat = scratch_->sat;
    sat.assign(7 * sw1 * (static_cast<std::size_t>(h) + 1), 0);
    auto at = [&](int ch, int x, int y) -> std::int32_t& {
      return sat[(static_cast<std::size_t>(ch) * (static_cast<std::size_t>(h) + 1) +
                  static_cast<std::size_t>(y)) * sw1 + static_cast<std::size_t>(x)];
    };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        std::int32_t v[7] = {0, 0, 0, 0, 0, 0, 0};
        if (!hole[i]) {
          const Rgba8 c = comp[i], q = ref.colour(x, y);
          v[0] = c.r, v[1] = c.g, v[2] = c.b, v[3] = q.r, v[4] = q.g, v[5] = q.b, v[6] = 1;
        }
        for (int ch = 0; ch < 7; ++ch)
          at(ch, x + 1, y + 1) = v[ch] + at(ch, x, y + 1) + at(ch, x + 1, y) - at(ch, x, y);
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (hole[static_cast<std::size_t>(y) * w + x]) {
          sum += error_.holeMse;
          continue;
        }
        const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1);
        const int y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
        double box[7];
        for (int ch = 0; ch < 7; ++ch)
          box[ch] = at(ch, x1, y1) - at(ch, x0, y1) - at(ch, x1, y0) + at(ch, x0, y0);
        const double m = box[6];  // >= 1: the pixel itself
        const double er = (box[0] - box[3]) / m, eg = (box[1] - box[4]) / m,
                     eb = (box[2] - box[5]) / m;
        sum += (er * er + eg * eg + eb * eb) / 3.0;
      }
  }
  const double mse = sum / static_cast<double>(n);
  splatMs_ += sw.ms();
  return mse;
}

// ---- the planner ----------------------------------------------------------------

Result<FrameFeatures> predictorFeatures(KeyframeProbe& probe, Predictor p, int k0, int k1,
                                        int frame) {
  if (!isProbePredictor(p)) return probe.features(k0, k1, frame);
  auto e = probe.probeError(k0, k1, frame);
  if (!e) return e.error();
  if (p == Predictor::ProbePsnrFeatures) {
    auto all = probe.features(k0, k1, frame);
    if (!all) return all.error();
    FrameFeatures ff = *all;
    ff.probeMse = *e;
    return ff;
  }
  FrameFeatures ff;
  ff.probeMse = *e;
  if (p == Predictor::ProbePsnrDistance) {
    auto d = probe.relDistance(k0, k1, frame);
    if (!d) return d.error();
    ff.relDistance = *d;
  }
  return ff;
}

Result<PredictorCalibration> calibratePredictor(KeyframeProbe& probe, Predictor p,
                                                const std::vector<CalibrationSample>& samples) {
  std::vector<FrameFeatures> features;
  std::vector<double> measured;
  features.reserve(samples.size());
  measured.reserve(samples.size());
  for (const CalibrationSample& s : samples) {
    if (!(s.k0 < s.frame && s.frame < s.k1))
      return makeError("predictor calibration: expected k0 < frame < k1, got (" +
                       std::to_string(s.k0) + ", " + std::to_string(s.frame) + ", " +
                       std::to_string(s.k1) + ")");
    auto f = predictorFeatures(probe, p, s.k0, s.k1, s.frame);
    if (!f) return f.error();
    features.push_back(*f);
    measured.push_back(s.psnrDb);
  }
  PredictorCalibration c;
  c.fit = fitPredictor(features, measured, p);
  const int params = predictorRegressors(p) + 1;
  std::vector<double> pr, me;
  double ss = 0;
  c.predictedDb.assign(samples.size(), std::nan(""));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double v = predictPsnr(c.fit, features[i], p);
    if (!std::isfinite(v) || !std::isfinite(measured[i])) continue;
    c.predictedDb[i] = v;
    pr.push_back(v), me.push_back(measured[i]);
    ss += (measured[i] - v) * (measured[i] - v);
  }
  c.samples = static_cast<int>(pr.size());
  if (!c.fit.finite() || c.samples <= params)
    return makeError("predictor calibration (" + std::string(predictorName(p)) + "): expected more than " +
                     std::to_string(params) + " measured in-between frames with distinct predictor "
                     "values, got " + std::to_string(samples.size()) + " frames that do not determine a fit");
  c.residualStdDb = std::sqrt(ss / (c.samples - params));
  c.spearman = spearman(pr, me);
  return c;
}

PathOffsets smoothResidualsAlongPath(int frames, const std::vector<int>& sampleFrames,
                                     const std::vector<double>& residualsDb, double widthFrames,
                                     double prior, const std::vector<int>& sampleGroup) {
  PathOffsets out;
  out.offsetDb.assign(static_cast<std::size_t>(std::max(frames, 0)), 0.0);
  out.heldOutResidualsDb.assign(residualsDb.size(), std::nan(""));
  const std::size_t n = std::min(sampleFrames.size(), residualsDb.size());
  const bool smooth = widthFrames > 0 && std::isfinite(widthFrames);
  const bool grouped = sampleGroup.size() >= n;
  auto groupOf = [&](std::size_t i) { return grouped ? sampleGroup[i] : sampleFrames[i]; };
  // Σ w r and Σ w at frame f, leaving out the samples of group `skip` (none
  // when held is false).
  auto sums = [&](int f, bool held, int skip, double* wr, double* w) {
    *wr = 0, *w = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if ((held && groupOf(i) == skip) || !std::isfinite(residualsDb[i])) continue;
      const double d = (sampleFrames[i] - f) / widthFrames;
      if (d * d > 25) continue;
      const double wi = std::exp(-0.5 * d * d);
      *wr += wi * residualsDb[i], *w += wi;
    }
  };
  double wr = 0, w = 0;
  if (smooth)
    for (int f = 0; f < frames; ++f) {
      sums(f, false, 0, &wr, &w);
      out.offsetDb[static_cast<std::size_t>(f)] = (w + prior) > 0 ? wr / (w + prior) : 0.0;
    }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(residualsDb[i])) continue;
    double off = 0;
    if (smooth) {
      sums(sampleFrames[i], true, groupOf(i), &wr, &w);
      off = (w + prior) > 0 ? wr / (w + prior) : 0;
    }
    out.heldOutResidualsDb[i] = residualsDb[i] - off;
  }
  double ss = 0;
  int m = 0;
  for (double r : out.heldOutResidualsDb)
    if (std::isfinite(r)) ss += r * r, ++m;
  out.heldOutRmsDb = m > 0 ? std::sqrt(ss / m) : 0.0;
  return out;
}

FramePredictor withPathOffsets(FramePredictor predict, std::vector<double> offsetDb) {
  if (offsetDb.empty()) return predict;
  return [predict = std::move(predict), off = std::move(offsetDb)](int k0, int k1, int f) {
    return predict(k0, k1, f) + pathOffsetAt(off, f);
  };
}

namespace {

// In-between frames of (k0, k1) measured ≥ target (NaN counts below).
double measuredGood(const std::vector<double>& psnr, double targetPsnrDb) {
  double n = 0;
  for (double v : psnr) n += v >= targetPsnrDb ? 1 : 0;
  return n;
}

}  // namespace

Result<VerifiedPlan> planVerified(int frames, double targetPsnrDb, const PlanSearch& search,
                                  const FramePredictor& predict, MeasuredSegments& measured,
                                  const SegmentMeasurer& measure, const VerifyOptions& opt) {
  if (frames < 3)
    return makeError("verified plan: expected at least 3 frames, got " + std::to_string(frames));
  if (search.minGap < 1 || search.maxGap < search.minGap)
    return makeError("verified plan: gaps must satisfy 1 <= min-gap <= max-gap, got min " +
                     std::to_string(search.minGap) + ", max " + std::to_string(search.maxGap));
  if (opt.maxRounds < 0 || !(opt.windowFrames >= 0) || !std::isfinite(opt.windowFrames) ||
      !(opt.prior >= 0) || !std::isfinite(targetPsnrDb) || !(opt.optimismDb >= 0) ||
      !std::isfinite(opt.optimismDb))
    return makeError(
        "verified plan: expected rounds >= 0, a finite window >= 0 frames, a prior >= 0, "
        "a finite target and a finite optimism >= 0 dB, got " +
        std::to_string(opt.maxRounds) + ", " + std::to_string(opt.windowFrames) + ", " +
        std::to_string(opt.prior) + ", " + std::to_string(targetPsnrDb) + ", " +
        std::to_string(opt.optimismDb));
  auto checkSegment = [&](const std::pair<int, int>& s, const std::vector<double>& v) -> Status {
    if (s.first < 0 || s.second >= frames || s.second - s.first < 1 ||
        v.size() != static_cast<std::size_t>(s.second - s.first - 1))
      return makeError("verified plan: a measured segment (" + std::to_string(s.first) + ", " +
                       std::to_string(s.second) + ") is outside the path or has " +
                       std::to_string(v.size()) + " frames, expected " +
                       std::to_string(std::max(s.second - s.first - 1, 0)));
    return {};
  };
  for (const auto& [s, v] : measured) HW_TRY(checkSegment(s, v));
  auto guaranteedPlan = [&](double* good) {
    return fewestKeyframesForMedian(
        frames, search.minGap, search.maxGap,
        [&](int k0, int k1) {
          const auto it = measured.find({k0, k1});
          return it == measured.end() ? 0.0 : measuredGood(it->second, targetPsnrDb);
        },
        good);
  };
  VerifiedPlan out;
  std::vector<int> plan;
  std::vector<int> sampleFrames, groups;
  std::vector<double> residuals;
  for (int round = 0;; ++round) {
    // Residuals of every measured frame, one group per segment; frames
    // identical to their reference are skipped, as the calibration skips
    // them (no error to fit).
    sampleFrames.clear(), groups.clear(), residuals.clear();
    int group = 0;
    for (const auto& [s, v] : measured) {
      for (std::size_t i = 0; i < v.size(); ++i) {
        if (!std::isfinite(v[i]) || v[i] >= kProbePsnrCap) continue;
        const int f = s.first + 1 + static_cast<int>(i);
        sampleFrames.push_back(f);
        residuals.push_back(v[i] - predict(s.first, s.second, f));
        groups.push_back(group);
      }
      ++group;
    }
    PathOffsets offsets = smoothResidualsAlongPath(frames, sampleFrames, residuals,
                                                   opt.windowFrames, opt.prior, groups);
    PredictionError err = search.error;
    if (opt.empiricalError) {
      err.setResiduals(offsets.heldOutResidualsDb);
      if (err.residualsDb.empty()) err = search.error;
    }
    VerifyRound vr;
    vr.heldOutRmsDb = offsets.heldOutRmsDb;
    std::vector<int> safe = guaranteedPlan(nullptr);
    vr.guaranteedKeyframes = static_cast<int>(safe.size());
    // The search aims one keyframe below the guaranteed schedule (when there
    // is one): the plan of that many most likely to reach the target, not the
    // fewest the optimism allows, which is rarely real and costs rounds
    // (docs/results/2026-12-02/verified_plan: table_verify.py).
    const int aim = safe.empty() ? 0 : static_cast<int>(safe.size()) - 1;
    plan = fewestKeyframesForMedian(
        frames, search.minGap, search.maxGap,
        [&](int k0, int k1) {
          const auto it = measured.find({k0, k1});
          if (it != measured.end()) return measuredGood(it->second, targetPsnrDb);
          double n = 0;
          for (int f = k0 + 1; f < k1; ++f)
            n += err.probabilityAtLeast(
                predict(k0, k1, f) + pathOffsetAt(offsets.offsetDb, f) + opt.optimismDb,
                targetPsnrDb);
          return n;
        },
        nullptr, aim);
    if (plan.empty()) plan = densestSchedule(frames, search.minGap);  // unreachable: measured next
    std::vector<std::pair<int, int>> fresh;
    for (std::size_t i = 1; i < plan.size(); ++i)
      if (plan[i] - plan[i - 1] >= 2 && !measured.count({plan[i - 1], plan[i]}))
        fresh.emplace_back(plan[i - 1], plan[i]);
    vr.keyframes = static_cast<int>(plan.size());
    vr.unmeasured = static_cast<int>(fresh.size());
    out.offsetDb = opt.windowFrames > 0 ? offsets.offsetDb : std::vector<double>{};
    // Done when the plan is measured, or when it needs no fewer keyframes
    // than the guaranteed schedule: nothing fewer is predicted to reach the
    // target.
    out.converged = fresh.empty() || (!safe.empty() && plan.size() >= safe.size());
    if (out.converged || round >= opt.maxRounds) {
      out.rounds.push_back(vr);
      break;
    }
    HW_TRY(measure(fresh, measured));
    for (const auto& s : fresh) {
      const auto it = measured.find(s);
      if (it == measured.end())
        return makeError("verified plan: segment (" + std::to_string(s.first) + ", " +
                         std::to_string(s.second) + ") was to be measured but was not");
      HW_TRY(checkSegment(s, it->second));
      vr.framesMeasured += s.second - s.first - 1;
    }
    out.rounds.push_back(vr);
  }
  double good = 0;
  std::vector<int> safe = guaranteedPlan(&good);
  if (!safe.empty()) {
    out.keyframes = std::move(safe);
    out.guaranteed = true;
    out.good = static_cast<int>(std::lround(good));
  } else {
    out.keyframes = std::move(plan);
  }
  return out;
}

Result<PlanResult> planAdaptiveSchedule(GeometryRenderer& renderer,
                                        const std::function<Camera(int)>& cameraOf, int frames,
                                        const PlannerOptions& opt) {
  if (opt.probeSize < 4 || opt.probeError.supersample < 1 || opt.probeError.supersample > 8 ||
      opt.probeError.blurRadius < 0 || opt.probeError.shiftTolerance < 0 ||
      !(opt.probeError.holeMse >= 0))
    return makeError("keyframe planner: expected probe size >= 4, supersample 1..8, blur radius >= 0"
                     ", shift tolerance >= 0 and hole MSE >= 0, got " +
                     std::to_string(opt.probeSize) + ", " +
                     std::to_string(opt.probeError.supersample) + ", " +
                     std::to_string(opt.probeError.blurRadius) + ", " +
                     std::to_string(opt.probeError.shiftTolerance) + ", " +
                     std::to_string(opt.probeError.holeMse));
  Stopwatch sw;
  KeyframeProbe probe(renderer, cameraOf, opt.probeSize, opt.probeError);
  auto r = planAdaptiveSchedule(probe, frames, opt);
  if (r) r->planMs = sw.ms();
  return r;
}

Result<PlanResult> planAdaptiveSchedule(KeyframeProbe& probe, int frames,
                                        const PlannerOptions& opt) {
  if (opt.minGap < 1 || opt.maxGap < opt.minGap)
    return makeError("keyframe planner: gaps must satisfy 1 <= min-gap <= max-gap, got min " +
                     std::to_string(opt.minGap) + ", max " + std::to_string(opt.maxGap));
  if (!std::isfinite(opt.targetPsnrDb))
    return makeError("keyframe planner: target PSNR must be finite");
  if (frames < 1) return makeError("keyframe planner: no frames to plan");
  if (!(std::isfinite(opt.error.sigmaDb) && opt.error.sigmaDb >= 0))
    return makeError("keyframe planner: expected an uncertainty >= 0 dB, got " +
                     std::to_string(opt.error.sigmaDb));
  if (!opt.useDefaultFit && !opt.fit.finite())
    return makeError("keyframe planner: the predictor's fit has a non-finite coefficient");
  for (double v : opt.frameOffsetDb)
    if (!std::isfinite(v)) return makeError("keyframe planner: a path offset of the prediction is not finite");
  if (opt.candidateStride < 1 || opt.framesPerSegment < 0)
    return makeError("keyframe planner: candidate stride must be >= 1 and frames per segment >= 0");
  Stopwatch sw;
  const double renderBefore = probe.renderMs();
  const int probesBefore = probe.probesRendered();
  PlanResult r;
  r.fit = opt.useDefaultFit ? defaultFit(opt.predictor) : opt.fit;
  Status failure;
  const FramePredictor predict = withPathOffsets(
      [&](int k0, int k1, int i) {
        if (!failure.ok()) return -std::numeric_limits<double>::infinity();
        auto f = predictorFeatures(probe, opt.predictor, k0, k1, i);
        if (!f) {
          failure = f.error();
          return -std::numeric_limits<double>::infinity();
        }
        return predictPsnr(r.fit, *f, opt.predictor);
      },
      opt.frameOffsetDb);
  PlanSearch search;
  search.minGap = opt.minGap;
  search.maxGap = opt.maxGap;
  search.criterion = opt.criterion;
  search.candidateStride = opt.candidateStride;
  search.framesPerSegment = opt.framesPerSegment;
  search.error = opt.error;
  r.keyframes = planKeyframes(frames, opt.targetPsnrDb, search, predict, &r.evaluations);
  if (!failure.ok()) return failure.error();
  r.planMs = sw.ms();
  r.probeRenderMs = probe.renderMs() - renderBefore;
  r.probes = probe.probesRendered() - probesBefore;
  return r;
}

}  // namespace hw::keyframe
