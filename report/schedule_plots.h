#pragma once
// Plots and tables of the keyframe planner's runs: the calibration walks,
// the planned schedule against the walk that ran it, and a verified plan's
// rounds.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "session/keyframe_planner.h"
#include "session/planned_walk.h"
#include "session/schedule_calibration.h"

namespace hw::report {

using session::PlannedFrame;
using session::ScheduleCalibration;

// calibration.csv (spacing,k0,k1,frame,psnr,predicted,offset: offset =
// the path offset at the frame, 0 without --calibration-window) and
// calibration.png (predicted vs measured, one colour per walk, the line
// measured = predicted) into outDir, atomically.
Status writeCalibration(const std::string& outDir, const ScheduleCalibration& cal,
                        const session::PredictorCalibration& fit, session::Predictor predictor,
                        const std::vector<double>& frameOffsetDb = {});

// planned.csv (frame,k0,k1,predicted,measured) and planned.png (both along
// the path, the target and the keyframes) into outDir; returns the median
// predicted PSNR of the in-between frames (NaN when there are none).
Result<double> writePlannedFrames(const std::string& outDir, const std::vector<PlannedFrame>& planned,
                                  const nlohmann::json& reportFrames, double targetDb,
                                  const std::vector<int>& keyframes);

// verify.png into outDir: each round of a verified plan against the frames
// measured before it, its plan's keyframes and the guaranteed schedule's;
// referenceKeyframes (> 0) as a line, labelled referenceLabel.
Status writeVerifyPlot(const std::string& outDir, const session::VerifiedPlan& plan,
                       int referenceKeyframes, const std::string& referenceLabel);

// A planned walk's pictures, before the walk: calibration.csv/png (when it
// calibrated) and verify.png (when it verified) into outDir (created).
Status writePlannedWalkPlots(const std::string& outDir, const session::PlannedWalk& planned);

// After the walk: planned.csv/png, and outDir/report.json's summary gains
// keyframe_schedule "adaptive" and planner (planned.planner with the
// predicted median), rewritten atomically.
Status addPlannerToWalkReport(const std::string& outDir, const session::PlannedWalk& planned);

}  // namespace hw::report
