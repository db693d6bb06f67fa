// The `publish` command: a baked walkthrough as a static web folder
// (session/publish.h, docs/publish.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "session/publish.h"

namespace hw::app {
namespace {

struct PublishCli {
  session::PublishOptions options;
};

int run(const PublishCli& o) {
  auto r = session::publish(o.options);
  if (!r) return fail(r.error().message);
  std::printf(
      "publish: %d keyframes, %d frames of %s (%dx%d), %.1f MB in %s; open it through a web "
      "server: cd %s && python3 -m http.server (docs/publish.md)\n",
      r->keyframes, r->frames, r->scene.c_str(), r->width, r->height, r->bytes / 1e6,
      o.options.outDir.c_str(), o.options.outDir.c_str());
  return 0;
}

}  // namespace

void addPublishCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<PublishCli>();
  PublishCli& o = *state;
  auto* cmd = app.add_subcommand(
      "publish",
      "Write a baked walkthrough (a keyframe database, 'hybridwalk bake') as a static web "
      "folder that plays it in a browser, warping the keyframes in WebGL 2 (docs/publish.md)");
  cmd->add_option("--keyframes", o.options.dbDir, "Keyframe database directory (hybridwalk bake)")
      ->required();
  cmd->add_option("--out", o.options.outDir, "Web folder to write (created)")->required();
  cmd->add_option("--path", o.options.pathFile,
                  "The camera path the database was baked from (default: the built-in path of "
                  "the scene the database names)");
  commands.push_back({cmd, [state](int, char**) { return run(*state); }});
}

}  // namespace hw::app
