#include "session/planner_search.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "core/check.h"

namespace hw::session {

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

std::vector<int> densestSchedule(int frames, int minGap) {
  std::vector<int> keys;
  for (int k = 0; k < frames - 1; k += minGap) keys.push_back(k);
  keys.push_back(frames - 1);
  return keys;
}

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

}  // namespace hw::session
