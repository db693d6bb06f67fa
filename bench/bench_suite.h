#pragma once
// The frame-timing benchmark behind `hybridwalk bench`: (a) scene complexity —
// geometry ms vs in-between ms of the built-in scenes from 100k to 4M
// triangles at the paper's two thresholds; (b) a walkthrough trace — per-frame
// and per-stage ms with keyframes marked; (c) keyframe spacing — PSNR vs
// keyframe_every; (d) each skip on and off; (e) per scene, the defaults against
// the paper's settings (bench/scene_table.h); (f) what a third keyframe or
// depth peeling could add to the holes (bench/disocclusion_study.h). Writes bench.json, CSVs, PNG plots and index.html.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/disocclusion_study.h"
#include "bench/scene_table.h"
#include "bench/skip_study.h"
#include "core/result.h"

namespace hw::bench {

struct BenchOptions {
  std::string outDir = "out/bench";
  std::vector<std::size_t> sizes{100000, 300000, 1000000, 2000000, 4000000};  // triangles
  std::vector<double> taus{2048.0, 32768.0};                                   // z' units
  std::vector<int> keyframeSpacings{2, 4, 6, 10, 15, 20, 30, 40};
  int renderFrames = 20;  // geometry-only frames per size (first one is warm-up)
  int walkFrames = 41;    // frames per walk in the complexity part
  std::string traceScene = "indoor";  // built-in scene for the trace and spacing parts
  std::size_t traceTriangles = 1000000;
  SkipStudyOptions skips;  // part (d)
  SceneTableOptions sceneTable;  // part (e); outDir, progress and GL strings are set from these
  DisocclusionOptions disocclusion;  // part (f)
  // Parts to run: complexity, trace, spacing (trace and spacing run
  // together), skips, scenes, disocclusion; empty = all.
  std::vector<std::string> parts;
  bool progress = true;
  std::string glRenderer, glVersion;
};

// A GL context must be current. Returns the bench.json document.
Result<nlohmann::json> runBenchSuite(const BenchOptions& options);

}  // namespace hw::bench
