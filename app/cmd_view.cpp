// The `view` command.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/option_checks.h"
#include "app/viewer.h"
#include "app/viewer_keys.h"
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
#include "scenes/catalogue.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "session/bake.h"
#include "session/export.h"
#include "session/keyframe_planner.h"
#include "session/presets.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct ViewCli {
  CLI::App* viewCmd = nullptr;
  Common viewC;
  // The preset's mode, LOD, hole pass, keyframe worker and frame pacing (the
  // walk's defaults), and the options that replace them; vo holds the
  // viewer's other options.
  PresetCli presetCli;
  app::ViewerOptions vo;
  std::string viewKeyframes;
  bool viewGeometry = false;
  bool viewNoHud = false;
};

// The viewer's share of the walk's options (a preset's, with the options given).
void setWalkShare(const session::WalkOptions& wo, app::ViewerOptions* vo) {
  app::applyWalkOptions(wo, vo);
  vo->renderHolesBudget = wo.renderHolesBudget;
  vo->keyframePacing = wo.keyframePacing;
  vo->keyframeBudgetScale = wo.keyframeBudgetScale;
  vo->keyframeStepsPerFrame = wo.keyframeStepsPerFrame;
  vo->keyframeFlushTriangles = wo.keyframeFlushTriangles;
  vo->frameBudgetMs = wo.frameBudgetMs;
  vo->frameBudgetAuto = wo.frameBudgetAuto;
  vo->frameBudgetQuantile = wo.frameBudgetQuantile;
  vo->frameBudgetWindow = wo.frameBudgetWindow;
}

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
    setWalkShare(wo, &o.vo);
    if (!o.viewC.path.empty()) {
      o.vo.playPath = o.viewC.path;
    }
    o.vo.sceneLabel = o.viewC.scene;
    o.vo.keyframeEvery = o.viewC.keyframeEvery;
    o.vo.hud = !o.viewNoHud;
    // The cheap inputs first: a wrong path file or database folder, or a
    // screenshot folder that cannot be written, fails before the scene loads
    // (the folder is made, as --out folders are).
    if (!o.vo.screenshotPath.empty()) {
      const std::string dir = std::filesystem::path(o.vo.screenshotPath).parent_path().string();
      if (!dir.empty())
        if (auto st = ensureWritableDir(dir); !st)
          return fail("--screenshot: " + st.error().message);
    }
    std::optional<scenes::CameraPath> played;
    if (!o.viewC.path.empty()) {
      auto pp = scenes::loadCameraPath(o.viewC.path);
      if (!pp) return fail(pp.error().message);
      played.emplace(std::move(*pp));
    }
    std::optional<keyframe::KeyframeDb> db;
    if (!o.viewKeyframes.empty()) {  // baked keyframes (docs/keyframe-db.md)
      auto d = keyframe::KeyframeDb::open(o.viewKeyframes);
      if (!d) return fail(d.error().message);
      db.emplace(std::move(*d));
    }
    auto s = scenes::loadScene(o.viewC.scene);
    if (!s) return fail(s.error().message);
    auto p = scenes::defaultPathFor(o.viewC.scene);
    if (!p) return fail(p.error().message);
    if (o.viewC.keyframeEvery > 0) p->keyframeEvery = o.viewC.keyframeEvery;
    if (db) {
      if (!played) played = *p;
      for (const char* opt : {"--width", "--height"}) {
        const int want = opt[2] == 'w' ? played->width : played->height;
        const int given = opt[2] == 'w' ? o.vo.width : o.vo.height;
        if (o.viewCmd->count(opt) > 0 && given != want)
          return fail(std::string(opt) + " " + std::to_string(given) + ": the database " +
                      o.viewKeyframes + " holds " + std::to_string(played->width) + "x" +
                      std::to_string(played->height) + " keyframes (omit " + opt +
                      " to take the database's size)");
      }
      o.vo.width = played->width;
      o.vo.height = played->height;
      // Scene, path and size must match; the LOD options, depth mode and frame
      // count are the database's own (they only decide what it holds).
      if (auto st = db->checkMatches(
              session::bakeProvenance(o.viewC.scene, s->triangleCount(), *played, played->frames,
                                      {}, kDefaultDepthMode),
              {"scene", "triangles", "path_hash", "resolution"});
          !st)
        return fail(st.error().message);
      db->setExpectation({[p = *played](int f) { return p.cameraAt(f); }, std::nullopt});
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
              "right mouse button held + W/A/S/D/Q/E (Shift x4, +/- speed); keys: " +
                  app::viewerKeyLine());
  PresetCli& pc = o.presetCli;
  addScenePath(viewCmd, o.viewC);
  addMaxMemoryOption(viewCmd);
  viewCmd->add_flag("--play", o.vo.play,
                    "Replay the camera path (--path, or the scene's default), one path frame per "
                    "frame, looping; any move takes over");
  viewCmd->add_option("--width", o.vo.width, "Window width, pixels")->check(CLI::Range(16, 8192))
      ->capture_default_str();
  viewCmd->add_option("--height", o.vo.height, "Window height, pixels")->check(CLI::Range(16, 8192))
      ->capture_default_str();
  addWalkOptionSet(
      viewCmd, &pc, viewRows(),
      "Settings to start from, as for walk: default (measured best on many scenes: --mode "
      "auto, --tau-px " +
          formatOptionNumber(session::presetOptions(session::Preset::Default).lod.tauParallaxPx) +
          ", region-local planarity, merged strips, keyframes built ahead on a worker thread, "
          "larger holes drawn by the geometry renderer within the walk's budget) or paper "
          "(Zheng et al. 1999 exactly: every frame hybrid, --tau 2^11, five-point stencil, no "
          "merging, keyframes rendered in the frame); options given replace the preset's, "
          "except that with paper an option departing from the paper is an error (--tau may "
          "vary)");
  viewCmd->add_flag("--geometry", o.viewGeometry, "Draw with the geometry renderer (--mode geometry)")
      ->excludes("--mode");
  viewCmd->add_flag("--no-hud", o.viewNoHud, "No on-screen text");
  viewCmd
      ->add_option("--exit-after", o.vo.exitAfterFrames,
                   "Quit after this many frames (scripted runs; 0 = when closed)")
      ->check(nonNegativeNumber())
      ->capture_default_str();
  viewCmd->add_option("--screenshot", o.vo.screenshotPath, "Write the last frame to this PNG on exit");
  viewCmd->add_option("--record", o.vo.recordPath,
                      "Camera path file for z (record) / Z (play) (default: hybridwalk_path.json)");
  viewCmd->add_option("--keys", o.vo.keys,
                      "Keys typed before the first frame, e.g. 'so'; '@N' types the keys after "
                      "it before frame N instead, e.g. 's@30p@60p' (PSNR of frames 30 and 60)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            auto k = app::parseScriptedKeys(v);
            return k ? std::string() : k.error().message;
          },
          "KEYS"));
  viewCmd->add_option("--keyframes", o.viewKeyframes,
                      "Warp keyframes baked by 'hybridwalk bake' from this scene and path instead of "
                      "rendering them while near the baked path (with --play, exactly the walk's "
                      "keyframe pairs); the window takes the database's size, the keyframes keep "
                      "the database's LOD");
  viewCmd->add_option("--frame-stats", o.vo.frameStatsPath,
                      "Write one CSV row per frame at exit: ms (time since the previous frame "
                      "ended), how it was drawn (mode: geometry, warp, keyframe), keyframe ms and "
                      "events (rendered in the frame = a stall, read, taken from the worker, "
                      "requested, waited for); the exit also prints the frame ms median / p95 / "
                      "max and the frames drawn each way");

  viewCmd
      ->add_option_function<std::string>(
          "--frames-on",
          [&o](const std::string& v) {
            o.vo.framesOn = v == "gpu"   ? app::ViewerOptions::FramesOn::Gpu
                            : v == "cpu" ? app::ViewerOptions::FramesOn::Cpu
                                         : app::ViewerOptions::FramesOn::Auto;
          },
          "Where frames drawn with OpenGL's warper (--warper gl, or auto on a GPU) are composed: "
          "gpu (composed, hole-filled and shown from a texture, never read back), cpu (read back "
          "and composed as walk does; the same pixels) or auto (gpu unless OpenGL is a CPU "
          "rasteriser such as llvmpipe, where cpu measured faster)")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->default_str("auto");
  setGroups(viewCmd, {{"Essentials", {"--help", "--scene", "--path", "--play", "--width", "--height",
                                      "--geometry", "--no-hud", "--exit-after", "--screenshot",
                                      "--record", "--keys"}},
                      {"Keyframes", {"--keyframes", "--keyframe-every"}},
                      {"Timing", {"--frame-stats", "--frames-on"}}});
  commands.push_back({viewCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
