#include "session/frame_mode.h"

#include <algorithm>
#include <cmath>

namespace hw::session {

const char* frameModeName(FrameMode m) {
  switch (m) {
    case FrameMode::Auto: return "auto";
    case FrameMode::Hybrid: return "hybrid";
    case FrameMode::Geometry: return "geometry";
  }
  return "?";
}

bool parseFrameMode(const std::string& s, FrameMode* out) {
  for (FrameMode m : {FrameMode::Auto, FrameMode::Hybrid, FrameMode::Geometry})
    if (s == frameModeName(m)) {
      *out = m;
      return true;
    }
  return false;
}

const char* frameKindName(FrameKind k) {
  switch (k) {
    case FrameKind::Geometry: return "geometry";
    case FrameKind::Warp: return "warp";
    case FrameKind::Keyframe: return "keyframe";
  }
  return "?";
}

void ModeChooser::Window::add(double ms, double triangles) {
  if (!std::isfinite(ms) || ms < 0) return;
  v[next] = ms;
  tri[next] = std::isfinite(triangles) ? triangles : -1;
  next = (next + 1) % kWindow;
  n = std::min(n + 1, kWindow);
}

// Linear interpolation between the order statistics around q (m - 1); the
// median of an even count is the mean of the middle two.
double ModeChooser::Window::quantile(double q, std::size_t last) const {
  const std::size_t m = std::min(n, std::max<std::size_t>(last, 1));
  if (m == 0) return std::nan("");
  std::array<double, kWindow> s;
  for (std::size_t k = 0; k < m; ++k) s[k] = v[(next + kWindow - 1 - k) % kWindow];  // newest first
  const auto end = s.begin() + static_cast<std::ptrdiff_t>(m);
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(m - 1);
  const auto lo = static_cast<std::ptrdiff_t>(pos);
  std::nth_element(s.begin(), s.begin() + lo, end);
  const double a = s[static_cast<std::size_t>(lo)];
  if (lo + 1 >= static_cast<std::ptrdiff_t>(m)) return a;
  const double b = *std::min_element(s.begin() + lo + 1, end);
  return a + (pos - static_cast<double>(lo)) * (b - a);
}

double ModeChooser::geometryMs() const {
  if (opt_.geometryByTriangles && viewTriangles_ >= 0) {
    const double at = geometryAtTriangles(viewTriangles_);
    if (std::isfinite(at)) return at;
  }
  return geometryRecentMs();
}

double ModeChooser::geometryAtTriangles(double triangles) const {
  if (!(triangles >= 0)) return std::nan("");
  // The nearest triangle count at or below `triangles`, and at or above.
  double below = -1, above = -1;
  for (std::size_t k = 0; k < geometry_.n; ++k) {
    const double t = geometry_.tri[k];
    if (t < 0) continue;
    if (t <= triangles && t > below) below = t;
    if (t >= triangles && (above < 0 || t < above)) above = t;
  }
  if (below < 0 && above < 0) return std::nan("");
  // The median ms of the samples within 2 % of count c (on the side of `triangles`).
  auto msNear = [&](double c) {
    std::array<double, kWindow> ms{};
    std::size_t m = 0;
    for (std::size_t k = 0; k < geometry_.n; ++k) {
      const double t = geometry_.tri[k];
      if (t >= 0 && std::abs(t - c) <= 0.02 * c && (t <= triangles) == (c <= triangles))
        ms[m++] = geometry_.v[k];
    }
    const auto mid = ms.begin() + static_cast<std::ptrdiff_t>(m / 2);
    std::nth_element(ms.begin(), mid, ms.begin() + static_cast<std::ptrdiff_t>(m));
    if (m % 2 == 1) return *mid;
    return (*mid + *std::max_element(ms.begin(), mid)) / 2;
  };
  if (below >= 0 && above >= 0) {
    const double lo = msNear(below), hi = msNear(above);
    if (above == below) return (lo + hi) / 2;
    return lo + (hi - lo) * (triangles - below) / (above - below);
  }
  // Above the samples: in proportion to the nearest. Below them: half of
  // the nearest's cost is taken as fixed (clearing, shading and reading back
  // the whole image: about 4 ms of the 4-18 ms of an indoor frame at 512²
  // is there at any triangle count), half in proportion.
  if (below >= 0) return below > 0 ? msNear(below) * triangles / below : msNear(below);
  return msNear(above) * (0.5 + 0.5 * triangles / above);
}

double ModeChooser::inBetweenMs() const {
  if (inBetween_.n > 0) return inBetween_.median();
  return floorMs_ >= 0 ? floorMs_ : std::nan("");
}

double ModeChooser::inBetweenTailMs() const {
  if (inBetween_.n > 0) return inBetween_.quantile(opt_.tailQuantile);
  return floorMs_ >= 0 ? floorMs_ : std::nan("");
}

double ModeChooser::predictedWarpMs(double framesPerSegment) const {
  const double f = std::max(1.0, framesPerSegment);
  const double warp = inBetweenMs();
  const double keyframe = keyframe_.n > 0 ? keyframe_.median() : geometryMs();
  return ((f - 1) * warp + keyframe) / f;  // NaN propagates
}

bool ModeChooser::warpNext(bool warpingNow, double framesPerSegment) const {
  const double geometry = geometryMs(), warp = predictedWarpMs(framesPerSegment);
  const double tail = inBetweenTailMs();
  if (!std::isfinite(geometry) || !std::isfinite(warp) || !std::isfinite(tail)) return warpingNow;
  return warp < (warpingNow ? opt_.leaveAbove : opt_.enterBelow) * geometry &&
         tail < (warpingNow ? opt_.tailLeaveAbove : opt_.tailEnterBelow) * geometry;
}

void ModeChooser::addInBetweenMs(double ms) {
  inBetween_.add(ms);
  if (!std::isfinite(ms) || ms < 0) return;
  segmentMinMs_ = segmentFrames_ == 0 ? ms : std::min(segmentMinMs_, ms);
  ++segmentFrames_;
}

void ModeChooser::startSegment() {
  segmentFrames_ = 0;
  segmentMinMs_ = 0;
}

bool ModeChooser::giveUp() const {
  const double geometry = geometryMs();
  return opt_.giveUpAfter > 0 && segmentFrames_ >= opt_.giveUpAfter && std::isfinite(geometry) &&
         segmentMinMs_ > opt_.tailLeaveAbove * geometry;
}

}  // namespace hw::session
