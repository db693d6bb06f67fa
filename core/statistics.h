#pragma once
// Small statistics over paired samples: a least-squares line, least squares
// with several regressors, Pearson and Spearman (rank) correlation. Pairs with
// a non-finite member are skipped where stated; nothing here throws.
#include <vector>

namespace hw {

// y ≈ intercept + slope · x.
struct LineFit {
  double intercept = 0;
  double slope = 0;
};

// Least-squares line through (x, y) pairs (pairs with a non-finite member are
// skipped); {NaN, NaN} with fewer than two distinct x. Precondition
// (checked): x and y have one size.
LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

// Least squares y ≈ coef[0] + Σ coef[j+1] · x[i][j] with k = x[0].size()
// regressors: the centred normal equations solved by Gaussian elimination
// with partial pivoting. A regressor constant over the data gets slope 0 (its
// level is in the intercept). Empty when the others are collinear, n ≤ k or
// there are no rows. Rows must be finite and all of size k (not checked).
std::vector<double> leastSquares(const std::vector<std::vector<double>>& x,
                                 const std::vector<double>& y);

// Pearson and Spearman (rank, ties averaged) correlation of the finite pairs;
// NaN when undefined (fewer than two pairs, or a constant side).
// Precondition (checked): x and y have one size.
double pearson(const std::vector<double>& x, const std::vector<double>& y);
double spearman(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace hw
