#pragma once
// The skip table: for each skip the walk can make (fused layers with
// the background drawn only where the foreground left holes, the coverage
// test that drops the background layer, the previous-frame pass, the sky
// drawn as rectangles at infinity instead of leaving empty pixels as holes,
// near objects drawn directly), the same walk with it on and off: in-between
// ms and PSNR, and how often it fired. Then each subdivision mode of large
// quads (none, uniform, adaptive) against none, with PSNR also over the pixels
// large leaves drew (walk summary psnr_large_quads). Part (d) of `hybridwalk bench`.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace hw::bench {

struct SkipScene {
  std::string spec;      // scenes::loadScene spec: indoor, outdoor, q3:oa_dm5, torcs:forza, ...
  std::string pathFile;  // camera path JSON; empty = the scene's default path
};

struct SkipStudyOptions {
  std::vector<SkipScene> scenes{{"indoor", ""},
                                {"outdoor", ""},
                                {"q3:oa_dm5", "paths/oa_dm5.json"},
                                {"torcs:forza", "paths/forza.json"}};
  int frames = 41;            // frames of each path per walk
  double nearDistance = 1.0;  // scene units (metres in every built-in and real scene)
  // The default walk is run this many times (≥ 2) per scene: the spread of
  // its in-between ms medians (max − min) is the run-to-run noise a
  // difference between on and off must exceed to count.
  int repeats = 3;
  bool progress = true;
  std::string glRenderer, glVersion;
};

// A GL context must be current. Scenes that cannot be loaded (e.g. real
// scenes not fetched) are reported in the result's "unavailable" list with
// the reason and a warning on stderr; the others are measured. Returns
// {"rows": [...], "unavailable": [...], "settings": {...}}. Each row has
// ms_difference (off − on in-between ms median), ms_noise (the scene's
// run-to-run spread) and within_noise (|ms_difference| ≤ ms_noise).
Result<nlohmann::json> runSkipStudy(const SkipStudyOptions& options);

// The rows as CSV (header + one line per row).
std::string skipStudyCsv(const nlohmann::json& study);

}  // namespace hw::bench
