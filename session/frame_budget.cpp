#include "session/frame_budget.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace hw::session {

AutoFrameBudget::AutoFrameBudget(int window, double quantile) : quantile_(quantile) {
  HW_CHECK_GE(window, 1);
  HW_CHECK(quantile > 0 && quantile <= 1);
  ring_.assign(static_cast<std::size_t>(window), 0.0);
  scratch_.reserve(ring_.size());
  const double need = quantile < 1 ? std::ceil(1.0 / (1.0 - quantile) - 1e-9) : 1e18;
  minSamples_ = static_cast<int>(std::min<double>(window, std::max(1.0, need)));
}

void AutoFrameBudget::add(double workMs) {
  if (!std::isfinite(workMs) || workMs < 0) return;
  ring_[next_] = workMs;
  next_ = (next_ + 1) % ring_.size();
  count_ = std::min(count_ + 1, ring_.size());
}

double AutoFrameBudget::budgetMs() const {
  if (count_ == 0 || count_ < static_cast<std::size_t>(minSamples_)) return 0.0;
  scratch_.assign(ring_.begin(), ring_.begin() + static_cast<std::ptrdiff_t>(count_));
  // Nearest rank: the ceil(q·n)-th smallest (1-based).
  const auto rank = static_cast<std::size_t>(
      std::ceil(quantile_ * static_cast<double>(count_) - 1e-9));
  const std::size_t k = std::clamp<std::size_t>(rank, 1, count_) - 1;
  std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k),
                   scratch_.end());
  return scratch_[k];
}

}  // namespace hw::session
