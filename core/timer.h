#pragma once
// Wall-clock stopwatch and order statistics for reports (median, p95).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/check.h"

namespace hw {

class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  double ms() const {
    return std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
  }
  // Milliseconds since the last call (or construction) and restart.
  double lap() {
    const auto now = Clock::now();
    const double t = std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return t;
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

// Linear-interpolated percentile, p in [0, 100]. NaN for an empty list.
inline double percentile(std::vector<double> v, double p) {
  HW_CHECK(p >= 0.0 && p <= 100.0);
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = p / 100.0 * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  // On an element exactly: no interpolation (keeps ±inf, avoids 0·inf = NaN).
  return frac == 0.0 ? v[lo] : v[lo] + frac * (v[hi] - v[lo]);
}
inline double median(std::vector<double> v) { return percentile(std::move(v), 50.0); }

}  // namespace hw
