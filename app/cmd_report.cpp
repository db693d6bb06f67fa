// The `report` command: a walk's page (index.html, psnr_along_path.png)
// rebuilt from its report.json, and its summary printed.
#include "app/commands.h"

#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "report/walk_page.h"

namespace hw::app {
namespace {

int runReport(const std::string& dir) {
  nlohmann::json summary;
  if (auto st = report::writeWalkPage(dir, &summary); !st) return fail(st.error().message);
  const report::WalkSummaryText t = report::walkSummaryText(summary);
  std::printf("%s\n", t.headline.c_str());
  for (const auto& d : t.details) std::printf("  %s\n", d.c_str());
  std::printf("page: %s/index.html\n", dir.c_str());
  return 0;
}

}  // namespace

void addReportCommand(CLI::App& app, Commands& commands) {
  auto dir = std::make_shared<std::string>();
  auto* c = app.add_subcommand(
      "report", "Rebuild a walk's page (DIR/index.html, psnr_along_path.png) from DIR/report.json "
                "and print its summary");
  c->add_option("DIR", *dir, "A walk's output folder (walk --out)")->required();
  commands.push_back({c, [dir](int, char**) { return runReport(*dir); }});
}

}  // namespace hw::app
