// The `path` command: a scene's default camera path (or a path file, resized)
// as JSON on stdout, in the format --path reads (docs/camera-path.md).
#include "app/commands.h"

#include <cstdio>
#include <memory>
#include <string>

#include "app/cli_common.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"

namespace hw::app {
namespace {

struct PathCli {
  std::string scene = "indoor";
  std::string path;
  int width = 0, height = 0;
};

int runPath(const PathCli& o) {
  scenes::CameraPath p;
  if (!o.path.empty()) {
    auto r = scenes::loadCameraPath(o.path);
    if (!r) return fail(r.error().message);
    p = std::move(*r);
  } else {
    auto r = scenes::defaultPathFor(o.scene);
    if (!r) return fail(r.error().message);
    p = std::move(*r);
  }
  if (o.width > 0) p.width = o.width;
  if (o.height > 0) p.height = o.height;
  std::fputs(scenes::cameraPathToJson(p).c_str(), stdout);
  return 0;
}

}  // namespace

void addPathCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<PathCli>();
  auto* c = app.add_subcommand(
      "path", "Print a scene's default camera path as JSON (the --path format, "
              "docs/camera-path.md), to edit and pass back with --path");
  c->add_option("--scene", o->scene, "Scene, as for walk (its default path)")->capture_default_str();
  c->add_option("--path", o->path, "A camera path file to print instead (resized by the options)");
  c->add_option("--width", o->width, "Frame width, pixels (0 = the path's)")
      ->check(CLI::Range(0, 16384))
      ->capture_default_str();
  c->add_option("--height", o->height, "Frame height, pixels (0 = the path's)")
      ->check(CLI::Range(0, 16384))
      ->capture_default_str();
  commands.push_back({c, [o](int, char**) { return runPath(*o); }});
}

}  // namespace hw::app
