#pragma once
// The subcommands of the `hybridwalk` program, one file each (app/cmd_*.cpp):
// each adds its options to the parser, bound to its own state, and a runner.
#include <CLI/CLI.hpp>

#include <functional>
#include <vector>

namespace hw::app {

struct Command {
  CLI::App* cli = nullptr;                  // run when this (sub)command was parsed
  std::function<int(int, char**)> run;      // exit code
};
using Commands = std::vector<Command>;

void addWalkCommand(CLI::App& app, Commands& commands);
void addRenderCommand(CLI::App& app, Commands& commands);
void addLodCommand(CLI::App& app, Commands& commands);
void addSweepCommand(CLI::App& app, Commands& commands);
void addBakeCommand(CLI::App& app, Commands& commands);
void addBenchCommand(CLI::App& app, Commands& commands);
void addExportCommand(CLI::App& app, Commands& commands);
void addViewCommand(CLI::App& app, Commands& commands);
void addCompareCommand(CLI::App& app, Commands& commands);
void addStressCommand(CLI::App& app, Commands& commands);
void addScheduleStudyCommand(CLI::App& app, Commands& commands);
void addScheduleOracleCommand(CLI::App& app, Commands& commands);
void addScenesCommand(CLI::App& app, Commands& commands);
void addPathCommand(CLI::App& app, Commands& commands);
void addCheckQuadsCommand(CLI::App& app, Commands& commands);
void addPublishCommand(CLI::App& app, Commands& commands);
void addReportCommand(CLI::App& app, Commands& commands);
void addInfoCommand(CLI::App& app, Commands& commands);

// Every command above, in the order `hybridwalk --help` lists them: the
// program's parser (app/main.cpp) and the tests that check its help.
void addAllCommands(CLI::App& app, Commands& commands);

}  // namespace hw::app
