#pragma once
// Threshold sweep: the walk at τ = 2^6 … 2^16 for both Δ² criteria, against
// baselines at matched quad count (uniform tiles, Rail-Track viewer; one quad
// per pixel, post-rendering warping), on the same frames. Run time against
// error: writes sweep.json / sweep.csv, PNG plots, an overlay per τ and a
// static index.html.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"
#include "session/presets.h"

namespace hw::bench {

struct SweepOptions {
  // The pipeline every run starts from: the preset's settings (Default: the
  // program's defaults), with every frame warped (mode hybrid) so each run
  // measures the warp, τ in z' units (no parallax threshold) and keyframes
  // built when needed (no worker sharing the CPUs with the measured frames);
  // each run then sets τ, the criterion, planarity and merging (the cells).
  session::Preset preset = session::Preset::Default;
  std::vector<double> taus;   // z' units; empty = 2^6, 2^7, …, 2^16
  bool bothCriteria = true;   // five-point and per-axis max (else five-point only)
  bool baselines = true;      // uniform tiles (matched to each five-point τ) and per-pixel
  bool variants = true;       // region-local planarity and strip merging, five-point
  // > 0 adds, per τ, the gradient-tolerance variant: five-point,
  // region-local + merge, LodOptions::tauGradient = this; variant name
  // "region-local+merge+grad=A". 0 = not run (the sweep as before).
  double tauGradient = 0;
  int maxFrames = 0;          // frames of the path per run; 0 = all
  DepthMode depthMode = kDefaultDepthMode;
  int overlayFrame = -1;      // keyframe for the overlays; −1 = the middle keyframe
  std::string outDir;         // required
  bool progress = true;
  // runSweep: keep the rows of an earlier interrupted run with the same
  // cells (outDir/.sweep-rows.jsonl) and run only the others. Without it a
  // row log left behind is started afresh.
  bool resume = false;
  std::string glRenderer, glVersion;
};

// What the runs start from, in words (the log, sweep.json's "pipeline", the page).
std::string sweepPipeline(const SweepOptions& options);

// The row log of an in-process sweep, outDir/.sweep-rows.jsonl: a header
// line naming the sweep's cells, then one line per finished cell's row, each
// appended (and flushed) as the cell finishes, so an interrupted sweep keeps
// what it ran. Removed when the sweep's outputs are written.
constexpr const char* kSweepRowLog = ".sweep-rows.jsonl";

// A GL context must be current. Returns the sweep.json document.
// Equivalent to runSweepCells over every cell, then finishSweep, with each
// row logged as it finishes (kSweepRowLog; options.resume reuses it).
Result<nlohmann::json> runSweep(const scenes::Scene& scene, const std::string& sceneLabel,
                                const scenes::CameraPath& path, const SweepOptions& options);

// The sweep as independent cells (for chunked runs, core/chunked_runs.h): cell
// order = per τ the LOD runs (five-point, per-axis max, three variants, the
// gradient variant if tauGradient > 0),
// then one uniform-tiles cell per τ, then per-pixel. A uniform-tiles cell
// finds its tile size itself — the five-point median quads per keyframe at its
// τ (taken from a five-point row run in the same call, else from meshing the
// keyframes: the same numbers), matched on the overlay keyframe — so no cell
// depends on another's result. A tiles cell whose tile size an earlier cell of
// the same call already ran returns {"cell", "duplicate_tile_size"}.
Result<int> sweepCellCount(const scenes::CameraPath& path, const SweepOptions& options);
// Rows already run, by cell (a resumed sweep's), and where each new row goes
// as soon as its cell finishes.
struct SweepCellLog {
  std::map<int, nlohmann::json> done;
  std::function<Status(const nlohmann::json& row)> append;
};
// Runs cells [first, last): a JSON array, one row per cell, each with "cell".
// With a log, cells in log->done are not run again (their rows are taken as
// they are) and every new row is passed to log->append.
Result<nlohmann::json> runSweepCells(const scenes::Scene& scene, const std::string& sceneLabel,
                                     const scenes::CameraPath& path, const SweepOptions& options,
                                     int first, int last, SweepCellLog* log = nullptr);
// Merges every cell's row (in cell order) into sweep.json/.csv, plots,
// overlays and index.html; uniform tiles are kept once per tile size (the
// first τ in order), as one in-process run writes them.
Result<nlohmann::json> finishSweep(const scenes::Scene& scene, const std::string& sceneLabel,
                                   const scenes::CameraPath& path, const SweepOptions& options,
                                   const nlohmann::json& cellRows);

}  // namespace hw::bench
