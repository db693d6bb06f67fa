// The `stress` command.
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
#include "session/schedule_calibration.h"
#include "bench/stress.h"
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

struct StressCli {
  CLI::App* stressCmd = nullptr;
  std::string stressOut = "out/stress";
  bool stressQuick = false;
  bool stressQuiet = false;
};

int run(StressCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    auto ctx = gl::createHeadlessContext();
    if (!ctx) return fail(ctx.error().message);
    bench::StressOptions so;
    so.outDir = o.stressOut;
    so.quick = o.stressQuick;
    so.progress = !o.stressQuiet;
    so.glRenderer = (*ctx)->renderer();
    so.glVersion = (*ctx)->version();
    auto res = bench::runStress(so);
    if (!res) return fail(res.error().message);
    const int failed = (*res)["cases_failed"].get<int>();
    std::printf("stress: %s; recommended default depth mode: %s; open %s/index.html\n",
                failed ? "SOME DEGENERATE CASES FAILED" : "all degenerate cases passed",
                (*res)["recommended_default"].dump().c_str(), o.stressOut.c_str());
    if (failed) return fail(std::to_string(failed) + " degenerate-camera cases failed (see cases.csv)");
    return 0;
}

}  // namespace

void addStressCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<StressCli>();
  StressCli& o = *state;
  // stress
  auto* stressCmd = o.stressCmd = app.add_subcommand(
      "stress", "Numerical stability: depth precision of the three depth modes over far/near "
                "ratios 10..1e6 and view angles 0..85 deg (Δ² noise, quads, corner and world "
                "errors, PSNR), and degenerate/extreme cameras; writes stress.json, CSVs, plots, "
                "index.html; exit 1 if a degenerate case fails");
  stressCmd->add_option("--out", o.stressOut, "Output directory")->capture_default_str();
  stressCmd->add_flag("--quick", o.stressQuick, "Smaller images and fewer cases");
  stressCmd->add_flag("--quiet", o.stressQuiet, "No progress line");
  addGlOptions(stressCmd);

  commands.push_back({stressCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
