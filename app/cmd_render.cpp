// The `render` command.
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
#include "scenes/catalogue.h"
#include "scenes/outdoor_scenes.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "app/cli_common.h"

namespace hw::app {
namespace {

using nlohmann::json;

int runRender(const Common& o, const std::string& outDir, bool quiet) {
  auto in = loadInputs(o);
  if (!in) return fail(in.error().message);
  if (auto st = ensureWritableDir(outDir); !st) return fail(st.error().message);
  keyframe::RenderOptions ropt;
  ropt.depthMode = depthModeOf(o.depth);
  auto r = keyframe::GeometryRenderer::create(in->scene, ropt);
  if (!r) return fail(r.error().message);
  const int frames = o.frames > 0 ? std::min(o.frames, in->path.frames) : in->path.frames;
  json first;  // where the first frame's eye stands, and how much of it is sky or void
  {
    keyframe::Keyframe kf;
    const Camera c0 = in->path.cameraAt(0);
    if (auto s = (*r)->renderKeyframe(c0, kf); !s) return fail(s.error().message);
    std::size_t empty = 0;
    for (std::uint8_t c : kf.covered.pixels()) empty += c == 0;
    const scenes::TriangleGrid grid(in->scene);
    const auto eye = scenes::checkEye(grid, c0.eye);
    const double pixels = static_cast<double>(kf.covered.pixels().size());
    first = {{"empty_fraction", static_cast<double>(empty) / pixels},
             {"sky_or_void_fraction",
              scenes::openViewFraction(grid, c0.eye, c0.forward, in->path.fovYDeg,
                                       in->path.farPlane, 64)},
             {"floor_drop", eye.floorDrop ? json(*eye.floorDrop) : json(nullptr)},
             {"clearance", eye.clearance}};
  }
  Image<Rgba8> img;
  json fr = json::array();
  std::vector<double> ms;
  Stopwatch progress, all;
  for (int i = 0; i < frames; ++i) {
    keyframe::RenderStats st;
    if (auto s = (*r)->renderColour(in->path.cameraAt(i), img, &st); !s) return fail(s.error().message);
    char name[32];
    std::snprintf(name, sizeof name, "%04d.png", i);
    if (auto s = writePng(outDir + "/" + name, img); !s) return fail(s.error().message);
    fr.push_back({{"index", i}, {"ms", st.drawMs + st.readbackMs}, {"draw_ms", st.drawMs},
                  {"readback_ms", st.readbackMs}, {"meshes_drawn", st.meshesDrawn},
                  {"triangles_drawn", st.trianglesDrawn}});
    ms.push_back(st.drawMs + st.readbackMs);
    if (!quiet && (progress.ms() > 1000 || i + 1 == frames)) {
      progress.restart();
      std::fprintf(stderr, "\rrender: frame %d/%d, ETA %.0f s   %s", i + 1, frames,
                   all.ms() / 1000.0 / (i + 1) * (frames - i - 1), i + 1 == frames ? "\n" : "");
    }
  }
  json report = {{"frames", fr},
                 {"summary",
                  {{"scene", {{"name", in->scene.name}, {"triangles", in->scene.triangleCount()}}},
                   {"resolution", {in->path.width, in->path.height}},
                   {"depth_mode", o.depth},
                   {"first_frame", first},
                   {"ms", {{"median", median(ms)}, {"p95", percentile(ms, 95)}}},
                   {"machine", machineInfo(in->context->renderer(), in->context->version())}}}};
  if (auto s = writeFileAtomic(outDir + "/render.json", report.dump(1)); !s) return fail(s.error().message);
  std::printf("rendered %d frames of %s (%zu triangles) at %dx%d: median %.2f ms, p95 %.2f ms\n"
              "frames and render.json in %s\n",
              frames, in->scene.name.c_str(), in->scene.triangleCount(), in->path.width,
              in->path.height, median(ms), percentile(ms, 95), outDir.c_str());
  return 0;
}

struct RenderCli {
  CLI::App* render = nullptr;
  Common renderC;
  bool renderQuiet = false;
  std::string renderOut = "out/render";
};

int run(RenderCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
  return runRender(o.renderC, o.renderOut, o.renderQuiet);
}

}  // namespace

void addRenderCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<RenderCli>();
  RenderCli& o = *state;
  // render
  auto* render = o.render = app.add_subcommand(
      "render", "Geometry renderer only: each frame of the path as PNG, plus render.json "
                "with per-frame times and the scene's triangle count");
  addCommon(render, o.renderC);
  render->add_option("--out", o.renderOut, "Output directory")->capture_default_str();
  render->add_flag("--quiet", o.renderQuiet, "No progress line");

  addForceOption(render);
  commands.push_back({render, [state](int argc, char** argv) {
    return runInOutputDir(state->render, state->renderOut, {"render.json"},
                          [&] { return run(*state, argc, argv); });
  }});
}

}  // namespace hw::app
