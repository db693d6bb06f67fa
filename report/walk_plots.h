#pragma once
// frame_times.png of a walk: each frame's work on the frame that paid for it
// (keyframe builds and uploads marked), the geometry renderer's time at the
// same camera, and with a budget the budget and the presented interval.
// Plain data in: the walk's driver fills these from its result.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/result.h"

namespace hw::report {

enum class DrawnAs : char { Geometry, Warp, Keyframe };

// One entry per walked frame.
struct FrameTimesData {
  std::vector<int> frame;           // frame index
  std::vector<DrawnAs> kind;        // how the frame was drawn
  std::vector<char> builtKeyframe;  // 1 = the frame paid for building or uploading a keyframe
  std::vector<double> workMs;       // ms.frame
  std::vector<double> intervalMs;   // ms.interval (work + pacing wait)
  std::vector<double> budgetMs;     // the frame's budget; 0 = none
  std::vector<double> referenceMs;  // geometry render at the same camera; NaN without reference
  double floorMs = -1;  // the fill floor: two layers of one full-screen quad (-1: not measured)
};

struct FrameTimesLook {
  std::string title;
  bool reference = false;  // draw referenceMs
  bool interval = false;   // draw intervalMs (frames paced to a budget)
};

Status writeFrameTimes(const std::string& pngPath, const FrameTimesData& times, const FrameTimesLook& look);

// strip_FRAME.png for each strip (reference | hybrid | difference x4 | holes,
// 4 px gaps), with a caption band above the panels: what each shows, and the
// frame's PSNR, SSIM and holes from stripInfo[i] (the walk report's
// summary.strips: frame, psnr, ssim, holes_before_fallback).
Status writeStrips(const std::string& outDir, const std::vector<Image<Rgba8>>& strips,
                   const nlohmann::json& stripInfo);

}  // namespace hw::report
