#pragma once
// frame_times.png of a walk: each frame's work on the frame that paid for it
// (keyframe builds and uploads marked), the geometry renderer's time at the
// same camera, and with a budget the budget and the presented interval.
#include <string>

#include "core/result.h"
#include "session/walk.h"

namespace hw::report {

Status writeFrameTimes(const std::string& pngPath, const session::WalkResult& result,
                       const session::WalkOptions& options, const std::string& sceneLabel);

}  // namespace hw::report
