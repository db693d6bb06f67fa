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

void ModeChooser::Window::add(double ms) {
  if (!std::isfinite(ms) || ms < 0) return;
  v[next] = ms;
  next = (next + 1) % kWindow;
  n = std::min(n + 1, kWindow);
}

double ModeChooser::Window::median() const {
  if (n == 0) return std::nan("");
  std::array<double, kWindow> s = v;
  const auto mid = s.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(s.begin(), mid, s.begin() + static_cast<std::ptrdiff_t>(n));
  if (n % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(s.begin(), mid));
}

double ModeChooser::inBetweenMs() const {
  if (inBetween_.n > 0) return inBetween_.median();
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
  if (!std::isfinite(geometry) || !std::isfinite(warp)) return warpingNow;
  return warp < (warpingNow ? opt_.leaveAbove : opt_.enterBelow) * geometry;
}

}  // namespace hw::session
