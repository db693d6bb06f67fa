// The `scenes` command.
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
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "app/cli_common.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct ScenesCli {
  CLI::App* scenesCmd = nullptr;
  CLI::App* fetchCmd = nullptr;
  CLI::App* listCmd = nullptr;
  std::string cacheDir = scenes::defaultSceneCacheDir();
  bool fetchQuiet = false;
  bool fetchOutdoor = false;
};

int runFetchCmd(ScenesCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    if (auto st = scenes::fetchScenePackages(o.cacheDir, !o.fetchQuiet, o.fetchOutdoor); !st)
      return fail(st.error().message);
    auto maps = scenes::listQ3Maps(scenes::defaultPk3Paths(o.cacheDir));
    if (!maps) return fail(maps.error().message);
    std::printf("scenes: %zu OpenArena maps in %s; use --scene q3:MAPNAME (e.g. q3:oa_dm5)\n",
                maps->size(), o.cacheDir.c_str());
    return 0;
}

int runListCmd(ScenesCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
  for (const auto& e : scenes::listScenes(o.cacheDir))
    std::printf("%-9s %-30s %s%s\n", e.kind.c_str(), e.spec.c_str(),
                e.fetched ? "" : "NOT FETCHED: ", e.note.c_str());
  return 0;
}

}  // namespace

void addScenesCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<ScenesCli>();
  ScenesCli& o = *state;
  // scenes fetch | list
  auto* scenesCmd = o.scenesCmd = app.add_subcommand("scenes", "Real scenes from Debian packages");
  scenesCmd->require_subcommand(1);
  auto* fetchCmd = o.fetchCmd = scenesCmd->add_subcommand(
      "fetch", "Download the OpenArena map, texture and data packages with apt-get download and "
               "unpack them into the cache (nothing is installed system-wide; idempotent). Maps "
               "are then named q3:MAPNAME");
  fetchCmd->add_option("--dir", o.cacheDir, "Cache directory ($HYBRIDWALK_CACHE overrides the default)")
      ->capture_default_str();
  fetchCmd->add_flag("--quiet", o.fetchQuiet, "No progress");
  fetchCmd->add_flag("--outdoor", o.fetchOutdoor,
                     "Also the outdoor scenes: torcs-data (TORCS tracks, torcs:NAME, 333 MB) and "
                     "morse-simulator-data (MORSE environments, morse:ENV/FILE, 82 MB)");
  auto* listCmd = o.listCmd = scenesCmd->add_subcommand("list", "List every scene by kind (built-in, q3: maps, torcs: tracks, morse: environments), "
              "marking the kinds not fetched yet");
  listCmd->add_option("--dir", o.cacheDir, "Cache directory")->capture_default_str();

  commands.push_back({fetchCmd, [state](int argc, char** argv) { return runFetchCmd(*state, argc, argv); }});
  commands.push_back({listCmd, [state](int argc, char** argv) { return runListCmd(*state, argc, argv); }});
}

}  // namespace hw::app
