#pragma once
// Calibrating the keyframe planner's predictor on the scene it plans for.
// The predictor's default fits come from the built-in indoor
// scene; on another scene or resolution the same predicted dB mean other
// measured dB (oa_dm5 at 512²: a target of 33.25 dB predicted gave a 29.3 dB
// median). Fixed-schedule walks of the same path, scene and pipeline options
// measure the in-between frames' PSNR against the geometry renderer; the
// predictor is refitted to them, so the planner's target is in measured dB,
// and the fit's residual spread is the planner's uncertainty.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "session/walk.h"
#include "core/result.h"
#include "session/keyframe_planner.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::session {

// One calibration walk: keyframes every `spacing` frames (0 and the last
// frame always), its in-between frames' PSNR median (as the walk report
// computes it) and how many there were.
struct CalibrationWalk {
  int spacing = 0;
  int keyframes = 0;
  int inBetween = 0;
  double psnrMedian = 0;  // dB; NaN when no frame had a finite PSNR
  double walkMs = 0;
};

struct ScheduleCalibration {
  std::vector<CalibrationWalk> walks;  // in the order of the spacings
  // Every in-between frame of every walk with a finite PSNR (a frame
  // identical to the reference has no error to fit; a frame in several walks
  // appears once per walk); spacing[i] is the walk samples[i] came from.
  std::vector<session::CalibrationSample> samples;
  std::vector<int> spacing;
  // Every in-between frame of every walk by segment, identical frames
  // counting kProbePsnrCap (99 dB) as the walk's statistics count them: what
  // the verified planner starts from.
  session::MeasuredSegments measured;
};

// Walks the first `frames` frames of `path` once per spacing (each in
// [2, frames − 1], checked: at least one in-between frame) with `base`'s
// pipeline options. Output, frame budget, async keyframes and keyframe
// sources are turned off (a budget's refreshes depend on timing; the
// predictor models the warp). A GL context must be current.
Result<ScheduleCalibration> runCalibrationWalks(const scenes::Scene& scene,
                                                const std::string& sceneLabel,
                                                const scenes::CameraPath& path, int frames,
                                                const std::vector<int>& spacings,
                                                const WalkOptions& base, bool progress);

// Walks only `segments` (keyframes at their ends; none may overlap another's
// span) with the calibration walks' settings and adds every in-between
// frame's PSNR to `out` (the verified planner's measurer). A GL context must
// be current.
Status measureSegments(const scenes::Scene& scene, const std::string& sceneLabel,
                       const scenes::CameraPath& path, int frames,
                       const std::vector<std::pair<int, int>>& segments, const WalkOptions& base,
                       session::MeasuredSegments& out);




// The planned schedule against the walk that ran it: every in-between frame's
// predicted PSNR (the planner's fit) and measured PSNR (the walk report's
// frames[].psnr; identical frames count 99 dB, as the walk's stats).
struct PlannedFrame {
  int frame = 0, k0 = 0, k1 = 0;
  double predictedDb = 0;
};
// Predictions of every in-between frame of `keyframes` (sorted, first 0),
// with frameOffsetDb[frame] added as the planner adds it (empty = none).
Result<std::vector<PlannedFrame>> predictSchedule(session::KeyframeProbe& probe,
                                                  session::Predictor predictor,
                                                  const session::PsnrFit& fit,
                                                  const std::vector<int>& keyframes,
                                                  const std::vector<double>& frameOffsetDb = {});

// A predictor fit as JSON: {"intercept", "slope", "slope2"} (null when not
// finite), and "more" (the slopes of regressors 3..) only when the fit has them.
nlohmann::json fitJson(const session::PsnrFit& f);

// The report's summary.planner.calibration block.
nlohmann::json calibrationJson(const ScheduleCalibration& cal,
                               const session::PredictorCalibration& fit);

}  // namespace hw::session
