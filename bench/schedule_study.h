#pragma once
// Fixed vs error-driven keyframe schedules: the walk with a
// keyframe every N frames for several N, the predictors' correlation with the
// measured per-frame PSNR of those walks, then the walk with planned
// (keyframe/keyframe_planner.h) schedules at several target PSNRs; keyframes
// per 100 frames against median and 5th-percentile in-between PSNR. Writes
// schedule.json, runs.csv, correlation.csv, schedule.png, predictor.png and
// index.html into a directory.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "session/walk.h"
#include "core/result.h"
#include "session/keyframe_planner.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::bench {

using session::WalkOptions;


struct ScheduleStudyOptions {
  std::string outDir = "out/schedule";
  std::vector<int> fixedSpacings{4, 6, 8, 10, 15, 20};  // frames between keyframes
  int referenceSpacing = 10;  // the headline compares with this fixed spacing
  // Target PSNRs (dB) of the planned runs. Empty: one per fixed spacing,
  // the target whose plan has as many keyframes as that fixed run (so the
  // curves compare at equal counts; the targets then do not depend on the
  // fit's scale, only on its sign).
  std::vector<double> targets;
  session::PlannerOptions planner;  // gaps, probe size, predictor; target ignored
  // Plan with the predictor whose rank correlation with the measured PSNR of
  // the fixed walks is strongest here (kAllPredictors and kProbePredictors),
  // and its fit; otherwise planner's.
  bool autoPredictor = true;
  WalkOptions walk;  // τ, planarity, depth, … (output, schedule and progress are set here)
  bool progress = true;
};

// A GL context must be current. Returns the schedule.json document.
Result<nlohmann::json> runScheduleStudy(const scenes::Scene& scene, const std::string& sceneLabel,
                                        const scenes::CameraPath& path,
                                        const ScheduleStudyOptions& options);

}  // namespace hw::bench
