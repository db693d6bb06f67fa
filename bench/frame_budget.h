#pragma once
// The automatic per-frame budget (`walk --frame-budget-ms auto`, issue #8
// "stable frame rate", after Qu et al. 2000 §3.4): a fixed budget only steadies
// the presented frame interval when it lies above most frames' work, and what
// "most" is depends on the scene, the LOD, the machine and its load. The auto
// budget follows a quantile of the work of the last in-between frames
// (without their refresh), so the frames faster than it present at the
// budget — spending the time left on refreshing stale pixels — and only those
// slower than that quantile are late. Pure logic, no allocation after
// construction.
#include <cstddef>
#include <vector>

namespace hw::bench {

class AutoFrameBudget {
 public:
  // window ≥ 1 frames; 0 < quantile ≤ 1. Checked.
  AutoFrameBudget(int window, double quantile);

  // The work (ms) of an in-between frame, without its refresh; non-finite or
  // negative values are ignored.
  void add(double workMs);
  // The budget for the next frame: the `quantile` of the samples held (the
  // last `window` added; nearest rank, the smallest sample with at least
  // quantile × n samples at or below it). 0 (no budget) until minSamples()
  // have been added.
  double budgetMs() const;
  int samples() const { return static_cast<int>(count_); }
  // A quantile q means something once one sample in 1/(1 − q) may lie above
  // it: min(window, ⌈1/(1 − q)⌉) samples (10 at q = 0.9; the whole window at
  // q = 1). Before that the nearest rank would be the largest sample, often a
  // first frame slowed by cold GL state, and every frame would wait for it.
  int minSamples() const { return minSamples_; }

 private:
  std::vector<double> ring_;
  mutable std::vector<double> scratch_;
  std::size_t next_ = 0, count_ = 0;
  double quantile_;
  int minSamples_ = 1;
};

}  // namespace hw::bench
