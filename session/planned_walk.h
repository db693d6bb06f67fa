#pragma once
// An error-driven keyframe schedule for a walk, end to end: optional
// calibration walks that refit the planner's predictor on this scene, path
// and resolution; the plan; optional verification rounds that measure the
// segments the plan picks; and the predictions of the schedule chosen. What
// `walk --schedule adaptive` runs before the walk itself.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"
#include "session/keyframe_planner.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"

namespace hw::session {

// The predictor's error model for --plan-by walk-median (PredictionError).
enum class PlanUncertainty {
  Auto,       // Empirical with a calibration, else none
  Empirical,  // the calibration's residuals (needs a calibration)
  Normal,     // a normal error with the calibration's residual spread (needs a calibration)
  Given,      // a normal error of PlannedWalkOptions::uncertaintyDb (0 = none)
};

struct PlannedWalkOptions {
  // Target (dB), predictor, criterion, gaps, probes; fit and error are set
  // here when a calibration runs.
  PlannerOptions plan;
  // Fixed schedules walked first to refit the predictor (each keyframes
  // every G frames, G in [2, frames − 1]); empty = the predictor's default fit.
  std::vector<int> calibrationSpacings;
  // > 0: the target is the measured PSNR median of the calibration walk every
  // targetSpacing frames (which must be one of calibrationSpacings), not
  // plan.targetPsnrDb.
  int targetSpacing = 0;
  PlanUncertainty uncertainty = PlanUncertainty::Auto;
  double uncertaintyDb = 0;  // Given only, dB ≥ 0
  // Path offsets from the calibration residuals (smoothResidualsAlongPath),
  // frames; 0 = none. Needs a calibration.
  double calibrationWindowFrames = 0;
  int verifyRounds = 0;           // planVerified rounds; 0 = plan only. Needs a calibration.
  double verifyOptimismDb = 1.0;  // VerifyOptions::optimismDb
  bool progress = true;           // a stderr line per verify round
};

struct PlannedWalk {
  std::vector<int> keyframes;           // the schedule to walk (first 0, last frames − 1)
  Predictor predictor = Predictor::HolesDistance;  // the one planned with
  double targetPsnrDb = 0;              // the target planned for (given or measured)
  std::vector<PlannedFrame> predicted;  // every in-between frame of `keyframes`, predicted
  // The report's summary.planner (settings, fit, costs, calibration, verify),
  // without predicted_psnr_median (the walk's report adds it).
  nlohmann::json planner;
  // With calibration spacings: the walks, the refit and the path offsets it
  // planned with (what report::writeCalibration draws).
  std::optional<ScheduleCalibration> calibration;
  PredictorCalibration calibrationFit;
  std::vector<double> calibrationOffsetDb;
  // With verify rounds: the verified plan (report::writeVerifyPlot), and the
  // keyframe count of the fixed schedule every targetSpacing frames (0 without).
  std::optional<VerifiedPlan> verified;
  int referenceKeyframes = 0;
  std::string referenceLabel;
};

// Plans the first `frames` frames of `path` (walk: the pipeline options the
// calibration and verification walks use). A GL context must be current.
// Errors: option values out of range, failed calibration or probe renders.
Result<PlannedWalk> planWalk(const scenes::Scene& scene, const std::string& sceneLabel,
                             const scenes::CameraPath& path, int frames, const WalkOptions& walk,
                             PlannedWalkOptions options);

}  // namespace hw::session
