#pragma once
// Verified plans: the planner measures the segments a plan picks, at the
// walk's own resolution, and plans again until measured frames guarantee
// the walk's median.
#include <map>
#include <utility>
#include <vector>

#include "core/result.h"
#include "session/planner_search.h"

namespace hw::session {

// A predictor's error is shared by a segment's frames, and a plan picks the
// segments predicted best, i.e. those it overrates (on forza at 512² the
// calibrated planner's segment-level error is 0.8 dB rms, and the fewest
// keyframes reaching fixed-10's median need it well under 0.5 dB: docs/
// results/2026-12-02/calibration_window). So measure them: walk the planned
// segments not measured yet at the walk's own resolution, count their frames
// exactly, correct the predictions near them along the path by their
// residuals, and plan again, aiming one keyframe below the guaranteed
// schedule (below); until a plan is made of measured segments only, or needs
// no fewer keyframes than the guaranteed schedule.
// The schedule returned is the fewest keyframes whose median measured frames
// alone guarantee: more than half of its in-between frames are measured ≥
// the target, a segment not measured counting as below it.

// Measured PSNRs (dB) of whole segments: (k0, k1) → in-between frames k0+1 ..
// k1−1 in order; a frame identical to its reference counts kProbePsnrCap, as
// the walk's statistics count it.
using MeasuredSegments = std::map<std::pair<int, int>, std::vector<double>>;
// Measures every segment of `segments` into `out` (every frame).
using SegmentMeasurer =
    std::function<Status(const std::vector<std::pair<int, int>>& segments, MeasuredSegments& out)>;

struct VerifyOptions {
  int maxRounds = 8;  // rounds that measure (≥ 0); 0 = plan once, measure nothing
  // Path offsets (smoothResidualsAlongPath) from the residuals of every
  // measured frame, frames; 0 = none.
  double windowFrames = 0;
  double prior = 2.0;  // samples, as smoothResidualsAlongPath
  // The error model of unmeasured frames: the measured frames' residuals left
  // by the offsets (held out by segment) instead of search.error.
  bool empiricalError = true;
  // Added to every unmeasured frame's prediction while searching, dB (≥ 0):
  // segments that might do better than predicted get measured too. The
  // schedule returned stays a guaranteed one, so optimism costs
  // measurements, never the target; converged with it means no schedule
  // with fewer keyframes is predicted to reach the target even that much
  // above its predictions.
  double optimismDb = 0;
};

struct VerifyRound {
  int keyframes = 0;       // this round's plan
  int unmeasured = 0;      // of its segments, not measured before the round
  int framesMeasured = 0;  // in-between frames this round measured
  // The fewest keyframes whose median measured frames alone guarantee,
  // before the round's measurements (0: none yet).
  int guaranteedKeyframes = 0;
  double heldOutRmsDb = 0;  // what the offsets leave of the measured frames' residuals
};

struct VerifiedPlan {
  std::vector<int> keyframes;
  // The last plan was all measured segments, or needed no fewer keyframes
  // than the guaranteed schedule (the search found nothing better to measure).
  bool converged = false;
  // keyframes: measured frames alone reach the target for more than half of
  // its in-between frames (segments not measured count as missing it), so
  // its median is at least the target; false: none does, the last plan.
  bool guaranteed = false;
  int good = 0;  // guaranteed: its in-between frames measured ≥ target (a lower bound)
  std::vector<VerifyRound> rounds;
  std::vector<double> offsetDb;  // the last round's path offsets (empty: window 0)
};

// `predict`: the calibrated predictor without path offsets. `measured`
// starts with what is known (the calibration walks' segments) and gains what
// the rounds measure. search.criterion is ignored (walk-median).
Result<VerifiedPlan> planVerified(int frames, double targetPsnrDb, const PlanSearch& search,
                                  const FramePredictor& predict, MeasuredSegments& measured,
                                  const SegmentMeasurer& measure, const VerifyOptions& options);

}  // namespace hw::session
