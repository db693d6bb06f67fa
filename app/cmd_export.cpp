// The `export` command.
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

struct ExportCli {
  CLI::App* exportCmd = nullptr;
  Common exportC;
  std::string exportOut = "out/keyframes";
  bool exportNoInBetween = false;
  bool exportQuiet = false;
};

int run(ExportCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    auto in = loadInputs(o.exportC);
    if (!in) return fail(in.error().message);
    session::ExportOptions eo;
    eo.inBetween = !o.exportNoInBetween;
    eo.maxFrames = o.exportC.frames;
    eo.progress = !o.exportQuiet;
    eo.depthMode = depthModeOf(o.exportC.depth);
    if (auto st = session::exportKeyframes(in->scene, in->path, o.exportOut, eo); !st)
      return fail(st.error().message);
    std::printf("exported keyframes of %s to %s (cameras.json lists them)\n", o.exportC.scene.c_str(),
                o.exportOut.c_str());
    return 0;
}

}  // namespace

void addExportCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<ExportCli>();
  ExportCli& o = *state;
  // export-keyframes
  auto* exportCmd = o.exportCmd = app.add_subcommand(
      "export-keyframes",
      "Write the path's keyframes for other view-synthesis tools: NAME.png (RGB), "
      "NAME.depth.pfm (float32 eye-space depth along the view direction, 0 = nothing drawn) and "
      "cameras.json (fx, fy, cx, cy in pixels with pixel centres at +0.5, near, far, "
      "world_from_camera 4x4 row-major in OpenCV axes: x right, y down, z forward); also the "
      "in-between cameras and their reference images");
  addCommon(exportCmd, o.exportC);
  exportCmd->add_flag("--no-in-between", o.exportNoInBetween, "Keyframes only");
  exportCmd->add_option("--out", o.exportOut, "Output directory")->capture_default_str();
  exportCmd->add_flag("--quiet", o.exportQuiet, "No progress line");

  addForceOption(exportCmd);
  commands.push_back({exportCmd, [state](int argc, char** argv) {
    return runInOutputDir(state->exportCmd, state->exportOut, {"cameras.json"},
                          [&] { return run(*state, argc, argv); });
  }});
}

}  // namespace hw::app
