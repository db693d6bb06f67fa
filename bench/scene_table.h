#pragma once
// The per-scene table of `hybridwalk bench` (part "scenes"): every scene walked
// with the program's defaults (session/presets.h) and with the paper's, in one
// run, so the ratios compare like with like: triangles, the share of frames
// drawn each way, frame ms over geometry ms at the same camera (median, p95),
// and the PSNR of warped frames (median, p5). Writes scenes.json, scenes.csv
// and scenes.md into the output directory.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace hw::bench {

struct SceneCase {
  std::string spec;  // as --scene
  std::string path;  // camera path file; empty or missing = the scene's default path
};

// The built-in indoor and outdoor scenes at 100k and 1M triangles, and the
// real scenes with the walking paths in paths/ (q3:, torcs:, morse: need
// `hybridwalk scenes fetch --outdoor`).
std::vector<SceneCase> defaultSceneCases();

struct SceneTableOptions {
  std::vector<SceneCase> cases = defaultSceneCases();
  std::string outDir = "out/bench";
  int frames = 0;              // per walk; 0 = the whole path
  int width = 0, height = 0;   // 0 = the path's
  bool progress = true;
  std::string glRenderer, glVersion;
};

// A GL context must be current. A scene that cannot be loaded gets a row with
// its error (and no figures); an output error fails the run.
Result<nlohmann::json> runSceneTable(const SceneTableOptions& options);

}  // namespace hw::bench
