// The `sweep` command.
#include "app/commands.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/viewer.h"
#include "session/bake.h"
#include "session/export.h"
#include "core/json_util.h"
#include "core/chunked_runs.h"
#include "session/schedule_calibration.h"
#include "bench/sweep.h"
#include "session/presets.h"
#include "session/walk.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "session/keyframe_planner.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "app/cli_common.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct SweepCli {
  CLI::App* sweep = nullptr;
  Common sweepC;
  std::string sweepOut = "out/sweep";
  std::string preset = "default";
  std::string sweepTaus;
  bool sweepOneCriterion = false;
  bool sweepNoBaselines = false;
  bool sweepQuiet = false;
  int sweepOverlayFrame = -1;
  bool sweepNoVariants = false;
  std::string sweepTauGradS = "0";
  int sweepPerTask = 4;
  DistributeCli sweepDist;
};

int run(SweepCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    bench::SweepOptions so;
    std::size_t start = 0;
    while (start < o.sweepTaus.size()) {
      std::size_t end = o.sweepTaus.find(',', start);
      if (end == std::string::npos) end = o.sweepTaus.size();
      const std::string t = o.sweepTaus.substr(start, end - start);
      double v = 0;
      if (!parseTau(t, &v))
        return fail("--tau: expected comma-separated non-negative numbers like 2^11,2^15, got '" + t + "'");
      so.taus.push_back(v);
      start = end + 1;
    }
    session::parsePreset(o.preset, &so.preset);  // checked by the option
    so.bothCriteria = !o.sweepOneCriterion;
    so.baselines = !o.sweepNoBaselines;
    so.variants = !o.sweepNoVariants;
    if (std::string err; !parseTauGradient(o.sweepTauGradS, &so.tauGradient, &err)) return fail(err);
    so.maxFrames = o.sweepC.frames;
    so.depthMode = depthModeOf(o.sweepC.depth);
    so.overlayFrame = o.sweepOverlayFrame;
    so.outDir = o.sweepOut;
    so.progress = !o.sweepQuiet;
    auto in = loadInputs(o.sweepC);
    if (!in) return fail(in.error().message);
    so.glRenderer = in->context->renderer();
    so.glVersion = in->context->version();
    auto cells = bench::sweepCellCount(in->path, so);
    if (!cells) return fail(cells.error().message);
    const int chunks = (*cells + o.sweepPerTask - 1) / o.sweepPerTask;
    const std::string work = o.sweepOut + "/.chunks";
    if (o.sweepDist.chunk >= 0) {  // one chunk: its cells' rows to WORK/chunk-I.json
      if (o.sweepDist.chunk >= chunks)
        return fail("--chunk: " + std::to_string(o.sweepDist.chunk) + " out of range 0.." + std::to_string(chunks - 1));
      if (auto st = failChunkHook(o.sweepDist.chunk); !st) return fail(st.error().message);
      so.progress = false;
      auto rows = bench::runSweepCells(in->scene, o.sweepC.scene, in->path, so, o.sweepDist.chunk * o.sweepPerTask,
                                       std::min(*cells, (o.sweepDist.chunk + 1) * o.sweepPerTask));
      if (!rows) return fail(rows.error().message);
      if (auto st = writeChunkResult(work, o.sweepDist.chunk, {{"rows", *rows}}); !st)
        return fail(st.error().message);
      return 0;
    }
    if (!o.sweepQuiet)
      std::fprintf(stderr, "sweep: %d cells, each a walk of %s\n", *cells, bench::sweepPipeline(so).c_str());
    so.resume = o.sweepDist.d.resume;  // in process: the row log; distributed: the chunks
    Result<json> res = makeError("");
    if (distributed(o.sweepDist.d)) {
      if (auto st = ensureWritableDir(o.sweepOut); !st) return fail(st.error().message);
      ChunkPlan plan{"sweep", work, chunks, chunkCommand(argc, argv)};
      o.sweepDist.d.progress = !o.sweepQuiet;
      if (auto st = runChunks(plan, o.sweepDist.d); !st) return fail(st.error().message);
      auto results = readChunkResults(plan);
      if (!results) return fail(results.error().message);
      json rows = json::array();
      for (const json& r : *results)
        for (const json& row : r.at("rows")) rows.push_back(row);
      res = bench::finishSweep(in->scene, o.sweepC.scene, in->path, so, rows);
      if (res) removeChunkDir(work);
    } else {
      res = bench::runSweep(in->scene, o.sweepC.scene, in->path, so);
    }
    if (!res) return fail(res.error().message);
    std::printf("sweep: %zu run%s of %s; open %s/index.html (plots, table, overlays); data in "
                "sweep.json, sweep.csv\n",
                (*res)["rows"].size(), (*res)["rows"].size() == 1 ? "" : "s",
                so.preset == session::Preset::Paper
                    ? "the paper's pipeline (--preset paper)"
                    : "the default pipeline, every frame warped (--preset paper: the paper's)",
                o.sweepOut.c_str());
    return 0;
}

}  // namespace

void addSweepCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<SweepCli>();
  SweepCli& o = *state;
  // sweep
  auto* sweep = o.sweep = app.add_subcommand(
      "sweep", "Run time against error: the walk (default pipeline, every frame warped; "
               "--preset paper: the paper's) for tau = 2^6 .. 2^16 (or --tau), both "
               "criteria, and baselines at matched quad count (uniform tiles, one quad per "
               "pixel); writes sweep.json, sweep.csv, plots, overlays and index.html");
  addCommon(sweep, o.sweepC);
  sweep->add_option("--preset", o.preset,
                    "Pipeline every run starts from: default (the program's defaults, every frame "
                    "warped, tau in z' units) or paper (Zheng et al. 1999 exactly); each run then "
                    "sets tau, the criterion, planarity and merging")
      ->check(CLI::IsMember({"default", "paper"}))
      ->capture_default_str();
  sweep->add_option("--tau", o.sweepTaus,
                    "Comma-separated thresholds in z' units, e.g. '2^8,2^11,2^15' (default "
                    "2^6..2^16)");
  sweep->add_flag("--five-point-only", o.sweepOneCriterion, "Skip the per-axis-max criterion");
  sweep->add_flag("--no-baselines", o.sweepNoBaselines, "Skip uniform tiles and per-pixel meshes");
  sweep->add_flag("--no-variants", o.sweepNoVariants,
                  "Skip the edge-strip variants (region-local planarity, strip merging)");
  sweep->add_option("--tau-gradient", o.sweepTauGradS,
                    "Adds the gradient-tolerance variant (five-point, region-local+merge, "
                    "--tau-gradient A) per tau; 0 = not run. " + tauGradientHelp())
      ->capture_default_str();
  sweep->add_option("--overlay-frame", o.sweepOverlayFrame,
                    "Frame whose quad mesh is drawn per tau (-1: the middle keyframe)")
      ->check(CLI::Range(-1, 1 << 30))
      ->capture_default_str();
  sweep->add_option("--out", o.sweepOut, "Output directory")->capture_default_str();
  sweep->add_flag("--quiet", o.sweepQuiet, "No progress line");
  sweep->add_option("--cells-per-task", o.sweepPerTask,
                    "Sweep cells (walks) per chunk (--slurm array task or --workers process)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  addDistribute(sweep, o.sweepDist, "--cells-per-task cells");

  addForceOption(sweep);
  commands.push_back({sweep, [state](int argc, char** argv) {
    if (state->sweepDist.chunk >= 0) return run(*state, argc, argv);  // in the parent's folder
    return runInOutputDir(state->sweep, state->sweepOut, {"sweep.json"},
                          [&] { return run(*state, argc, argv); });
  }});
}

}  // namespace hw::app
