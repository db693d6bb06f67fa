#include "core/statistics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>

#include "core/check.h"

namespace hw {

LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
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

}  // namespace hw
