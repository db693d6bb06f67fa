// The `compare` command.
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
#include "session/walk.h"
#include "core/file_io.h"
#include "core/safe_io.h"
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

struct CompareCli {
  CLI::App* cmpCmd = nullptr;
  std::string cmpA;
  std::string cmpB;
  std::string cmpDiff;
};

int run(CompareCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    if (!o.cmpDiff.empty())
    if (auto st = checkOutputPath(o.cmpDiff, "--diff"); !st) return fail(st.error().message);
  auto ia = readPng(o.cmpA, metricImageLimits());
    if (!ia) return fail(ia.error().message);
    auto ib = readPng(o.cmpB, metricImageLimits());
    if (!ib) return fail(ib.error().message);
    if (ia->width() != ib->width() || ia->height() != ib->height())
      return fail("compare: " + o.cmpA + " is " + std::to_string(ia->width()) + "x" +
                  std::to_string(ia->height()) + ", " + o.cmpB + " is " + std::to_string(ib->width()) +
                  "x" + std::to_string(ib->height()) + " (expected the same size)");
    long differing = 0;
    int maxDiff = 0;
    for (int y = 0; y < ia->height(); ++y)
      for (int x = 0; x < ia->width(); ++x) {
        const Rgba8 p = ia->at(x, y), q = ib->at(x, y);
        const int d = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
        differing += d > 0;
        maxDiff = std::max(maxDiff, d);
      }
    if (!o.cmpDiff.empty())
      if (auto st = writePng(o.cmpDiff, diffImage(*ia, *ib)); !st) return fail(st.error().message);
    std::printf("psnr_db %.2f ssim %.4f differing_pixels %ld of %ld max_channel_diff %d\n",
                psnrCapped(*ia, *ib), ssim(*ia, *ib), differing,
                static_cast<long>(ia->width()) * ia->height(), maxDiff);
    return 0;
}

}  // namespace

void addCompareCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<CompareCli>();
  CompareCli& o = *state;
  // compare
  auto* cmpCmd = o.cmpCmd = app.add_subcommand(
      "compare", "Compare two PNG images of the same size (e.g. a viewer screenshot and a walk "
                 "frame): PSNR (dB, RGB), SSIM, pixels that differ, largest channel difference");
  cmpCmd->add_option("a", o.cmpA, "First PNG")->required();
  cmpCmd->add_option("b", o.cmpB, "Second PNG")->required();
  cmpCmd->add_option("--diff", o.cmpDiff, "Write |a - b| x4 per channel to this PNG");

  commands.push_back({cmpCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
