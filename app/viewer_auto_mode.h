#pragma once
// The viewer's `--mode auto` as plain logic: every kFrames frames, hybrid or
// geometry, whichever session::ModeChooser (the walk's rule,
// session/frame_mode.h) predicts cheaper from this session's frame costs.
// While hybrid only keyframes rendered in the frame measure the geometry:
// until kMinGeometrySamples geometry renders are known (so that one slow
// render does not decide), and with keyframes from the worker or a database
// every kProbeEvery choices, a choice draws one frame as geometry (a probe).
// Between choices, hybrid frames that all cost more than drawing give the
// segment up at once (ModeChooser::giveUp), as the walk does. No GL.
#include "session/frame_mode.h"

namespace hw::app {

class ViewerAutoMode {
 public:
  static constexpr int kFrames = 10, kProbeEvery = 4, kMinGeometrySamples = 3;

  struct Step {
    bool hybrid = true;  // how this frame and the next ones are drawn
    bool probe = false;  // this one frame as geometry, to measure it
    bool switched = false;
    bool gaveUp = false;  // switched to geometry between choices
  };
  // Before frame `frame`, which views `viewTriangles` (< 0: not known), the
  // frames so far drawn hybrid or not; probeRegularly: keyframes come from
  // the worker or a database (no geometry render in the frame).
  Step step(bool hybrid, double viewTriangles, long frame, bool probeRegularly);
  // After a frame (not the first, a load): how it was drawn, its work ms, the
  // geometry render's ms and triangles for a geometry frame; a keyframe
  // rendered in it is a geometry render too (its render ms and triangles).
  void record(session::FrameKind kind, double workMs, double geometryMs, double triangles,
              bool builtKeyframe, double keyframeRenderMs, double keyframeTriangles);

  double geometryMs() const { return chooser_.geometryMs(); }  // NaN: unknown
  long switches() const { return switches_; }
  long firstGeometryChoice() const { return firstGeometry_; }  // -1: never

 private:
  session::ModeChooser chooser_;
  int framesSinceChoice_ = 0, choicesSinceProbe_ = 0, geometrySamples_ = 0;
  long switches_ = 0, firstGeometry_ = -1;
};

}  // namespace hw::app
