// The viewer's options checked, and its share of a walk's (app/viewer.h).
#include <cmath>
#include <string>

#include "app/viewer.h"
#include "app/viewer_keys.h"
#include "core/short_number.h"

namespace hw::app {

void applyWalkOptions(const session::WalkOptions& walk, ViewerOptions* out) {
  out->mode = walk.mode;
  out->lod = walk.lod;
  out->asyncKeyframes = walk.asyncKeyframes;
  out->renderHoles = walk.renderHoles;
  out->renderHolesBudget = walk.renderHolesBudget;
  out->simplifyHoles = walk.simplifyHoles;
  out->holeRectsMax = walk.holeRectsMax;
  out->holeTilePx = walk.holeTilePx;
  out->warper = walk.warper;
  out->warperThreads = walk.warperThreads;
}

Status checkViewerOptions(const ViewerOptions& o) {
  if (o.width < 16 || o.height < 16 || o.width > 16384 || o.height > 16384)
    return makeError("window size must be in [16, 16384] pixels, got " + std::to_string(o.width) +
                     "x" + std::to_string(o.height));
  if (!(o.lod.tau >= 0) || !std::isfinite(o.lod.tau))
    return makeError("tau must be finite and >= 0, got " + shortNumber(o.lod.tau));
  if (!(o.lod.tauParallaxPx >= 0) || !std::isfinite(o.lod.tauParallaxPx))
    return makeError("tau-px must be finite and >= 0, got " + shortNumber(o.lod.tauParallaxPx));
  if (!(o.lod.tauGradient >= 0) || !std::isfinite(o.lod.tauGradient))
    return makeError("tau gradient must be finite and >= 0, got " + shortNumber(o.lod.tauGradient));
  if (!(o.keyframeAngleDeg > 0 && o.keyframeAngleDeg < 180) || !(o.keyframeDistance >= 0) ||
      !std::isfinite(o.keyframeDistance))
    return makeError("keyframe thresholds: distance must be >= 0 and angle in (0, 180) degrees");
  if (o.exitAfterFrames < 0)
    return makeError("exit-after frame count must be >= 0, got " +
                     std::to_string(o.exitAfterFrames));
  if (auto k = parseScriptedKeys(o.keys); !k) return k.error();
  return {};
}

}  // namespace hw::app
