// Statistics helpers (core/statistics.h): least-squares fits and correlations
// on data whose answer is known.
#include "core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hw {
namespace {

TEST(Statistics, LineThroughExactPointsIsRecovered) {
  const std::vector<double> x{1, 2, 3, 4, std::nan("")}, y{5, 3, 1, -1, 7};
  const LineFit f = fitLine(x, y);
  EXPECT_NEAR(f.slope, -2.0, 1e-12);
  EXPECT_NEAR(f.intercept, 7.0, 1e-12);
  EXPECT_TRUE(std::isnan(fitLine({1, 1}, {2, 3}).slope));
}

TEST(Statistics, CorrelationsOfMonotoneAndIndependentData) {
  std::vector<double> x, y, z;
  for (int i = 0; i < 50; ++i) {
    x.push_back(i);
    y.push_back(std::exp(0.1 * i));  // monotone, not linear
    z.push_back(i % 2 ? 1.0 : -1.0);
  }
  EXPECT_NEAR(spearman(x, y), 1.0, 1e-12);
  EXPECT_LT(pearson(x, y), 0.95);
  EXPECT_GT(pearson(x, y), 0.7);
  EXPECT_NEAR(pearson(x, x), 1.0, 1e-12);
  std::vector<double> neg(x.rbegin(), x.rend());
  EXPECT_NEAR(spearman(x, neg), -1.0, 1e-12);
  EXPECT_LT(std::abs(pearson(x, z)), 0.1);
  EXPECT_TRUE(std::isnan(pearson({1, 2, 3}, {4, 4, 4})));
}

TEST(Statistics, LeastSquaresRecoversTwoSlopesAndZerosAConstantRegressor) {
  std::vector<std::vector<double>> x;
  std::vector<double> y;
  for (int i = 0; i < 20; ++i) {
    const double a = i % 5, b = (i * 7) % 11;
    x.push_back({a, b, 3.0});
    y.push_back(1.5 + 2.0 * a - 0.5 * b);
  }
  const std::vector<double> c = leastSquares(x, y);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_NEAR(c[0], 1.5, 1e-9);
  EXPECT_NEAR(c[1], 2.0, 1e-9);
  EXPECT_NEAR(c[2], -0.5, 1e-9);
  EXPECT_EQ(c[3], 0.0);
  EXPECT_TRUE(leastSquares({{1.0, 1.0}, {2.0, 2.0}, {3.0, 3.0}}, {1, 2, 3}).empty());
}

}  // namespace
}  // namespace hw
