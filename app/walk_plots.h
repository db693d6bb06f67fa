#pragma once
// The walk's and the planner's pictures: session results handed to report/
// as its plain data.
#include <string>

#include "core/result.h"
#include "session/planned_walk.h"
#include "session/walk.h"

namespace hw::app {

// frame_times.png (report::writeFrameTimes), titled with the scene, mode,
// async keyframes and budget.
Status writeFrameTimes(const std::string& pngPath, const session::WalkResult& result,
                       const session::WalkOptions& options, const std::string& sceneLabel);

// strip_FRAME.png for each of the walk's strips (report::writeStrips).
Status writeStrips(const std::string& outDir, const session::WalkResult& result);

// A planned walk's pictures, before the walk: calibration.csv/png (when it
// calibrated) and verify.png (when it verified) into outDir (created).
Status writePlannedWalkPlots(const std::string& outDir, const session::PlannedWalk& planned);

// After the walk: report::addPlannerToWalkReport with the plan's predictions.
Status addPlannerToWalkReport(const std::string& outDir, const session::PlannedWalk& planned);

}  // namespace hw::app
