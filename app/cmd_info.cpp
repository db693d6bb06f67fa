// The `info` command: the headless OpenGL backends this build has, every way
// to get a context on this machine (EGL's surfaceless platform, each EGL
// device, OSMesa) with its strings and whether it gives 4.5 core, and which
// one `--gl auto` takes (docs/gpu.md).
#include "app/commands.h"

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "app/cli_common.h"
#include "core/gl/context.h"

namespace hw::app {
namespace {

int runInfo() {
  using gl::Backend;
  const gl::HeadlessOptions chosen = gl::headlessOptions();
  const char* env = std::getenv("HYBRIDWALK_GL");
  std::printf("headless OpenGL backends built: egl %s, osmesa %s\n",
              gl::backendBuilt(Backend::Egl) ? "yes" : "no",
              gl::backendBuilt(Backend::OsMesa) ? "yes" : "no");
  std::printf("HYBRIDWALK_GL: %s\n", env && *env ? env : "unset");
  std::printf("\n");
  for (const gl::BackendProbe& p : gl::probeHeadlessBackends()) {
    const std::string how = p.backend == Backend::OsMesa ? "--gl osmesa"
                            : p.eglDevice >= 0 ? "--gl egl --gl-device " + std::to_string(p.eglDevice)
                                               : "--gl egl";
    std::printf("%s  [%s]\n", p.name.c_str(), how.c_str());
    if (p.core45) {
      std::printf("  vendor:   %s\n  renderer: %s\n  version:  %s\n  4.5 core: yes\n",
                  p.vendor.c_str(), p.renderer.c_str(), p.version.c_str());
    } else {
      std::printf("  4.5 core: no (%s)\n", p.error.c_str());
    }
  }
  // What a rendering command with these settings does: create the context.
  gl::HeadlessOptions asked = chosen;
  auto ctx = gl::createHeadlessContext(asked);
  std::printf("\n");
  if (!ctx) {
    std::printf("--gl %s%s: no context\n", gl::backendName(asked.backend),
                asked.eglDevice >= 0 ? (" --gl-device " + std::to_string(asked.eglDevice)).c_str() : "");
    return fail(ctx.error().message);
  }
  std::printf("--gl %s%s takes: %s (%s, %s)\n", gl::backendName(asked.backend),
              asked.eglDevice >= 0 ? (" --gl-device " + std::to_string(asked.eglDevice)).c_str() : "",
              (*ctx)->backend().c_str(), (*ctx)->renderer().c_str(), (*ctx)->version().c_str());
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, Commands& commands) {
  auto* c = app.add_subcommand(
      "info", "List the headless OpenGL backends and EGL devices (vendor, renderer, version, "
              "whether each gives OpenGL 4.5 core) and which one --gl auto takes (docs/gpu.md)");
  addGlOptions(c);
  commands.push_back({c, [](int, char**) { return runInfo(); }});
}

}  // namespace hw::app
