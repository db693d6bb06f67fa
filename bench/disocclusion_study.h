#pragma once
// The disocclusion study (part "disocclusion" of `hybridwalk bench`): what a
// third keyframe or a second depth layer per keyframe could add to the pixels
// both keyframes of a pair miss. Each in-between frame of a path is drawn as
// the walk draws it with the default preset in hybrid mode, holes copied from
// the previous frame; then, for that frame only, its holes are filled in turn
//  - from the keyframe before the pair, warped to the frame (a third keyframe);
//  - from the keyframe after the pair, warped likewise (where the path has no
//    such keyframe, the frame is scored as it is);
//  - by the geometry renderer's hole rectangles (the default preset's pass);
//  - with the exact pixels where the surface lies inside the view of one of
//    the pair's keyframes (what depth peeling could reach at best: a surface
//    that keyframe saw behind the nearest one);
//  - with every hole pixel exact (what any filling could reach);
// and each is scored against the geometry renderer at the frame's camera.
// Holes are split by where their surface lies: outside both keyframes' views
// (new to the eye, as in a sharp turn), inside one of them but hidden or not
// meshed (disoccluded), or empty (sky).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/scene_table.h"
#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::bench {

struct DisocclusionOptions {
  // Scene and camera path (bench/scene_table.h).
  std::vector<SceneCase> cases{{"indoor", ""},
                               {"indoor", "paths/indoor_sharp_turn.json"},
                               {"q3:oa_dm5", "paths/oa_dm5.json"},
                               {"torcs:forza", "paths/forza.json"}};
  int frames = 120;           // first frames of each path; 0 = all
  int width = 0, height = 0;  // 0 = the path's
  bool progress = true;
};

// One path. A GL context must be current. Returns {"scene", "path", "frames":
// [per in-between frame], "summary"}; see docs/results for the fields.
Result<nlohmann::json> runDisocclusionPath(const scenes::Scene& scene, const std::string& label,
                                           const std::string& pathLabel,
                                           const scenes::CameraPath& path,
                                           const DisocclusionOptions& options);

// Every case; a scene or path that cannot be loaded is listed under
// "unavailable" with its error.
Result<nlohmann::json> runDisocclusionStudy(const DisocclusionOptions& options);

// One row per in-between frame of every path.
std::string disocclusionCsv(const nlohmann::json& study);

}  // namespace hw::bench
