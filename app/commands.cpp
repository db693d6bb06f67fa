// The program's command list, shared by app/main.cpp and the help tests.
#include "app/commands.h"

namespace hw::app {

void addAllCommands(CLI::App& app, Commands& commands) {
  for (auto add :
       {addWalkCommand, addRenderCommand, addLodCommand, addSweepCommand, addBakeCommand,
        addBenchCommand, addExportCommand, addViewCommand, addCompareCommand, addStressCommand,
        addScheduleStudyCommand, addScheduleOracleCommand, addScenesCommand, addPathCommand,
        addCheckQuadsCommand, addPublishCommand, addReportCommand, addInfoCommand})
    add(app, commands);
}

}  // namespace hw::app
