// The `view` command.
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
#include "bench/slurm.h"
#include "session/schedule_calibration.h"
#include "bench/schedule_oracle.h"
#include "bench/schedule_study.h"
#include "bench/stress.h"
#include "bench/sweep.h"
#include "session/presets.h"
#include "session/walk.h"
#include "report/schedule_plots.h"
#include "report/walk_plots.h"
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
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "app/cli_common.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct ViewCli {
  CLI::App* viewCmd = nullptr;
  Common viewC;
  // The preset's mode, LOD and keyframe worker (the defaults), and the
  // options that replace them; vo holds the viewer's other options.
  PresetCli presetCli;
  app::ViewerOptions vo;
  std::string viewKeyframes;
  bool viewGeometry = false;
  bool viewNoHud = false;
  std::string viewPacing = "time";
  FrameBudgetCli viewFb;
};

int run(ViewCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    session::Preset preset = session::Preset::Default;
    session::WalkOptions wo;
    if (const int code = applyPresetCli(o.viewCmd, o.presetCli, &preset, &wo); code != 0)
      return code;
    if (o.viewGeometry) wo.mode = session::FrameMode::Geometry;
    if (const int code = refusePaperDeparture(preset, wo,
                                              [&](const std::string& option) {
                                                return option == "--mode" && o.viewGeometry
                                                           ? std::string("--geometry")
                                                           : option;
                                              });
        code != 0)
      return code;
    app::applyWalkOptions(wo, &o.vo);
    if (!o.viewC.path.empty()) {
      o.vo.playPath = o.viewC.path;
    }
    o.vo.sceneLabel = o.viewC.scene;
    using VP = app::ViewerOptions::KeyframePacing;
    o.vo.keyframePacing = o.viewPacing == "time"     ? VP::Time
                        : o.viewPacing == "slices" ? VP::Slices
                        : o.viewPacing == "steps"  ? VP::Steps
                                                 : VP::None;
    o.vo.frameBudgetMs = o.viewFb.ms();
    o.vo.frameBudgetAuto = o.viewFb.isAuto();
    o.vo.frameBudgetQuantile = o.viewFb.quantile;
    o.vo.frameBudgetWindow = o.viewFb.window;
    o.vo.hud = !o.viewNoHud;
    auto s = scenes::loadScene(o.viewC.scene);
    if (!s) return fail(s.error().message);
    auto p = scenes::defaultPathFor(o.viewC.scene);
    if (!p) return fail(p.error().message);
    if (!o.viewKeyframes.empty()) {  // baked keyframes (docs/keyframe-db.md)
      auto db = keyframe::KeyframeDb::open(o.viewKeyframes);
      if (!db) return fail(db.error().message);
      scenes::CameraPath played = *p;
      if (!o.viewC.path.empty()) {
        auto pp = scenes::loadCameraPath(o.viewC.path);
        if (!pp) return fail(pp.error().message);
        played = std::move(*pp);
      }
      for (const char* opt : {"--width", "--height"}) {
        const int want = opt[2] == 'w' ? played.width : played.height;
        const int given = opt[2] == 'w' ? o.vo.width : o.vo.height;
        if (o.viewCmd->count(opt) > 0 && given != want)
          return fail(std::string(opt) + " " + std::to_string(given) + ": the database " +
                      o.viewKeyframes + " holds " + std::to_string(played.width) + "x" +
                      std::to_string(played.height) + " keyframes (omit " + opt +
                      " to take the database's size)");
      }
      o.vo.width = played.width;
      o.vo.height = played.height;
      // Scene, path and size must match; the LOD options, depth mode and frame
      // count are the database's own (they only decide what it holds).
      if (auto st = db->checkMatches(
              session::bakeProvenance(o.viewC.scene, s->triangleCount(), played, played.frames, {},
                                    kDefaultDepthMode),
              {"scene", "triangles", "path_hash", "resolution"});
          !st)
        return fail(st.error().message);
      db->setExpectation({[p = played](int f) { return p.cameraAt(f); }, std::nullopt});
      if (auto st = db->checkFiles(); !st) return fail(st.error().message);
      o.vo.keyframeDb = std::make_shared<keyframe::KeyframeDb>(std::move(*db));
    }
    return app::runViewer(*s, *p, o.vo);
}

}  // namespace

void addViewCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<ViewCli>();
  ViewCli& o = *state;
  // view
  auto* viewCmd = o.viewCmd = app.add_subcommand(
      "view", "Interactive viewer (GLFW window; needs a display, e.g. xvfb-run): fly with the "
              "right mouse button held + W/A/S/D/Q/E (Shift x4, +/- speed), g hybrid/geometry, "
              "w wireframe/quad outlines, s statistics, o overlay, m hole mask, p PSNR, c "
              "screenshot, z/Z record/play path, space home, h help, Esc quit");
  PresetCli& pc = o.presetCli;
  viewCmd->add_option("--scene", o.viewC.scene, scenes::sceneSpecHelp())->capture_default_str();
  viewCmd->add_option("--path", o.viewC.path,
                      "Camera path JSON (docs/camera-path.md) to play and to start from (default: "
                      "the scene's own)");
  viewCmd->add_flag("--play", o.vo.play,
                    "Replay the camera path (--path, or the scene's default), one path frame per "
                    "frame, looping; any move takes over");
  viewCmd->add_option("--width", o.vo.width, "Window width, pixels")->check(CLI::Range(16, 8192))
      ->capture_default_str();
  viewCmd->add_option("--height", o.vo.height, "Window height, pixels")->check(CLI::Range(16, 8192))
      ->capture_default_str();
  viewCmd->add_option("--preset", pc.preset,
                      "Settings to start from, as for walk: default (measured best on many "
                      "scenes: --mode auto, --tau-px " + PresetCli::formatNumber(pc.defaults.lod.tauParallaxPx) +
                      ", region-local planarity, merged strips, keyframes built ahead on a worker "
                      "thread) or paper (Zheng et al. 1999 exactly: every frame hybrid, --tau "
                      "2^11, five-point stencil, no merging, keyframes rendered in the frame); "
                      "options given replace the preset's, except that with paper an option "
                      "departing from the paper is an error (--tau may vary)")
      ->check(CLI::IsMember({"default", "paper"}))
      ->capture_default_str();
  viewCmd->add_option("--mode", pc.mode,
                      "How frames are drawn: auto (every 10 frames hybrid or geometry, whichever "
                      "costs less as measured in this session, geometry when about even; the walk's "
                      "rule), hybrid (every frame warped from two keyframes, the paper's) or "
                      "geometry (the geometry renderer, as --geometry); g switches between hybrid "
                      "and geometry by hand (and ends auto)")
      ->check(CLI::IsMember({"auto", "hybrid", "geometry"}))
      ->capture_default_str();
  viewCmd->add_flag("--geometry", o.viewGeometry, "Draw with the geometry renderer (--mode geometry)")
      ->excludes("--mode");
  viewCmd->add_flag("--no-hud", o.viewNoHud, "No on-screen text");
  viewCmd->add_option("--exit-after", o.vo.exitAfterFrames,
                      "Quit after this many frames (scripted runs; 0 = when closed)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  viewCmd->add_option("--screenshot", o.vo.screenshotPath, "Write the last frame to this PNG on exit");
  viewCmd->add_option("--record", o.vo.recordPath,
                      "Camera path file for z (record) / Z (play) (default: hybridwalk_path.json)");
  viewCmd->add_option("--keys", o.vo.keys, "Keys typed before the first frame, e.g. 'so'");
  viewCmd->add_option("--tau", pc.tau,
                      "LOD threshold on |Δ²z'| in z' units (2^24 scale), '2^11' or '2048' form; "
                      "replaces --tau-px (the paper's threshold; --preset paper: 2^11)");
  viewCmd->add_option("--tau-px", pc.tauPx,
                      "LOD threshold as parallax error: pixels per scene unit of camera motion (the "
                      "same meaning indoors and out); 0 = use --tau")
      ->check(CLI::NonNegativeNumber)
      ->excludes("--tau")
      ->capture_default_str();
  viewCmd->add_option("--criterion", pc.criterion,
                      "Planarity test: five-point (paper's eq. 3) or per-axis-max (max(|Δ²x|,|Δ²y|))")
      ->check(CLI::IsMember({"five-point", "per-axis-max"}))
      ->capture_default_str();
  viewCmd->add_option("--planarity", pc.planarity,
                      "Planarity test: stencil (paper: Δ² stencils reach across region borders) or "
                      "region-local (second differences only inside the region)")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  viewCmd->add_flag("--merge-strips,!--no-merge-strips", pc.mergeStrips,
                    std::string("Merge adjacent coplanar leaves (within max(tau/4, 4) z' units) "
                                "into larger quads, or not (default: ") +
                        (pc.defaults.lod.mergeStrips ? "merge" : "not") + ")");
  viewCmd->add_option("--tau-gradient", pc.tauGradient, tauGradientHelp())->capture_default_str();
  viewCmd->add_option("--keyframes", o.viewKeyframes,
                      "Warp keyframes baked by 'hybridwalk bake' from this scene and path instead of "
                      "rendering them while near the baked path (with --play, exactly the walk's "
                      "keyframe pairs); the window takes the database's size, the keyframes keep "
                      "the database's LOD");
  viewCmd->add_flag("--async-keyframes,!--sync-keyframes", pc.asyncKeyframes,
                    "Render and mesh keyframes ahead on a worker thread with a second OpenGL "
                    "context (a hidden window): the viewer requests the next keyframe and warps "
                    "the ones it has until it is ready instead of rendering it in the frame "
                    "(keyframes are identical; when one arrives changes), or render them in the "
                    "frame that needs them. Lost (no keyframe within reach) it waits for the one "
                    "in flight if that is within reach, else renders one in the frame; baked "
                    "--keyframes are read as without it. With s s, the statistics show keyframe "
                    "stalls and waits (default: " +
                        std::string(pc.defaults.asyncKeyframes ? "ahead on the worker" : "in the frame") +
                        ")");
  viewCmd->add_option("--keyframe-pacing", o.viewPacing,
                      "With --async-keyframes, as for walk: time (per frame the worker may take "
                      "budget-scale x last build ms / F of wall time, F = the frames the "
                      "viewer takes per keyframe: measured from its requests, at most the frames "
                      "until it would be lost, starting from keyframe_every / 2 of the path), "
                      "slices (the same budget, run after each frame is shown, counted in its "
                      "time), steps (--keyframe-steps-per-frame steps per frame) or none (as fast "
                      "as it can)")
      ->check(CLI::IsMember({"time", "slices", "steps", "none"}))
      ->capture_default_str();
  viewCmd->add_option("--keyframe-budget-scale", o.vo.keyframeBudgetScale,
                      "With --keyframe-pacing time or slices: the worker's time per frame as a "
                      "multiple of its even share (> 1 lets it get ahead)")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  viewCmd->add_option("--keyframe-steps-per-frame", o.vo.keyframeStepsPerFrame,
                      "With --keyframe-pacing steps: worker steps (a flushed piece of the render, "
                      "the readback, a mesh-build step) per frame")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  viewCmd->add_option("--keyframe-flush-triangles", o.vo.keyframeFlushTriangles,
                      "With --async-keyframes: the worker flushes its keyframe render after about "
                      "this many triangles (0 = one flush)")
      ->capture_default_str();
  addFrameBudgetOptions(viewCmd, o.viewFb,
                        "after a frame is shown the viewer waits until this many ms have passed "
                        "since it started, so frames are presented at a steady cadence (pacing "
                        "only: the viewer does not refresh stale pixels)");
  viewCmd->add_option("--frame-stats", o.vo.frameStatsPath,
                      "Write one CSV row per frame at exit: ms (time since the previous frame "
                      "ended), how it was drawn (mode: geometry, warp, keyframe), keyframe ms and "
                      "events (rendered in the frame = a stall, read, taken from the worker, "
                      "requested, waited for); the exit also prints the frame ms median / p95 / "
                      "max and the frames drawn each way");

  setGroups(viewCmd, {{"Essentials", {"--help", "--scene", "--path", "--play", "--width", "--height",
                                      "--preset", "--mode", "--geometry", "--no-hud",
                                      "--exit-after", "--screenshot", "--record", "--keys"}},
                      {"Level of detail", {"--tau", "--tau-px", "--criterion", "--planarity",
                                           "--merge-strips", "--no-merge-strips",
                                           "--tau-gradient"}},
                      {"Keyframes", {"--keyframes", "--async-keyframes", "--sync-keyframes",
                                     "--keyframe-pacing", "--keyframe-budget-scale",
                                     "--keyframe-steps-per-frame", "--keyframe-flush-triangles"}},
                      {"Timing", {"--frame-budget-ms", "--frame-budget-quantile",
                                  "--frame-budget-window", "--frame-stats"}}});
  commands.push_back({viewCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
