#pragma once
// What a person reads about one walk, from its report.json alone (plain
// JSON, docs/walk-report.md): the summary line to quote and the details
// printed after it, the PSNR-along-the-path plot, and the walk's page
// (index.html). `hybridwalk walk` writes them; `hybridwalk report DIR`
// rebuilds them from DIR/report.json.
//
// The counts keep one name each, everywhere they are printed:
//   frames warped / drawn as geometry / keyframe frames (frames_by_mode;
//     they add up to the walk's frames),
//   keyframes in the schedule (keyframe_frames), keyframes built (rendered
//     and meshed in this run) or read (from a database) (summary.keyframes).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace hw::report {

struct WalkSummaryText {
  std::string headline;              // one line, never "nan"
  std::vector<std::string> details;  // one line each, unindented
};

// From report.json's "summary" object. Missing or null statistics read as
// "not measured" (and say why where the summary tells: --no-reference, the
// frame mode), never as "nan".
WalkSummaryText walkSummaryText(const nlohmann::json& summary);

// Why no frame was warped, as a clause ("auto: drawing was cheaper here, 19 ms
// against a warp of 27.6 ms; `--mode hybrid` warps every frame"); empty when
// some frame was warped.
std::string whyNothingWarped(const nlohmann::json& summary);

// psnr_along_path.png: each warped frame's PSNR against the geometry frame at
// the same camera, by frame index, with the keyframe frames and the frames
// drawn as geometry marked along the bottom. `report` is the whole report
// ({"frames": [...], "summary": {...}}).
Status writePsnrAlongPath(const std::string& pngPath, const nlohmann::json& report);

// The page's HTML for a report: summary line and table, the plots and strips
// that exist among `files` (names relative to the page), the settings that
// ran, the machine and GL renderer.
std::string walkPageHtml(const nlohmann::json& report, const std::vector<std::string>& files);

// Reads DIR/report.json, writes DIR/psnr_along_path.png and DIR/index.html;
// the report's summary to *summary when given. Errors name the file
// (missing, not JSON, not a walk report).
Status writeWalkPage(const std::string& dir, nlohmann::json* summary = nullptr);

}  // namespace hw::report
