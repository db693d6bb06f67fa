#include "app/keyframe_pacing.h"

#include <algorithm>
#include <cmath>

namespace hw::app {

double earlyAheadDistance(double sNewest, double sOlder, bool recedingFromNewest, double spacing,
                          double fraction) {
  if (!(sNewest >= 0) || !(spacing > 0)) return 0.0;
  // Progress from the older keyframe to the newest: sOlder / (sOlder + sNewest).
  if (!recedingFromNewest && sOlder < 1e200 && !(sOlder >= fraction * (sOlder + sNewest)))
    return 0.0;
  const double d = recedingFromNewest ? spacing - sNewest : spacing + sNewest;
  return d > 0 ? d : 0.0;
}

double updateRequestInterval(double estimate, double interval) {
  if (!(interval > 0) || !std::isfinite(interval)) return estimate;
  if (!(estimate > 0) || interval <= estimate) return interval;
  return estimate + 0.25 * (interval - estimate);
}

double workerPacingFrames(double intervalEstimate, double distanceToLost, double stepPerFrame,
                          double maxFrames) {
  const double hi = std::max(1.0, maxFrames);
  double frames = intervalEstimate > 0 ? intervalEstimate : hi;
  if (stepPerFrame > 1e-9 && std::isfinite(distanceToLost))
    frames = std::min(frames, std::max(0.0, distanceToLost) / stepPerFrame - 1.0);
  return std::clamp(frames, 1.0, hi);
}

}  // namespace hw::app
