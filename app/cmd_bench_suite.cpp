// The `bench` command.
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
#include "bench/bench_suite.h"
#include "session/export.h"
#include "core/json_util.h"
#include "session/schedule_calibration.h"
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

struct BenchCli {
  CLI::App* benchCmd = nullptr;
  std::string benchOut = "out/bench";
  std::string benchSizes;
  bool benchQuick = false;
  bool benchQuiet = false;
  std::vector<std::string> benchOnly;
};

int run(BenchCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    bench::BenchOptions bo;
    bo.outDir = o.benchOut;
    bo.progress = !o.benchQuiet;
    if (o.benchQuick) {
      bo.sizes = {100000, 300000};
      bo.keyframeSpacings = {5, 10, 20};
      bo.renderFrames = 6;
      bo.walkFrames = 21;
      bo.traceTriangles = 100000;
      bo.skips.frames = 11;
      bo.skips.scenes = {{"indoor", ""}};
      bo.sceneTable.cases = {{"indoor:100k", ""}, {"outdoor:100k", ""}};
      bo.sceneTable.frames = 41;
      bo.disocclusion.cases = {{"indoor", ""}};
      bo.disocclusion.frames = 41;
    }
    bo.parts = o.benchOnly;
    if (!o.benchSizes.empty()) {
      bo.sizes.clear();
      std::size_t start = 0;
      while (start < o.benchSizes.size()) {
        std::size_t end = o.benchSizes.find(',', start);
        if (end == std::string::npos) end = o.benchSizes.size();
        std::string t = o.benchSizes.substr(start, end - start);
        double mul = 1;
        if (!t.empty() && (t.back() == 'k' || t.back() == 'K')) mul = 1e3, t.pop_back();
        else if (!t.empty() && (t.back() == 'm' || t.back() == 'M')) mul = 1e6, t.pop_back();
        double v = 0;
        if (!parseTau(t, &v) || v * mul < 1000 || v * mul > 5e7)
          return fail("--sizes: expected triangle counts between 1k and 50M like 100k,1M, got '" +
                      o.benchSizes.substr(start, end - start) + "'");
        bo.sizes.push_back(static_cast<std::size_t>(v * mul));
        start = end + 1;
      }
    }
    auto ctx = gl::createHeadlessContext();
    if (!ctx) return fail(ctx.error().message);
    bo.glRenderer = (*ctx)->renderer();
    bo.glVersion = (*ctx)->version();
    auto res = bench::runBenchSuite(bo);
    if (!res) return fail(res.error().message);
    std::printf("bench: done in %.0f s; open %s/index.html; data in bench.json and CSVs\n",
                (*res)["elapsed_s"].get<double>(), o.benchOut.c_str());
    return 0;
}

// "100k,1M": triangle counts as --sizes takes them.
std::string sizesText(const std::vector<std::size_t>& sizes) {
  std::string out;
  for (std::size_t n : sizes) {
    if (!out.empty()) out += ",";
    if (n % 1000000 == 0) out += std::to_string(n / 1000000) + "M";
    else if (n % 1000 == 0) out += std::to_string(n / 1000) + "k";
    else out += std::to_string(n);
  }
  return out;
}

}  // namespace

void addBenchCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<BenchCli>();
  BenchCli& o = *state;
  // bench
  auto* benchCmd = o.benchCmd = app.add_subcommand(
      "bench", "Frame-timing benchmark: geometry vs in-between ms over scene sizes 100k..4M "
               "triangles (tau 2^11, 2^15), a walkthrough trace with per-stage ms, PSNR vs "
               "keyframe spacing, and each skip on and off; writes bench.json, CSVs, plots and "
               "index.html");
  benchCmd->add_option("--out", o.benchOut, "Output directory")->capture_default_str();
  benchCmd->add_option("--sizes", o.benchSizes,
                       "Comma-separated triangle counts for the complexity part (k/M suffixes); "
                       "default " + sizesText(bench::BenchOptions{}.sizes));
  benchCmd->add_flag("--quick", o.benchQuick,
                     "Small version: sizes 100k,300k, fewer frames, trace at 100k, 3 spacings, skips on indoor only (11 frames)");
  benchCmd->add_flag("--quiet", o.benchQuiet, "No progress lines");
  addGlOptions(benchCmd);
  benchCmd->add_option("--only", o.benchOnly,
                       "Run only these parts (comma-separated): complexity, trace, spacing, skips "
                       "(skips = the table: each skip on and off, and --subdivide none, "
                       "uniform, adaptive with PSNR also over the pixels of leaves larger than a "
                       "cell, on indoor, outdoor, q3:oa_dm5 and torcs:forza; real scenes need "
                       "'scenes fetch --outdoor'), scenes (per scene: the defaults against "
                       "--preset paper: share of frames per mode, frame/geometry ms, PSNR; "
                       "scenes.md, scenes.csv), disocclusion (what a third keyframe or depth "
                       "peeling could add to the holes, against the hole rectangles; "
                       "disocclusion.csv), floor (one full-screen textured quad as one and two "
                       "warped layers at 256², 512², 1024²)")
      ->delimiter(',')
      ->check(CLI::IsMember(
          {"complexity", "trace", "spacing", "skips", "scenes", "disocclusion", "floor"}));

  commands.push_back({benchCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
