// AutoFrameBudget (walk --frame-budget-ms auto): nearest-rank quantile over a
// sliding window of in-between frames' work.
// HoleCostModel (walk --render-holes-budget): rectangles that fit a budget.
#include "session/frame_budget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hw::session {
namespace {

TEST(AutoFrameBudget, NoBudgetBeforeTheFirstSample) {
  AutoFrameBudget b(1, 0.9);
  EXPECT_EQ(b.budgetMs(), 0.0);
  EXPECT_EQ(b.samples(), 0);
}

TEST(AutoFrameBudget, NearestRankQuantile) {
  AutoFrameBudget b(10, 0.9);
  for (int i = 10; i >= 1; --i) b.add(i);  // 1..10 in any order
  EXPECT_EQ(b.samples(), 10);
  EXPECT_EQ(b.budgetMs(), 9.0);  // ceil(0.9 * 10) = 9th smallest
  AutoFrameBudget m(10, 0.5);
  for (int i = 1; i <= 10; ++i) m.add(i);
  EXPECT_EQ(m.budgetMs(), 5.0);
  AutoFrameBudget top(10, 1.0);
  for (int i = 1; i <= 10; ++i) top.add(i);
  EXPECT_EQ(top.budgetMs(), 10.0);
  AutoFrameBudget low(10, 0.01);
  for (int i = 1; i <= 10; ++i) low.add(i);
  EXPECT_EQ(low.budgetMs(), 1.0);
}

TEST(AutoFrameBudget, NoBudgetUntilTheQuantileMeansSomething) {
  AutoFrameBudget b(30, 0.9);
  EXPECT_EQ(b.minSamples(), 10);
  b.add(100);  // a slow first frame
  for (int i = 1; i <= 8; ++i) {
    b.add(i);
    EXPECT_EQ(b.budgetMs(), 0.0) << i;
  }
  b.add(9);  // ten samples: the 9th smallest, the slow first frame left out
  EXPECT_EQ(b.budgetMs(), 9.0);
  EXPECT_EQ(AutoFrameBudget(30, 0.5).minSamples(), 2);
  EXPECT_EQ(AutoFrameBudget(4, 0.9).minSamples(), 4);   // the window is smaller
  EXPECT_EQ(AutoFrameBudget(30, 1.0).minSamples(), 30);  // the max needs the window
  EXPECT_EQ(AutoFrameBudget(30, 0.01).minSamples(), 2);
}

TEST(AutoFrameBudget, FewerSamplesThanTheWindow) {
  AutoFrameBudget b(30, 0.6);  // min samples ceil(2.5) = 3
  b.add(7);
  b.add(3);
  EXPECT_EQ(b.budgetMs(), 0.0);
  b.add(5);
  EXPECT_EQ(b.budgetMs(), 5.0);  // ceil(1.8) = 2nd of {3, 5, 7}
  b.add(1);
  EXPECT_EQ(b.budgetMs(), 5.0);  // ceil(2.4) = 3rd of {1, 3, 5, 7}
}

TEST(AutoFrameBudget, OnlyTheLastWindowCounts) {
  AutoFrameBudget b(4, 1.0);
  for (double w : {100.0, 1.0, 2.0, 3.0}) b.add(w);
  EXPECT_EQ(b.budgetMs(), 100.0);
  b.add(4.0);  // 100 leaves the window
  EXPECT_EQ(b.samples(), 4);
  EXPECT_EQ(b.budgetMs(), 4.0);
  for (int i = 0; i < 100; ++i) b.add(2.0);
  EXPECT_EQ(b.budgetMs(), 2.0);
}

TEST(AutoFrameBudget, IgnoresNonFiniteAndNegativeWork) {
  AutoFrameBudget b(1, 1.0);
  b.add(5.0);
  b.add(std::nan(""));
  b.add(std::numeric_limits<double>::infinity());
  b.add(-1.0);
  EXPECT_EQ(b.samples(), 1);
  EXPECT_EQ(b.budgetMs(), 5.0);
}

TEST(AutoFrameBudget, BudgetDoesNotReorderTheWindow) {
  // budgetMs() partitions a scratch copy: the sliding window must still drop
  // the oldest sample, not whatever nth_element moved.
  AutoFrameBudget b(3, 1.0);
  b.add(9.0);
  b.add(1.0);
  b.add(5.0);
  EXPECT_EQ(b.budgetMs(), 9.0);
  b.add(2.0);  // drops 9
  EXPECT_EQ(b.budgetMs(), 5.0);
  b.add(3.0);  // drops 1
  EXPECT_EQ(b.budgetMs(), 5.0);
  b.add(4.0);  // drops 5
  EXPECT_EQ(b.budgetMs(), 4.0);
}

TEST(HoleCostModel, AllRectanglesUntilAMeasurementCounts) {
  HoleCostModel m;
  EXPECT_EQ(m.maxRects(0.0, 12), 12);
  EXPECT_EQ(m.maxRects(5.0, 0), 0);
  m.update(12, 50.0);  // the first (cold) draw: ignored
  EXPECT_EQ(m.maxRects(0.5, 12), 12);
  m.update(10, 2.0);  // 0.2 ms per rectangle
  EXPECT_DOUBLE_EQ(m.perRectMs, 0.2);
}

TEST(HoleCostModel, FitsTheBudgetAndKeepsOne) {
  HoleCostModel m;
  m.update(1, 1.0);
  m.update(4, 2.0);  // 0.5 ms each
  EXPECT_EQ(m.maxRects(1.6, 12), 3);
  EXPECT_EQ(m.maxRects(100.0, 12), 12);
  EXPECT_EQ(m.maxRects(0.1, 12), 1);  // over budget: still the one with most holes
  EXPECT_EQ(m.maxRects(-3.0, 12), 1);
  EXPECT_EQ(m.maxRects(std::nan(""), 12), 1);
}

TEST(HoleCostModel, FollowsTheNewestMeasurements) {
  HoleCostModel m;
  m.update(1, 1.0);
  m.update(2, 1.0);  // 0.5
  m.update(2, 2.0);  // 1.0: 0.75·0.5 + 0.25·1.0
  EXPECT_DOUBLE_EQ(m.perRectMs, 0.625);
  m.update(0, 5.0);             // no rectangle: ignored
  m.update(3, std::nan(""));    // ignored
  EXPECT_DOUBLE_EQ(m.perRectMs, 0.625);
}

}  // namespace
}  // namespace hw::session
