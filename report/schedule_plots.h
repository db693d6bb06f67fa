#pragma once
// Plots and tables of the keyframe planner's runs: the calibration walks,
// the planned schedule against the walk that ran it, and a verified plan's
// rounds. Plain data in: the planner's driver fills these from its results.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace hw::report {

// One measured in-between frame of a calibration walk (keyframes every
// `spacing` frames), with its prediction (NaN: none) and path offset.
struct CalibrationPoint {
  int spacing = 0, k0 = 0, k1 = 0, frame = 0;
  double psnrDb = 0, predictedDb = 0, offsetDb = 0;
};

struct CalibrationPlot {
  std::vector<CalibrationPoint> points;
  std::vector<int> walkSpacings;  // one series per walk, in this order
  std::string predictor;          // its name, for the title
  double residualStdDb = 0, spearman = 0;
};

// A planned in-between frame: its bracketing keyframes and predicted PSNR.
struct PlannedPoint {
  int frame = 0, k0 = 0, k1 = 0;
  double predictedDb = 0;
};

// One round of a verified plan.
struct VerifyRoundPoint {
  int keyframes = 0;            // the round's plan
  int guaranteedKeyframes = 0;  // 0: none yet
  int framesMeasured = 0;       // in-between frames the round measured
};

struct VerifyPlot {
  std::vector<VerifyRoundPoint> rounds;
  std::size_t keyframes = 0;  // of the final plan
  bool guaranteed = false;
  int referenceKeyframes = 0;  // > 0: drawn as a line labelled referenceLabel
  std::string referenceLabel;
};

// calibration.csv (spacing,k0,k1,frame,psnr,predicted,offset: offset =
// the path offset at the frame, 0 without --calibration-window) and
// calibration.png (predicted vs measured, one colour per walk, the line
// measured = predicted) into outDir, atomically.
Status writeCalibration(const std::string& outDir, const CalibrationPlot& cal);

// planned.csv (frame,k0,k1,predicted,measured) and planned.png (both along
// the path, the target and the keyframes) into outDir; returns the median
// predicted PSNR of the in-between frames (NaN when there are none).
Result<double> writePlannedFrames(const std::string& outDir, const std::vector<PlannedPoint>& planned,
                                  const nlohmann::json& reportFrames, double targetDb,
                                  const std::vector<int>& keyframes);

// verify.png into outDir: each round of a verified plan against the frames
// measured before it, its plan's keyframes and the guaranteed schedule's.
Status writeVerifyPlot(const std::string& outDir, const VerifyPlot& plan);

// After the walk: planned.csv/png, and outDir/report.json's summary gains
// keyframe_schedule "adaptive" and planner (the planner's summary with the
// predicted median), rewritten atomically.
Status addPlannerToWalkReport(const std::string& outDir, const std::vector<PlannedPoint>& predicted,
                              double targetPsnrDb, const nlohmann::json& planner);

}  // namespace hw::report
