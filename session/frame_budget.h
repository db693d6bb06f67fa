#pragma once
// The per-frame budget's two models. The automatic budget (`walk
// --frame-budget-ms auto`, after Qu et al. 2000 §3.4): a fixed budget only steadies
// the presented frame interval when it lies above most frames' work, and what
// "most" is depends on the scene, the LOD, the machine and its load. The auto
// budget follows a quantile of the work of the last in-between frames
// (without their refresh), so the frames faster than it present at the
// budget — spending the time left on refreshing stale pixels — and only those
// slower than that quantile are late. Pure logic, no allocation after
// construction.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <vector>

namespace hw::session {

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

// Estimated cost of a scissored geometry render (GeometryRenderer::
// renderColourRect) of p pixels, copy into the frame included:
// scale · (fixed + perPixel · p) · (1 + kMargin). fixed and perPixel come from
// two renders measured at warm-up (a tile and the whole image); scale follows
// the measured / estimated ratio of each refresh (exponential average), so
// the estimate tracks the scene and the load.
struct RefreshCostModel {
  static constexpr double kMargin = 0.1;  // headroom against timing noise
  static constexpr double kAlpha = 0.25;  // weight of the newest measurement
  double fixedMs = 0, perPixelMs = 0, scale = 1;

  void calibrate(long long smallPx, double smallMs, long long fullPx, double fullMs) {
    perPixelMs = fullPx > smallPx ? (fullMs - smallMs) / static_cast<double>(fullPx - smallPx) : 0;
    if (!(perPixelMs > 0)) perPixelMs = fullMs / static_cast<double>(fullPx > 1 ? fullPx : 1);
    fixedMs = smallMs - perPixelMs * static_cast<double>(smallPx);
    if (!(fixedMs > 0)) fixedMs = 0;
  }
  double predict(long long px) const {
    return scale * (fixedMs + perPixelMs * static_cast<double>(px)) * (1 + kMargin);
  }
  // The most pixels whose estimate fits in `ms` (0: not even an empty render).
  long long maxPixels(double ms) const {
    const double base = ms / (scale * (1 + kMargin)) - fixedMs;
    if (!(base > 0)) return 0;
    if (!(perPixelMs > 0)) return LLONG_MAX;
    return static_cast<long long>(std::fmin(base / perPixelMs, 1e15));
  }
  void update(long long px, double ms) {
    const double base = fixedMs + perPixelMs * static_cast<double>(px);
    if (base > 0 && std::isfinite(ms)) scale = (1 - kAlpha) * scale + kAlpha * (ms / base);
  }
};

// Estimated cost of drawing hole rectangles (WalkOptions::renderHoles): a
// running mean of the measured ms per rectangle (exponential average). Its
// vertex work is what a rectangle's sub-frustum holds, the whole depth of the
// scene behind a few pixels, so a rectangle costs about the same whatever its
// size; the mean tracks the scene and the load. The first measurement is
// left out (the first scissored draw pays for compiling its shaders).
struct HoleCostModel {
  static constexpr double kAlpha = 0.25;  // weight of the newest measurement
  double perRectMs = 0;                   // 0: nothing measured yet
  int seen = 0;                           // measurements offered, the first ignored

  // The most rectangles whose estimate fits in `ms`; before a measurement,
  // `wanted` (all of them). At least 1 while any is wanted, so the estimate
  // keeps learning (one rectangle costs a few percent of a geometry frame).
  int maxRects(double ms, int wanted) const {
    if (wanted <= 0) return 0;
    if (!(perRectMs > 0)) return wanted;
    if (!(ms > perRectMs)) return 1;
    const double n = std::floor(ms / perRectMs);
    return n >= wanted ? wanted : std::max(1, static_cast<int>(n));
  }
  void update(int rects, double ms) {
    if (rects <= 0 || !std::isfinite(ms) || ms < 0) return;
    if (seen++ == 0) return;
    const double per = ms / rects;
    perRectMs = perRectMs > 0 ? (1 - kAlpha) * perRectMs + kAlpha * per : per;
  }
};

}  // namespace hw::session
