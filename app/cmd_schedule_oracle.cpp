// The `oracle` command.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/option_checks.h"
#include "app/viewer.h"
#include "bench/schedule_oracle.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/json_util.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "session/bake.h"
#include "session/export.h"
#include "session/keyframe_planner.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct ScheduleOracleCli {
  CLI::App* oracleCmd = nullptr;
  Common oracleC;
  std::string oracleOut = "out/schedule-oracle";
  std::string oracleSpacings = "4,6,8,10,15,20";
  StudyLod oracleLod;
  bool oracleQuiet = false;
  int oracleRef = 10;
  int oracleMaxGap = 20;
  std::string oracleTable;
  bool oracleNoPlanner = false;
  bench::ScheduleOracleOptions oracleDefaults;
  int oracleProbePsnrSize = oracleDefaults.probePsnrSize;
  session::ProbeErrorOptions oracleProbeError = oracleDefaults.probeError;
  bool oracleProbePsnrOnly = false;
  bool oracleNoPreviousFill = false;
};

int run(ScheduleOracleCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    bench::ScheduleOracleOptions so;
    if (std::string e = parseSpacings(o.oracleSpacings, o.oracleMaxGap, "--max-gap", &so.fixedSpacings);
        !e.empty())
      return fail(e);
    if (std::find(so.fixedSpacings.begin(), so.fixedSpacings.end(), o.oracleRef) == so.fixedSpacings.end())
      return fail("--reference-spacing: expected one of --spacings '" + o.oracleSpacings + "', got " +
                  std::to_string(o.oracleRef));
    if (std::string e = applyStudyLod(o.oracleLod, &so.walk.lod); !e.empty()) return fail(e);
    so.walk.depthMode = depthModeOf(o.oracleC.depth);
    so.walk.maxFrames = o.oracleC.frames;
    so.referenceSpacing = o.oracleRef;
    so.maxGap = o.oracleMaxGap;
    so.tableCsv = o.oracleTable;
    so.planner = !o.oracleNoPlanner;
    so.probePsnrSize = o.oracleProbePsnrSize;
    so.probeError = o.oracleProbeError;
    if (o.oracleNoPreviousFill) so.probeError.previousFill = false;
    so.probePsnrOnly = o.oracleProbePsnrOnly;
    so.outDir = o.oracleOut;
    so.progress = !o.oracleQuiet;
    auto in = loadInputs(o.oracleC);
    if (!in) return fail(in.error().message);
    so.walk.glRenderer = in->context->renderer();
    so.walk.glVersion = in->context->version();
    auto res = bench::runScheduleOracle(in->scene, o.oracleC.scene, in->path, so);
    if (!res) return fail(res.error().message);
    const json& h = (*res)["headline"];
    auto n = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
    std::printf("schedule-oracle: fixed every %d: %.1f keyframes/100 frames, median %.2f dB; the best "
                "schedule reaching that median: %.1f keyframes/100 (%+.0f %%; goal -30 %%);\n"
                "  the error-driven planner: %.1f keyframes/100 (%+.0f %%)\n  open %s/oracle.png\n",
                o.oracleRef, n(h["reference_keyframes_per_100"]), n(h["reference_psnr_median"]),
                n(h["oracle_keyframes_per_100"]), -100 * n(h["best_possible_reduction"]),
                n(h["planner_keyframes_per_100"]), -100 * n(h["planner_reduction"]),
                o.oracleOut.c_str());
    for (const json& pp : h["probe_predictors"])
      std::printf("  %s (%d px): %.1f keyframes/100 (%+.0f %%, %s); fit on this table: %.1f "
                  "(%+.0f %%); one walk-median plan %.0f ms\n",
                  pp["predictor"].get<std::string>().c_str(), pp["probe_size"].get<int>(),
                  n(pp["keyframes_per_100"]), -100 * n(pp["reduction"]),
                  pp["criterion"].get<std::string>().c_str(), n(pp["in_sample_keyframes_per_100"]),
                  -100 * n(pp["in_sample_reduction"]), n(pp["walk_median_plan_ms"]));
    return 0;
}

}  // namespace

void addScheduleOracleCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<ScheduleOracleCli>();
  ScheduleOracleCli& o = *state;
  // schedule-oracle
  auto* oracleCmd = o.oracleCmd = app.add_subcommand(
      "schedule-oracle",
      "The best any keyframe schedule can do on a path: measures the PSNR of every in-between "
      "frame for every keyframe pair up to --max-gap frames apart (--max-gap*(--max-gap+1)/2-1 "
      "walks), then finds by dynamic programming the fewest keyframes whose median in-between "
      "PSNR reaches each fixed schedule's. The bound for the error-driven schedule. "
      "Writes oracle.json, oracle.csv, oracle.png, segments.csv (the measured table, for "
      "--table) and features.csv (the planner's probe features of every entry)");
  addCommon(oracleCmd, o.oracleC);
  addStudyLodOptions(oracleCmd, o.oracleLod);
  oracleCmd->add_option("--max-gap", o.oracleMaxGap,
                        "Longest gap between keyframes considered, frames (cost grows with its square)")
      ->check(CLI::Range(2, 60))
      ->capture_default_str();
  oracleCmd->add_option("--spacings", o.oracleSpacings,
                        "Fixed schedules compared: keyframe_every values, frames, each <= --max-gap")
      ->capture_default_str();
  oracleCmd->add_option("--reference-spacing", o.oracleRef,
                        "Fixed spacing the headline compares with, frames (one of --spacings)")
      ->check(CLI::Range(1, 60))
      ->capture_default_str();
  oracleCmd->add_option("--table", o.oracleTable,
                        "Score from an earlier run's segments.csv instead of walking (same scene, "
                        "path, size, --frames, --max-gap and LOD options)");
  oracleCmd->add_flag("--no-planner", o.oracleNoPlanner,
                      "Do not score the error-driven planner (targets 18..40 dB predicted, "
                      "worst-frame and segment-median criteria) on the table");
  oracleCmd->add_option("--probe-psnr-size", o.oracleProbePsnrSize,
                        "Also score the probe predictors (probe-psnr, probe-psnr+distance) with "
                        "probes of this size, pixels on the longer side (0 = not scored); writes "
                        "probe_error.csv")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  oracleCmd->add_flag("--probe-psnr-only", o.oracleProbePsnrOnly,
                      "Score only the probe predictors (not the default predictor's curves or "
                      "features.csv)");
  oracleCmd
      ->add_option("--probe-hole-mse", o.oracleProbeError.holeMse,
                   "Probe predictors with --probe-no-previous-fill: squared error charged per "
                   "hole pixel of the warped probe, (0-255)^2 units")
      ->check(numberRange(0.0, 65025.0))
      ->capture_default_str();
  oracleCmd->add_option("--probe-blur", o.oracleProbeError.blurRadius,
                        "Probe predictors: box-blur radius of the compared probes, probe pixels (0 = none)")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  oracleCmd->add_option("--probe-tolerance", o.oracleProbeError.shiftTolerance,
                        "Probe predictors without blur: compare each warped pixel with the best "
                        "reference pixel within this many probe pixels (0 = the same pixel)")
      ->check(CLI::Range(0, 4))
      ->capture_default_str();
  oracleCmd->add_flag("--probe-no-previous-fill", o.oracleNoPreviousFill,
                      "Probe predictors: charge --probe-hole-mse per hole of the warped probe "
                      "instead of filling it from the previous frame's, as the walk does");
  oracleCmd->add_option("--probe-supersample", o.oracleProbeError.supersample,
                        "Probe predictors: render probes at this many times their size and "
                        "box-filter down (1 = off)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  oracleCmd->add_option("--out", o.oracleOut, "Output directory")->capture_default_str();
  oracleCmd->add_flag("--quiet", o.oracleQuiet, "No progress line");

  commands.push_back({oracleCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
