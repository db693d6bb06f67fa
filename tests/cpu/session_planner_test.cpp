// The error-driven keyframe planner's schedule logic with fake predictors:
// gaps respected, ends are keyframes, harder stretches get denser keyframes,
// a stricter target never gives fewer keyframes; and the fit/correlation
// helpers the schedule study uses.
#include "session/keyframe_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <vector>

namespace hw::session {
namespace {

// Nested by construction: a frame's predicted PSNR falls with its distance to
// the nearer keyframe, scaled by a per-frame difficulty ≥ 0. A sub-segment
// only brings keyframes closer, so it is never predicted worse.
FramePredictor difficultyPredictor(const std::vector<double>& difficulty) {
  return [difficulty](int k0, int k1, int i) {
    return 50.0 - difficulty[static_cast<std::size_t>(i)] * std::min(i - k0, k1 - i);
  };
}

void expectValidSchedule(const std::vector<int>& ks, int frames, int minGap, int maxGap) {
  ASSERT_FALSE(ks.empty());
  EXPECT_EQ(ks.front(), 0);
  EXPECT_EQ(ks.back(), frames - 1);
  for (std::size_t j = 1; j < ks.size(); ++j) {
    const int gap = ks[j] - ks[j - 1];
    EXPECT_LE(gap, maxGap) << "between " << ks[j - 1] << " and " << ks[j];
    if (j + 1 < ks.size()) {
      EXPECT_GE(gap, minGap) << "between " << ks[j - 1] << " and " << ks[j];
    }
    EXPECT_GE(gap, 1);
  }
}

TEST(KeyframePlanner, AnAlwaysGoodPredictorGivesMaximumGaps) {
  const auto ks = planKeyframes(101, 30, 2, 25, [](int, int, int) { return 60.0; });
  EXPECT_EQ(ks, (std::vector<int>{0, 25, 50, 75, 100}));
}

TEST(KeyframePlanner, AnAlwaysBadPredictorGivesMinimumGaps) {
  const auto ks = planKeyframes(11, 30, 3, 25, [](int, int, int) { return 10.0; });
  EXPECT_EQ(ks, (std::vector<int>{0, 3, 6, 9, 10}));  // the last gap may be shorter
}

TEST(KeyframePlanner, NanPredictionFailsLikeALowOne) {
  const auto ks = planKeyframes(9, 30, 2, 8, [](int, int, int) { return std::nan(""); });
  EXPECT_EQ(ks, (std::vector<int>{0, 2, 4, 6, 8}));
}

TEST(KeyframePlanner, SingleAndTwoFramePaths) {
  EXPECT_EQ(planKeyframes(1, 30, 1, 5, [](int, int, int) { return 0.0; }), std::vector<int>{0});
  EXPECT_EQ(planKeyframes(2, 30, 3, 5, [](int, int, int) { return 0.0; }),
            (std::vector<int>{0, 1}));
}

TEST(KeyframePlanner, EveryPlannedFrameMeetsTheTargetWhenTheMinimumGapAllows) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(0.2, 3.0);
  std::vector<double> diff(200);
  for (auto& v : diff) v = d(rng);
  const auto pred = difficultyPredictor(diff);
  long evals = 0;
  const auto ks = planKeyframes(200, 44.0, 1, 40, pred, &evals);
  expectValidSchedule(ks, 200, 1, 40);
  EXPECT_GT(evals, 0);
  for (std::size_t j = 1; j < ks.size(); ++j)
    for (int i = ks[j - 1] + 1; i < ks[j]; ++i) EXPECT_GE(pred(ks[j - 1], ks[j], i), 44.0) << i;
}

TEST(KeyframePlanner, HardStretchesGetDenserKeyframes) {
  // Frames 0..99 easy, 100..199 four times as hard.
  std::vector<double> diff(200, 0.5);
  for (int i = 100; i < 200; ++i) diff[static_cast<std::size_t>(i)] = 2.0;
  const auto ks = planKeyframes(200, 40.0, 2, 60, difficultyPredictor(diff));
  expectValidSchedule(ks, 200, 2, 60);
  int easy = 0, hard = 0;
  for (int k : ks) (k < 100 ? easy : hard) += 1;
  EXPECT_GE(hard, 3 * easy) << "easy " << easy << " hard " << hard;
}

TEST(KeyframePlanner, GapsAndEndsHoldForRandomPredictorsAndSettings) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int frames = std::uniform_int_distribution<int>(1, 150)(rng);
    const int minGap = std::uniform_int_distribution<int>(1, 8)(rng);
    const int maxGap = minGap + std::uniform_int_distribution<int>(0, 30)(rng);
    std::vector<double> noise(static_cast<std::size_t>(frames) * 7 + 13);
    for (auto& v : noise) v = std::uniform_real_distribution<double>(10, 50)(rng);
    // Not nested at all: arbitrary values per (k0, k1, i).
    auto pred = [&](int k0, int k1, int i) {
      return noise[static_cast<std::size_t>(k0 * 3 + k1 * 5 + i) % noise.size()];
    };
    const auto ks = planKeyframes(frames, 30.0, minGap, maxGap, pred);
    expectValidSchedule(ks, frames, minGap, maxGap);
    EXPECT_TRUE(std::is_sorted(ks.begin(), ks.end()));
  }
}

TEST(KeyframePlanner, AStricterTargetNeverGivesFewerKeyframes) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> diff(300);
    for (auto& v : diff) v = std::uniform_real_distribution<double>(0.0, 4.0)(rng);
    const auto pred = difficultyPredictor(diff);
    std::size_t previous = 0;
    for (double target = 10; target <= 50; target += 0.5) {
      const auto ks = planKeyframes(300, target, 2, 30, pred);
      EXPECT_GE(ks.size(), previous) << "target " << target << " trial " << trial;
      previous = ks.size();
    }
    EXPECT_EQ(planKeyframes(300, 50.5, 2, 30, pred).size(),
              planKeyframes(300, 99, 2, 30, pred).size());
  }
}

TEST(KeyframePlanner, MedianCriterionKeepsHalfTheFramesAboveTheTargetWithFewerKeyframes) {
  std::mt19937 rng(5);
  std::vector<double> diff(240);
  for (auto& v : diff) v = std::uniform_real_distribution<double>(0.2, 3.0)(rng);
  const auto pred = difficultyPredictor(diff);
  for (double target : {30.0, 38.0, 44.0}) {
    const auto med = planKeyframes(240, target, 2, 40, pred, nullptr, PlanCriterion::SegmentMedian);
    const auto worst = planKeyframes(240, target, 2, 40, pred, nullptr, PlanCriterion::WorstFrame);
    expectValidSchedule(med, 240, 2, 40);
    EXPECT_LE(med.size(), worst.size()) << target;
    int good = 0, all = 0;
    for (std::size_t j = 1; j < med.size(); ++j)
      for (int i = med[j - 1] + 1; i < med[j]; ++i, ++all)
        good += pred(med[j - 1], med[j], i) >= target;
    EXPECT_GE(2 * good, all) << target;
  }
  PlanCriterion c;
  for (const char* n : {"worst", "mean", "median"}) {
    ASSERT_TRUE(parsePlanCriterion(n, &c));
    EXPECT_STREQ(planCriterionName(c), n);
  }
  EXPECT_FALSE(parsePlanCriterion("p5", &c));
}

TEST(KeyframePlanner, CheaperSearchKeepsGapsAndCallsThePredictorLess) {
  std::mt19937 rng(9);
  std::vector<double> diff(300);
  for (auto& v : diff) v = std::uniform_real_distribution<double>(0.2, 3.0)(rng);
  const auto pred = difficultyPredictor(diff);
  long full = 0, cheap = 0;
  const auto a = planKeyframes(300, 40.0, 2, 30, pred, &full);
  PlanSearch s;
  s.minGap = 2;
  s.maxGap = 30;
  s.candidateStride = 3;
  s.framesPerSegment = 3;
  const auto b = planKeyframes(300, 40.0, s, pred, &cheap);
  expectValidSchedule(b, 300, 2, 30);
  EXPECT_LT(cheap * 3, full);
  // Within a factor of two of the full search's count on this predictor.
  EXPECT_LE(b.size(), 2 * a.size());
  EXPECT_GE(2 * b.size(), a.size());
  // Candidates step by 3 from k + minGap (or land on the last frame / k + maxGap).
  for (std::size_t j = 1; j + 1 < b.size(); ++j) {
    const int gap = b[j] - b[j - 1];
    EXPECT_TRUE((gap - 2) % 3 == 0 || gap == 30) << gap;
  }
  // An always-good predictor still reaches the maximum gap.
  s.candidateStride = 4;  // 2, 6, ..., 26, then 30
  EXPECT_EQ(planKeyframes(61, 30, s, [](int, int, int) { return 60.0; }),
            (std::vector<int>{0, 30, 60}));
}

TEST(KeyframePlannerFit, TwoRegressorFitRecoversBothSlopes) {
  std::vector<FrameFeatures> f;
  std::vector<double> y;
  for (int i = 0; i < 30; ++i) {
    FrameFeatures g;
    g.holeFraction = 0.001 * (1 + i % 7);
    g.relDistance = 0.01 * (1 + (i * 5) % 11);
    f.push_back(g);
    y.push_back(18.0 - 2.5 * std::log10(g.holeFraction + 1e-5) -
                4.0 * std::log10(g.relDistance + 1e-3));
  }
  const PsnrFit fit = fitPredictor(f, y, Predictor::HolesDistance);
  EXPECT_NEAR(fit.intercept, 18.0, 1e-9);
  EXPECT_NEAR(fit.slope, -2.5, 1e-9);
  EXPECT_NEAR(fit.slope2, -4.0, 1e-9);
  EXPECT_NEAR(predictPsnr(fit, f[3], Predictor::HolesDistance), y[3], 1e-9);
  const PsnrFit one = fitPredictor(f, y, Predictor::Holes);  // one regressor: slope2 stays 0
  EXPECT_EQ(one.slope2, 0.0);
  EXPECT_LT(one.slope, 0.0);
}

TEST(KeyframePlannerFit, RegressorsAreFiniteAtZeroAndGrowWithTheFeature) {
  FrameFeatures zero, more;
  more.relDistance = 0.2;
  more.angleDeg = 5;
  more.holeFraction = 0.01;
  more.stretch = 0.3;
  more.disagreementMse = 100;
  for (Predictor p : kAllPredictors) {
    EXPECT_TRUE(std::isfinite(predictorValue(zero, p))) << predictorName(p);
    EXPECT_GT(predictorValue(more, p), predictorValue(zero, p)) << predictorName(p);
    Predictor back;
    ASSERT_TRUE(parsePredictor(predictorName(p), &back));
    EXPECT_EQ(back, p);
    EXPECT_LT(defaultFit(p).slope, 0) << "worse feature must predict lower PSNR";
  }
  Predictor none;
  EXPECT_FALSE(parsePredictor("psnr", &none));
}

// The fewest keyframes over every schedule of a short path (0 and frames−1
// keyframes; gaps minGap..maxGap, only the last may be shorter) whose
// in-between frames' summed count(k0, k1, f) — per segment, then over
// segments, the DP's order, so exact ties agree — exceeds half of them; 0
// when no schedule does.
int fewestByBruteForce(int frames, int minGap, int maxGap,
                       const std::function<double(int, int, int)>& count) {
  int best = 0;
  for (unsigned mask = 0; mask < (1u << (frames - 2)); ++mask) {
    std::vector<int> keys{0};
    for (int i = 1; i < frames - 1; ++i)
      if (mask & (1u << (i - 1))) keys.push_back(i);
    keys.push_back(frames - 1);
    bool ok = true;
    double good = 0;
    for (std::size_t j = 1; j < keys.size() && ok; ++j) {
      const int gap = keys[j] - keys[j - 1];
      if (gap > maxGap || (gap < minGap && j + 1 < keys.size())) ok = false;
      double segment = 0;
      for (int f = keys[j - 1] + 1; ok && f < keys[j]; ++f) segment += count(keys[j - 1], keys[j], f);
      good += segment;
    }
    const int inBetween = frames - static_cast<int>(keys.size());
    if (ok && inBetween >= 1 && 2 * good > inBetween && (best == 0 || static_cast<int>(keys.size()) < best))
      best = static_cast<int>(keys.size());
  }
  return best;
}

// Walk-median: the fewest keyframes (gaps from minGap, only the last shorter)
// with more than half of the frames predicted >= target, checked against every
// schedule of a short path; planKeyframes' walk-median is that schedule, and
// when no schedule reaches the target it falls back to the densest one.
TEST(KeyframePlanner, WalkMedianIsTheFewestKeyframesOverEverySchedule) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(20.0, 40.0);
  for (int trial = 0; trial < 30; ++trial) {
    const int frames = 7 + trial % 7, minGap = 1 + trial % 3, maxGap = minGap + 1 + trial % 4;
    std::vector<double> table(static_cast<std::size_t>(frames * frames * frames));
    for (double& v : table) v = u(rng);
    const FramePredictor predict = [&](int k0, int k1, int f) {
      return table[static_cast<std::size_t>((k0 * frames + k1) * frames + f)];
    };
    for (double target : {25.0, 30.0, 35.0}) {
      const int best = fewestByBruteForce(frames, minGap, maxGap, [&](int k0, int k1, int f) {
        return predict(k0, k1, f) >= target ? 1.0 : 0.0;
      });
      long evals = 0;
      const std::vector<int> dp = fewestKeyframesForMedian(frames, target, minGap, maxGap, predict, &evals);
      ASSERT_EQ(static_cast<int>(dp.size()), best) << frames << " " << minGap << " " << maxGap << " " << target;
      EXPECT_GT(evals, 0);
      PlanSearch search;
      search.minGap = minGap;
      search.maxGap = maxGap;
      search.criterion = PlanCriterion::WalkMedian;
      const std::vector<int> planned = planKeyframes(frames, target, search, predict);
      if (best > 0) {
        EXPECT_EQ(planned, dp);
      } else {  // unreachable: every minGap frames
        std::vector<int> dense;
        for (int k = 0; k < frames - 1; k += minGap) dense.push_back(k);
        dense.push_back(frames - 1);
        EXPECT_EQ(planned, dense);
      }
      expectValidSchedule(planned, frames, minGap, maxGap);
    }
  }
  PlanCriterion c{};
  ASSERT_TRUE(parsePlanCriterion("walk-median", &c));
  EXPECT_EQ(c, PlanCriterion::WalkMedian);
  EXPECT_STREQ(planCriterionName(c), "walk-median");
}

// With an uncertainty each frame counts as P(measured >= target) under a
// normal error; the DP is still the fewest keyframes, now of expected counts,
// checked against every schedule of a short path.
TEST(KeyframePlanner, WalkMedianWithUncertaintyIsTheFewestOverEveryScheduleOfExpectedCounts) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(20.0, 40.0);
  for (int trial = 0; trial < 24; ++trial) {
    const int frames = 7 + trial % 6, minGap = 1 + trial % 2, maxGap = minGap + 2 + trial % 3;
    const double sigma = 0.5 + (trial % 4);
    // Normal errors on even trials, an empirical (skewed) residual set on odd.
    PredictionError err;
    if (trial % 2 == 0) {
      err.sigmaDb = sigma;
    } else {
      err.setResiduals({-3 * sigma, -sigma, -0.5, 0.0, 0.2, 0.4, sigma, 1.5 * sigma});
    }
    std::vector<double> table(static_cast<std::size_t>(frames * frames * frames));
    for (double& v : table) v = u(rng);
    const FramePredictor predict = [&](int k0, int k1, int f) {
      return table[static_cast<std::size_t>((k0 * frames + k1) * frames + f)];
    };
    for (double target : {26.0, 30.0, 34.0}) {
      const int best = fewestByBruteForce(frames, minGap, maxGap, [&](int k0, int k1, int f) {
        return err.probabilityAtLeast(predict(k0, k1, f), target);
      });
      int good = -1;
      const std::vector<int> dp =
          fewestKeyframesForMedian(frames, target, minGap, maxGap, predict, nullptr, &good, &err);
      ASSERT_EQ(static_cast<int>(dp.size()), best)
          << frames << " " << minGap << " " << maxGap << " " << target << " sigma " << sigma;
      if (best > 0) {
        expectValidSchedule(dp, frames, minGap, maxGap);
        EXPECT_GE(2 * good + 1, frames - best) << "expected count rounded down";
      }
    }
  }
}

// A schedule whose frames are all predicted exactly at the target passes the
// plain count (>= target), though each reaches it only half the time under
// any symmetric error; with an uncertainty the planner takes the denser
// schedule whose frames clear the target by a margin.
TEST(KeyframePlanner, AnUncertaintyRefusesAMedianPredictedJustAtTheTarget) {
  const double target = 30;
  const FramePredictor predict = [&](int k0, int k1, int) {
    return k1 - k0 <= 5 ? target + 3.0 : k1 - k0 <= 10 ? target : target - 10.0;
  };
  const std::vector<int> plain = fewestKeyframesForMedian(101, target, 2, 20, predict);
  PredictionError one;
  one.sigmaDb = 1.0;
  const std::vector<int> soft = fewestKeyframesForMedian(101, target, 2, 20, predict, nullptr, nullptr, &one);
  ASSERT_FALSE(plain.empty());
  ASSERT_FALSE(soft.empty());
  EXPECT_GT(soft.size(), plain.size());
  // Under a 1 dB error the plain plan's frames reach the target less than
  // half the time in expectation; the soft plan's more than half.
  auto expectedShare = [&](const std::vector<int>& keys) {
    double n = 0;
    int all = 0;
    for (std::size_t j = 1; j < keys.size(); ++j)
      for (int f = keys[j - 1] + 1; f < keys[j]; ++f)
        ++all, n += one.probabilityAtLeast(predict(keys[j - 1], keys[j], f), target);
    return n / all;
  };
  EXPECT_LE(expectedShare(plain), 0.5);
  EXPECT_GT(expectedShare(soft), 0.5);
  // A tiny uncertainty where every frame clears the target by 3 dB changes nothing.
  PredictionError tiny;
  tiny.sigmaDb = 0.1;
  const FramePredictor clear = [&](int k0, int k1, int) { return k1 - k0 <= 10 ? target + 3.0 : target - 10.0; };
  EXPECT_EQ(fewestKeyframesForMedian(101, target, 2, 20, clear),
            fewestKeyframesForMedian(101, target, 2, 20, clear, nullptr, nullptr, &tiny));
}

TEST(KeyframePlanner, ProbabilityOfReachingTheTarget) {
  PredictionError none, normal, emp;
  normal.sigmaDb = 2.0;
  EXPECT_TRUE(none.none());
  EXPECT_EQ(none.probabilityAtLeast(30.0, 30.0), 1.0);
  EXPECT_EQ(none.probabilityAtLeast(29.99, 30.0), 0.0);
  EXPECT_NEAR(normal.probabilityAtLeast(30.0, 30.0), 0.5, 1e-12);
  EXPECT_NEAR(normal.probabilityAtLeast(32.0, 30.0), 0.841344746, 1e-8);  // Φ(1)
  EXPECT_NEAR(normal.probabilityAtLeast(28.0, 30.0), 0.158655254, 1e-8);  // Φ(−1)
  EXPECT_EQ(normal.probabilityAtLeast(std::nan(""), 30.0), 0.0);
  EXPECT_EQ(none.probabilityAtLeast(std::nan(""), 30.0), 0.0);
  EXPECT_EQ(normal.probabilityAtLeast(std::numeric_limits<double>::infinity(), 30.0), 1.0);
  // Empirical: residuals {−4, −1, 0, 0.5, 1} (NaN dropped, sorted); a frame
  // predicted 0.5 dB above the target reaches it when e ≥ −0.5: 3 of 5.
  emp.setResiduals({1.0, -1.0, std::nan(""), 0.5, -4.0, 0.0});
  EXPECT_FALSE(emp.none());
  ASSERT_EQ(emp.residualsDb.size(), 5u);
  EXPECT_EQ(emp.residualsDb.front(), -4.0);
  EXPECT_DOUBLE_EQ(emp.probabilityAtLeast(30.5, 30.0), 0.6);
  EXPECT_DOUBLE_EQ(emp.probabilityAtLeast(30.0, 30.0), 0.6);   // e ≥ 0: 0, 0.5, 1
  EXPECT_DOUBLE_EQ(emp.probabilityAtLeast(31.0, 30.0), 0.8);   // e ≥ −1
  EXPECT_DOUBLE_EQ(emp.probabilityAtLeast(25.0, 30.0), 0.0);   // e ≥ 5: none
  EXPECT_DOUBLE_EQ(emp.probabilityAtLeast(40.0, 30.0), 1.0);
  EXPECT_EQ(emp.probabilityAtLeast(std::nan(""), 30.0), 0.0);
}

// probe-psnr+features: six regressors by least squares. Exact data give the
// coefficients back; data that do not determine them give NaN; a fit whose
// extra slopes do not match the predictor predicts NaN.
TEST(KeyframePlannerFit, SixRegressorFitRecoversEverySlope) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const PsnrFit truth(35.0, -6.0, -1.5, {-0.7, -0.2, -0.05, -0.3});
  std::vector<FrameFeatures> f;
  std::vector<double> y;
  for (int i = 0; i < 200; ++i) {
    FrameFeatures x;
    x.probeMse = std::pow(10.0, 3 * u(rng));
    x.relDistance = std::pow(10.0, -2 + 2 * u(rng));
    x.holeFraction = 0.2 * u(rng);
    x.stretch = u(rng);
    x.disagreementMse = 100 * u(rng);
    x.angleDeg = 20 * u(rng);
    f.push_back(x);
    y.push_back(predictPsnr(truth, x, Predictor::ProbePsnrFeatures));
  }
  ASSERT_TRUE(std::isfinite(y[0]));
  EXPECT_EQ(predictorRegressors(Predictor::ProbePsnrFeatures), 6);
  EXPECT_EQ(predictorValuesMore(f[0], Predictor::ProbePsnrFeatures).size(), 4u);
  EXPECT_TRUE(predictorValuesMore(f[0], Predictor::ProbePsnrDistance).empty());
  const PsnrFit fit = fitPredictor(f, y, Predictor::ProbePsnrFeatures);
  ASSERT_TRUE(fit.finite());
  EXPECT_NEAR(fit.intercept, 35.0, 1e-6);
  EXPECT_NEAR(fit.slope, -6.0, 1e-6);
  EXPECT_NEAR(fit.slope2, -1.5, 1e-6);
  ASSERT_EQ(fit.more.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(fit.more[i], truth.more[i], 1e-6) << i;
  // One feature constant (as angle is on a path that never turns): slope 0,
  // its level in the intercept, the others still exact.
  std::vector<FrameFeatures> flat = f;
  std::vector<double> yFlat;
  for (auto& x : flat) {
    x.stretch = 0.5;
    yFlat.push_back(predictPsnr(truth, x, Predictor::ProbePsnrFeatures));
  }
  const PsnrFit flatFit = fitPredictor(flat, yFlat, Predictor::ProbePsnrFeatures);
  ASSERT_TRUE(flatFit.finite());
  EXPECT_EQ(flatFit.more[1], 0.0);
  EXPECT_NEAR(flatFit.slope, -6.0, 1e-6);
  EXPECT_NEAR(flatFit.more[0], -0.7, 1e-6);
  EXPECT_NEAR(predictPsnr(flatFit, flat[3], Predictor::ProbePsnrFeatures), yFlat[3], 1e-6);
  // Two features carrying the same regressor: not determined.
  std::vector<FrameFeatures> twin = f;
  for (auto& x : twin) x.holeFraction = x.stretch + 1e-3 - 1e-5;
  EXPECT_FALSE(fitPredictor(twin, y, Predictor::ProbePsnrFeatures).finite());
  // Fewer frames than coefficients.
  EXPECT_FALSE(fitPredictor({f.begin(), f.begin() + 5}, {y.begin(), y.begin() + 5},
                            Predictor::ProbePsnrFeatures)
                   .finite());
  // A two-regressor fit used for the six-regressor predictor: no prediction.
  EXPECT_TRUE(std::isnan(predictPsnr(PsnrFit(35.0, -6.0, -1.5), f[0], Predictor::ProbePsnrFeatures)));
  EXPECT_TRUE(defaultFit(Predictor::ProbePsnrFeatures).finite());
  Predictor p = Predictor::Holes;
  ASSERT_TRUE(parsePredictor("probe-psnr+features", &p));
  EXPECT_EQ(p, Predictor::ProbePsnrFeatures);
  EXPECT_TRUE(isProbePredictor(p));
}

// The calibration's residuals smoothed along the path: a constant residual is
// the offset everywhere (prior 0), a step keeps both levels away from the
// step, the prior shrinks toward 0, a sample's held-out residual is computed
// without the samples of its group (default: its frame), and non-finite
// residuals are skipped.
TEST(KeyframePlannerPathOffsets, SmoothedResidualsAlongThePath) {
  const int frames = 100;
  std::vector<int> at;
  std::vector<double> constant, step;
  for (int f = 1; f < frames - 1; ++f) {
    at.push_back(f);
    constant.push_back(-1.5);
    step.push_back(f < 50 ? 2.0 : -1.0);
  }
  PathOffsets c = smoothResidualsAlongPath(frames, at, constant, 3.0, 0.0);
  ASSERT_EQ(c.offsetDb.size(), 100u);
  ASSERT_EQ(c.heldOutResidualsDb.size(), constant.size());
  for (double v : c.offsetDb) EXPECT_NEAR(v, -1.5, 1e-12);
  for (double v : c.heldOutResidualsDb) EXPECT_NEAR(v, 0.0, 1e-12);
  EXPECT_NEAR(c.heldOutRmsDb, 0.0, 1e-12);
  // The prior: Σw / (Σw + 2) of the residual, less where samples are sparse
  // (the ends) than in the middle.
  PathOffsets shrunk = smoothResidualsAlongPath(frames, at, constant, 3.0, 2.0);
  EXPECT_LT(shrunk.offsetDb[50], -1.0);
  EXPECT_GT(shrunk.offsetDb[50], -1.5);
  EXPECT_GT(shrunk.offsetDb[0], shrunk.offsetDb[50]);
  // A step: more than 5 widths away only one level counts; monotone between.
  PathOffsets st = smoothResidualsAlongPath(frames, at, step, 3.0, 0.0);
  EXPECT_NEAR(st.offsetDb[20], 2.0, 1e-12);
  EXPECT_NEAR(st.offsetDb[80], -1.0, 1e-12);
  for (int f = 1; f < frames; ++f) EXPECT_LE(st.offsetDb[f], st.offsetDb[f - 1] + 1e-12) << f;
  EXPECT_GT(st.offsetDb[49], -1.0);
  EXPECT_LT(st.offsetDb[49], 2.0);
  // Held out: an outlier at frame 30 among zeros keeps its whole residual
  // (the others say 0 there), though its own offset moved toward it.
  std::vector<double> outlier(at.size(), 0.0);
  outlier[29] = 10.0;  // at[29] == 30
  PathOffsets o = smoothResidualsAlongPath(frames, at, outlier, 3.0, 2.0);
  EXPECT_GT(o.offsetDb[30], 0.5);
  EXPECT_DOUBLE_EQ(o.heldOutResidualsDb[29], 10.0);
  EXPECT_LT(o.heldOutResidualsDb[30], 0.0);  // its neighbour: the outlier pulled its offset up
  // Held out by group: a stretch 28..32 off by +10 among zeros. One frame
  // held out still has its group's other frames pulling its offset up; the
  // whole group held out, the others say 0 and the residual stays whole.
  std::vector<double> stretch(at.size(), 0.0);
  std::vector<int> group(at.size());
  for (std::size_t i = 0; i < at.size(); ++i) {
    group[i] = at[i] / 5;  // frames 25..29, 30..34, ...: 28..32 spans two groups
    if (at[i] >= 28 && at[i] <= 32) stretch[i] = 10.0;
  }
  for (auto& g : group) g = (g == 5 || g == 6) ? 100 : g;  // 25..34 one group
  PathOffsets perFrame = smoothResidualsAlongPath(frames, at, stretch, 3.0, 2.0);
  PathOffsets perGroup = smoothResidualsAlongPath(frames, at, stretch, 3.0, 2.0, group);
  EXPECT_EQ(perFrame.offsetDb, perGroup.offsetDb);  // groups only change what is held out
  EXPECT_LT(perFrame.heldOutResidualsDb[29], 7.0);
  EXPECT_DOUBLE_EQ(perGroup.heldOutResidualsDb[29], 10.0);
  // Width 0: no offsets; the held-out residuals are the residuals.
  PathOffsets none = smoothResidualsAlongPath(frames, at, step, 0.0);
  for (double v : none.offsetDb) EXPECT_EQ(v, 0.0);
  EXPECT_EQ(none.heldOutResidualsDb, step);
  // A NaN residual is skipped; frames beyond 5 widths of every sample get 0.
  std::vector<int> two = {10, 11};
  PathOffsets n = smoothResidualsAlongPath(frames, two, {std::nan(""), 4.0}, 2.0, 0.0);
  EXPECT_NEAR(n.offsetDb[10], 4.0, 1e-12);
  EXPECT_EQ(n.offsetDb[90], 0.0);
  EXPECT_TRUE(std::isnan(n.heldOutResidualsDb[0]));
  EXPECT_EQ(n.heldOutResidualsDb[1], 4.0);  // nothing else near: offset 0
  EXPECT_EQ(n.heldOutRmsDb, 4.0);            // the NaN left out
  // Predictions with offsets: frame i gains offsetDb[i]; frames past the end none.
  const FramePredictor p = withPathOffsets([](int, int, int f) { return 30.0 + f; }, {1.0, -2.0});
  EXPECT_EQ(p(0, 5, 0), 31.0);
  EXPECT_EQ(p(0, 5, 1), 29.0);
  EXPECT_EQ(p(0, 5, 3), 33.0);
}

// What the offsets are for: a predictor blind to a hard stretch of the path
// (measured 3 dB below it on frames 0..59) plans too few keyframes there and
// misses the median of the fixed schedule it was asked for; corrected by the
// smoothed residuals of a calibration walk every 10 frames, it reaches it.
TEST(KeyframePlannerPathOffsets, CalibrationOffsetsCorrectAPredictorBlindToAStretch) {
  const int frames = 120;
  std::vector<double> difficulty(frames);
  for (int i = 0; i < frames; ++i) difficulty[i] = 0.6 + 0.3 * std::sin(0.21 * i);
  const FramePredictor predicted = difficultyPredictor(difficulty);
  const auto measured = [&](int k0, int k1, int i) { return predicted(k0, k1, i) - (i < 60 ? 3.0 : 0.0); };
  const auto medianOf = [&](const std::vector<int>& ks) {
    std::vector<double> v;
    for (std::size_t j = 1; j < ks.size(); ++j)
      for (int f = ks[j - 1] + 1; f < ks[j]; ++f) v.push_back(measured(ks[j - 1], ks[j], f));
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  std::vector<int> fixed10;
  for (int k = 0; k < frames - 1; k += 10) fixed10.push_back(k);
  fixed10.push_back(frames - 1);
  const double target = medianOf(fixed10);
  std::vector<int> at;
  std::vector<double> residual;
  for (std::size_t j = 1; j < fixed10.size(); ++j)
    for (int f = fixed10[j - 1] + 1; f < fixed10[j]; ++f) {
      at.push_back(f);
      residual.push_back(measured(fixed10[j - 1], fixed10[j], f) - predicted(fixed10[j - 1], fixed10[j], f));
    }
  // Without the prior the offsets are the residuals' −3 dB (away from frame 60).
  const PathOffsets exact = smoothResidualsAlongPath(frames, at, residual, 3.0, 0.0);
  const PathOffsets shrunk = smoothResidualsAlongPath(frames, at, residual, 3.0);  // prior 2
  const std::vector<int> blind = fewestKeyframesForMedian(frames, target, 2, 20, predicted);
  const std::vector<int> corrected =
      fewestKeyframesForMedian(frames, target, 2, 20, withPathOffsets(predicted, exact.offsetDb));
  const std::vector<int> partly =
      fewestKeyframesForMedian(frames, target, 2, 20, withPathOffsets(predicted, shrunk.offsetDb));
  expectValidSchedule(blind, frames, 2, 20);
  expectValidSchedule(corrected, frames, 2, 20);
  EXPECT_LT(medianOf(blind), target - 0.5);
  EXPECT_GE(medianOf(corrected), target);
  EXPECT_GT(corrected.size(), blind.size());
  // The prior's shrinkage (9 samples per 10 frames: offsets about −2.3 dB)
  // leaves part of the miss: less than a quarter of the blind plan's.
  EXPECT_GT(medianOf(partly), target - 0.25 * (target - medianOf(blind)));
}

// ---- verified plans ------------------------------------------------------------

// A path whose measured PSNRs are the predictor's plus an error shared by each
// segment (±1.5 dB, fixed by (k0, k1)): what a probe predictor's segment-level
// errors look like.
struct SegmentErrorPath {
  static constexpr int kFrames = 120;
  std::vector<double> difficulty = std::vector<double>(kFrames);
  FramePredictor predicted;
  SegmentErrorPath() {
    for (int i = 0; i < kFrames; ++i) difficulty[i] = 0.6 + 0.3 * std::sin(0.21 * i);
    predicted = difficultyPredictor(difficulty);
  }
  static double segmentError(int k0, int k1) { return 1.5 * std::sin(12.9898 * k0 + 78.233 * k1); }
  double truth(int k0, int k1, int f) const { return predicted(k0, k1, f) + segmentError(k0, k1); }
  std::vector<double> segment(int k0, int k1) const {
    std::vector<double> v;
    for (int f = k0 + 1; f < k1; ++f) v.push_back(truth(k0, k1, f));
    return v;
  }
  std::vector<double> inBetween(const std::vector<int>& ks) const {
    std::vector<double> v;
    for (std::size_t j = 1; j < ks.size(); ++j)
      for (int f = ks[j - 1] + 1; f < ks[j]; ++f) v.push_back(truth(ks[j - 1], ks[j], f));
    return v;
  }
  double median(const std::vector<int>& ks) const {
    std::vector<double> v = inBetween(ks);
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  }
  static std::vector<int> fixed(int g) {
    std::vector<int> ks;
    for (int k = 0; k < kFrames - 1; k += g) ks.push_back(k);
    ks.push_back(kFrames - 1);
    return ks;
  }
  MeasuredSegments calibration() const {  // the fixed schedule every 10 frames
    MeasuredSegments m;
    for (int g : {10}) {
      const auto ks = fixed(g);
      for (std::size_t j = 1; j < ks.size(); ++j) m[{ks[j - 1], ks[j]}] = segment(ks[j - 1], ks[j]);
    }
    return m;
  }
};

TEST(KeyframePlannerVerified, MeasuresWhatThePlanPicksUntilItsMedianIsKnown) {
  const SegmentErrorPath path;
  const int frames = SegmentErrorPath::kFrames;
  const double target = path.median(SegmentErrorPath::fixed(10));
  PlanSearch search;
  search.minGap = 2;
  search.maxGap = 20;
  // The predictor alone (plain count) overrates the segments it picks: its
  // plan misses the median it was asked for.
  const std::vector<int> blind = fewestKeyframesForMedian(frames, target, 2, 20, path.predicted);
  EXPECT_LT(path.median(blind), target);
  // The best any schedule can do: the DP on the truth itself.
  const std::vector<int> best = fewestKeyframesForMedian(
      frames, target, 2, 20, [&](int k0, int k1, int f) { return path.truth(k0, k1, f); });
  MeasuredSegments measured = path.calibration();
  std::set<std::pair<int, int>> asked;
  int calls = 0;
  const SegmentMeasurer measure = [&](const std::vector<std::pair<int, int>>& segs,
                                      MeasuredSegments& out) {
    ++calls;
    EXPECT_FALSE(segs.empty());
    for (const auto& s : segs) {
      EXPECT_FALSE(out.count(s)) << "measured twice: " << s.first << ", " << s.second;
      EXPECT_TRUE(asked.insert(s).second);
      out[s] = path.segment(s.first, s.second);
    }
    return Status{};
  };
  VerifyOptions vo;
  vo.maxRounds = 60;
  auto r = planVerified(frames, target, search, path.predicted, measured, measure, vo);
  ASSERT_TRUE(r) << r.error().message;
  expectValidSchedule(r->keyframes, frames, 2, 20);
  EXPECT_TRUE(r->converged);
  EXPECT_TRUE(r->guaranteed);
  EXPECT_EQ(static_cast<int>(r->rounds.size()), calls + 1);
  // Its median is guaranteed by measured frames: `good` counts those reaching
  // the target (a segment not measured counts none), more than half of the
  // in-between frames; the truth has at least as many, and its median
  // reaches the target.
  int measuredGood = 0;
  for (std::size_t j = 1; j < r->keyframes.size(); ++j) {
    const auto it = measured.find({r->keyframes[j - 1], r->keyframes[j]});
    if (it != measured.end())
      measuredGood += static_cast<int>(std::count_if(it->second.begin(), it->second.end(),
                                                     [&](double x) { return x >= target; }));
  }
  EXPECT_EQ(r->good, measuredGood);
  const std::vector<double> v = path.inBetween(r->keyframes);
  EXPECT_GT(2 * measuredGood, static_cast<int>(v.size()));
  EXPECT_GE(std::count_if(v.begin(), v.end(), [&](double x) { return x >= target; }), measuredGood);
  EXPECT_GE(path.median(r->keyframes), target);
  // No schedule beats the truth's; the verified one comes within a keyframe of
  // it and below the fixed schedule's 13, after measuring fewer frames than
  // three walks of the path.
  EXPECT_GE(r->keyframes.size(), best.size());
  EXPECT_LE(r->keyframes.size(), best.size() + 1);
  EXPECT_LT(r->keyframes.size(), SegmentErrorPath::fixed(10).size());
  int framesMeasured = 0;
  for (const VerifyRound& vr : r->rounds) framesMeasured += vr.framesMeasured;
  EXPECT_LT(framesMeasured, 3 * frames);
  // It stopped on a plan of measured segments or on one no better than the
  // measured schedule.
  const VerifyRound& lastRound = r->rounds.back();
  EXPECT_TRUE(lastRound.unmeasured == 0 || lastRound.keyframes >= lastRound.guaranteedKeyframes);
  EXPECT_EQ(lastRound.framesMeasured, 0);
  EXPECT_EQ(lastRound.guaranteedKeyframes, static_cast<int>(r->keyframes.size()));
}

TEST(KeyframePlannerVerified, WithoutRoundsNothingIsMeasuredAndTheKnownSegmentsDecide) {
  const SegmentErrorPath path;
  const double target = path.median(SegmentErrorPath::fixed(10)) - 0.01;
  PlanSearch search;
  search.maxGap = 20;
  MeasuredSegments measured = path.calibration();
  const SegmentMeasurer never = [](const std::vector<std::pair<int, int>>&, MeasuredSegments&) {
    ADD_FAILURE() << "measured with 0 rounds";
    return Status{};
  };
  VerifyOptions vo;
  vo.maxRounds = 0;
  vo.windowFrames = 3;
  auto r =
      planVerified(SegmentErrorPath::kFrames, target, search, path.predicted, measured, never, vo);
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r->rounds.size(), 1u);
  EXPECT_EQ(r->rounds[0].framesMeasured, 0);
  // Fixed-10 is measured and reaches the target: the schedule is guaranteed,
  // with no more keyframes than it.
  EXPECT_TRUE(r->guaranteed);
  EXPECT_LE(r->keyframes.size(), SegmentErrorPath::fixed(10).size());
  EXPECT_GE(path.median(r->keyframes), target);
  EXPECT_EQ(r->offsetDb.size(), static_cast<std::size_t>(SegmentErrorPath::kFrames));
}

TEST(KeyframePlannerVerified, BadMeasurementsAreErrors) {
  const SegmentErrorPath path;
  PlanSearch search;
  search.maxGap = 20;
  VerifyOptions vo;
  vo.maxRounds = 3;
  const double target = path.median(SegmentErrorPath::fixed(10));
  {  // a measurer that returns too few frames
    MeasuredSegments m = path.calibration();
    auto r = planVerified(
        SegmentErrorPath::kFrames, target, search, path.predicted, m,
        [](const std::vector<std::pair<int, int>>& segs, MeasuredSegments& out) {
          for (const auto& s : segs) out[s] = {30.0};
          return Status{};
        },
        vo);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("expected"), std::string::npos) << r.error().message;
  }
  {  // one that forgets a segment
    MeasuredSegments m = path.calibration();
    auto r = planVerified(
        SegmentErrorPath::kFrames, target, search, path.predicted, m,
        [](const std::vector<std::pair<int, int>>&, MeasuredSegments&) { return Status{}; }, vo);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("was not"), std::string::npos) << r.error().message;
  }
  {  // one that fails: its error comes back
    MeasuredSegments m = path.calibration();
    auto r = planVerified(
        SegmentErrorPath::kFrames, target, search, path.predicted, m,
        [](const std::vector<std::pair<int, int>>&, MeasuredSegments&) -> Status {
          return makeError("walk failed: GL context lost");
        },
        vo);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("GL context lost"), std::string::npos);
  }
  {  // a known segment outside the path, a negative round count
    MeasuredSegments m{{{100, 130}, std::vector<double>(29, 30.0)}};
    const SegmentMeasurer none = [](const std::vector<std::pair<int, int>>&, MeasuredSegments&) {
      return Status{};
    };
    EXPECT_FALSE(
        planVerified(SegmentErrorPath::kFrames, target, search, path.predicted, m, none, vo));
    MeasuredSegments ok;
    VerifyOptions bad = vo;
    bad.maxRounds = -1;
    EXPECT_FALSE(
        planVerified(SegmentErrorPath::kFrames, target, search, path.predicted, ok, none, bad));
  }
}

}  // namespace
}  // namespace hw::session
