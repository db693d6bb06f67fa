// The viewer's --mode auto (app/viewer_auto_mode.h).
#include "app/viewer_auto_mode.h"

namespace hw::app {

ViewerAutoMode::Step ViewerAutoMode::step(bool hybrid, double viewTriangles, long frame,
                                          bool probeRegularly) {
  Step s;
  s.hybrid = hybrid;
  // The geometry cost compared against is this view's (ModeChooserOptions::geometryByTriangles).
  chooser_.setViewTriangles(viewTriangles);
  if (++framesSinceChoice_ < kFrames) {
    if (hybrid && chooser_.giveUp()) {
      s.hybrid = false;
      s.switched = s.gaveUp = true;
      ++switches_;
      if (firstGeometry_ < 0) firstGeometry_ = frame;
    }
    return s;
  }
  framesSinceChoice_ = 0;
  chooser_.startSegment();
  const bool next = chooser_.warpNext(hybrid, kFrames);
  if (next != hybrid) {
    s.hybrid = next;
    s.switched = true;
    ++switches_;
    if (!next && firstGeometry_ < 0) firstGeometry_ = frame;
  } else if (hybrid && (geometrySamples_ < kMinGeometrySamples ||
                        (probeRegularly && ++choicesSinceProbe_ >= kProbeEvery))) {
    choicesSinceProbe_ = 0;
    s.probe = true;
  }
  return s;
}

void ViewerAutoMode::record(session::FrameKind kind, double workMs, double geometryMs,
                            double triangles, bool builtKeyframe, double keyframeRenderMs,
                            double keyframeTriangles) {
  if (builtKeyframe) {
    chooser_.addGeometryMs(keyframeRenderMs, keyframeTriangles);
    ++geometrySamples_;
  }
  switch (kind) {
    case session::FrameKind::Geometry:
      chooser_.addGeometryMs(geometryMs, triangles);
      ++geometrySamples_;
      break;
    case session::FrameKind::Keyframe:
      chooser_.addKeyframeMs(workMs);
      break;
    case session::FrameKind::Warp:
      chooser_.addInBetweenMs(workMs);
      break;
  }
}

}  // namespace hw::app
