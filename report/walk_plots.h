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

// strip_FRAME.png for each of the walk's strips, with a caption band above
// the panels: what each shows, and the frame's PSNR, SSIM and holes.
Status writeStrips(const std::string& outDir, const session::WalkResult& result);

}  // namespace hw::report
