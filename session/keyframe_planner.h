#pragma once
// Error-driven keyframe schedule: instead of a keyframe every N
// frames, walk the known camera path forward and start a new keyframe when a
// cheap predictor says an in-between frame would fall below a target PSNR.
// Backward warping (Zheng et al. 1999 §2) needs the keyframe *after* a frame
// too, so the planner looks ahead along the path, as the Rail-Track viewer
// does. The predictor works on low-resolution probes of the candidate
// keyframes (a few ms each), never on the frame's own reference image.
// A viewer without a known path would run the same test on predicted motion:
// extrapolate the eye and view direction from the last frames' velocity,
// place the candidate next keyframe at the extrapolated pose a look-ahead
// time away, and render it (asynchronously) as soon as the predictor says a
// frame between the current keyframe and that candidate drops below target;
// a wrong guess costs holes, filled from the previous frame as usual.
#include <functional>
#include <vector>

#include "core/camera.h"
#include "core/result.h"
#include "keyframe/geometry_renderer.h"
#include "session/planner_calibration.h"
#include "session/planner_predictors.h"
#include "session/planner_probe.h"
#include "session/planner_search.h"
#include "session/planner_verify.h"

namespace hw::session {

struct PlannerOptions {
  double targetPsnrDb = 24.0;  // in-between frames should not fall below this, dB (predicted)
  int minGap = 2;              // frames between consecutive keyframes (≥ 1)
  int maxGap = 30;             // frames (≥ minGap)
  // holes+distance: on indoor a 1 dB higher median than holes alone at equal
  // keyframe count (p5 both well above fixed); the best fit on q3:oa_dm5.
  Predictor predictor = Predictor::HolesDistance;
  PlanCriterion criterion = PlanCriterion::WorstFrame;
  bool useDefaultFit = true;  // fit = defaultFit(predictor)
  PsnrFit fit;                // used when !useDefaultFit
  int probeSize = 64;         // pixels, longer side of the probes
  ProbeErrorOptions probeError;  // probe-psnr only
  int candidateStride = 1;    // see PlanSearch
  int framesPerSegment = 0;   // see PlanSearch (0 = every in-between frame)
  PredictionError error;      // walk-median: the predictor's error (see PlanSearch)
  std::vector<double> frameOffsetDb;  // added to frame i's prediction (PathOffsets; empty = none)
};

struct PlanResult {
  std::vector<int> keyframes;  // sorted, first 0, last frames−1
  double planMs = 0;           // whole plan: probes, splats, search (wall clock)
  double probeRenderMs = 0;    // of which probe renders
  int probes = 0;              // probe keyframes rendered
  long evaluations = 0;        // predictor calls
  PsnrFit fit;                 // the fit used
};

// Plans an error-driven schedule for `frames` frames of a path. A GL context
// must be current; `renderer` draws the probes (its scene is the walk's).
Result<PlanResult> planAdaptiveSchedule(keyframe::GeometryRenderer& renderer,
                                        const std::function<Camera(int)>& cameraOf, int frames,
                                        const PlannerOptions& options);
// The same on an existing probe (its probes and memoised features are
// reused; planMs then excludes what earlier plans already paid for).
Result<PlanResult> planAdaptiveSchedule(KeyframeProbe& probe, int frames,
                                        const PlannerOptions& options);

}  // namespace hw::session
