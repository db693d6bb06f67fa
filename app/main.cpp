// The `hybridwalk` program: a dispatcher over the subcommands in app/cmd_*.cpp.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/cli_common.h"
#include "app/option_checks.h"
#include "app/commands.h"
#include "core/memory.h"
#include "core/safe_io.h"

namespace {

// CLI11 only says "A subcommand is required" for a misspelt command; name it.
bool knownCommand(const CLI::App& parent, int argc, char** argv, int argi) {
  if (argi >= argc || argv[argi][0] == '-') return true;
  std::string names;
  for (const CLI::App* sub : parent.get_subcommands({})) {
    if (sub->get_name() == argv[argi]) return true;
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  std::vector<std::string> known;
  for (const CLI::App* sub : parent.get_subcommands({})) known.push_back(sub->get_name());
  const std::string near = hw::app::closestName(argv[argi], known);
  std::fprintf(stderr, "hybridwalk: error: unknown command '%s'%s (expected one of: %s; see --help)\n",
               argv[argi], near.empty() ? "" : ("; did you mean " + near + "?").c_str(),
               names.c_str());
  return false;
}

int runMain(int argc, char** argv) {
  using namespace hw::app;  // NOLINT
  CLI::App app{
      "hybridwalk: real-time walkthroughs that mix geometry and images (Zheng, Bao, Peng & Sun "
      "1999).\nKeyframes are drawn with OpenGL (headless EGL or OSMesa, --gl); every frame between two "
      "keyframes is backward-warped from their level-of-detail quad meshes.\nUnits: distances "
      "are the scene's; tau is in z' units of the 24-bit depth buffer (2^24 scale, eq. 2; the "
      "paper uses 2^11 and 2^15); times in ms."};
  app.formatter(std::make_shared<GroupedHelp>());
  app.require_subcommand(1);
  app.set_version_flag("--version", "hybridwalk 0.1");

  Commands commands;
  addAllCommands(app, commands);

  if (!knownCommand(app, argc, argv, 1)) return kExitUsage;
  if (argc > 1 && std::string(argv[1]) == "scenes" &&
      !knownCommand(*app.get_subcommand("scenes"), argc, argv, 2))
    return kExitUsage;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return reportParseError(app, e);
  }
  if (const std::string err = checkParsedOptions(app); !err.empty()) {
    std::fprintf(stderr, "hybridwalk: error: %s\n", err.c_str());
    return kExitUsage;
  }
  for (const Command& c : commands)
    if (c.cli->parsed()) return c.run(argc, argv);
  return fail("no command was given (see --help)");
}

}  // namespace

// Every subcommand runs inside one guard: an exception that escapes (out of
// memory above all) becomes one line and exit 1, with temporaries removed,
// instead of std::terminate's abort.
int main(int argc, char** argv) {
  hw::fixMallocMmapThreshold();  // flat RSS in long walks (core/memory.h)
  hw::dieWithParentIfWorker();   // a --workers chunk stops when its parent does
  hw::installSignalCleanup();    // SIGINT/SIGTERM: temporaries removed, exit 130/143
  try {
    return runMain(argc, argv);
  } catch (const std::bad_alloc&) {
    hw::removeRegisteredTemporaries();
    std::fprintf(stderr,
                 "hybridwalk: error: out of memory (an input asked for more than this machine "
                 "has; see docs/bad-input.md for the limits)\n");
  } catch (const std::exception& e) {
    hw::removeRegisteredTemporaries();
    std::fprintf(stderr, "hybridwalk: error: internal error: %s\n", e.what());
  } catch (...) {
    hw::removeRegisteredTemporaries();
    std::fprintf(stderr, "hybridwalk: error: internal error: unknown exception\n");
  }
  return hw::app::kExitRuntime;
}
