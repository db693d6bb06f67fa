// The defaults --help shows, for every option of every command of the real
// program (the parser app/main.cpp builds): the shown default is the value of
// the field the option is bound to, an option bound to a field with a value
// shows it, and the shown default given back on the command line parses and
// changes nothing the command reads.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/cli_common.h"
#include "app/commands.h"

namespace hw::app {
namespace {

// The program's parser with every command, as main.cpp builds it. The
// commands keep their bound state alive.
struct Program {
  CLI::App app{"hybridwalk"};
  Commands commands;
  Program() {
    app.formatter(std::make_shared<GroupedHelp>());
    app.require_subcommand(1);
    addAllCommands(app, commands);
  }
};

// A command's path from the top ("walk", "scenes fetch").
std::vector<std::vector<std::string>> commandPaths(const CLI::App& app,
                                                   std::vector<std::string> prefix = {}) {
  std::vector<std::vector<std::string>> out;
  for (const CLI::App* sub : app.get_subcommands({})) {
    auto path = prefix;
    path.push_back(sub->get_name());
    if (sub->get_subcommands({}).empty()) out.push_back(path);
    else for (auto& p : commandPaths(*sub, path)) out.push_back(p);
  }
  return out;
}

CLI::App* commandAt(CLI::App* app, const std::vector<std::string>& path) {
  for (const std::string& name : path) app = app->get_subcommand(name);
  return app;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : " ") + x;
  return s;
}

// What a command needs on every command line (its required options and
// positionals), so that it parses with one more option.
const std::map<std::string, std::vector<std::string>> kRequired = {
    {"bake", {"--out", "db"}},
    {"check-quads", {"--out", "o"}},
    {"compare", {"a.png", "b.png"}},
    {"publish", {"--keyframes", "db", "--out", "web"}},
    {"report", {"dir"}},
};

// The command line `path + required + extra`, parsed; throws what CLI11 throws.
std::unique_ptr<Program> parse(const std::vector<std::string>& path,
                               const std::vector<std::string>& extra) {
  auto p = std::make_unique<Program>();
  std::vector<std::string> args = path;
  if (auto it = kRequired.find(joined(path)); it != kRequired.end())
    args.insert(args.end(), it->second.begin(), it->second.end());
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them reversed
  p->app.parse(reversed);
  return p;
}

// The value of every field the command's options are bound to, as text.
std::map<std::string, std::string> boundValues(CLI::App* cmd) {
  std::map<std::string, std::string> out;
  for (CLI::Option* o : cmd->get_options()) {
    if (o->get_name().empty()) continue;
    o->capture_default_str();
    out[o->get_name()] = o->get_default_str();
  }
  return out;
}

// The value the option's field holds, as text ("" when it is bound to none).
std::string fieldValue(CLI::Option* o) {
  const std::string shown = o->get_default_str();
  o->capture_default_str();
  const std::string field = o->get_default_str();
  o->default_str(shown);
  return field;
}

// A value option the user sees (hidden ones, in no group, are internal).
bool takesValue(const CLI::Option* o) { return o->get_expected_min() > 0 && !o->get_group().empty(); }

TEST(HelpDefaults, EveryCommandIsChecked) {
  Program p;
  const auto paths = commandPaths(p.app);
  EXPECT_GE(paths.size(), 19u);  // 18 commands, scenes has two
  for (const auto& path : paths) {
    SCOPED_TRACE(joined(path));
    EXPECT_NO_THROW(parse(path, {})) << "the command does not parse with only kRequired";
  }
}

// The default --help shows is the field's value; a field with a value shows it.
TEST(HelpDefaults, ShownDefaultIsTheField) {
  Program p;
  for (const auto& path : commandPaths(p.app)) {
    for (CLI::Option* o : commandAt(&p.app, path)->get_options()) {
      if (o->get_lnames().empty() || !takesValue(o)) continue;
      SCOPED_TRACE(joined(path) + " " + o->get_name());
      const std::string shown = o->get_default_str();
      const std::string field = fieldValue(o);
      if (!field.empty() && field != "[]") {  // "[]": an empty list
        EXPECT_EQ(shown, field) << "--help shows a default the field does not hold";
      }
    }
  }
}

// The default --help shows, given on the command line, parses and leaves every
// field of the command as it was without it.
TEST(HelpDefaults, GivingTheShownDefaultChangesNothing) {
  Program shape;
  int checked = 0;
  for (const auto& path : commandPaths(shape.app)) {
    const auto none = parse(path, {});
    const auto base = boundValues(commandAt(&none->app, path));
    for (CLI::Option* o : commandAt(&shape.app, path)->get_options()) {
      if (o->get_lnames().empty() || !takesValue(o) || o->get_default_str().empty()) continue;
      const std::string name = "--" + o->get_lnames().front();
      SCOPED_TRACE(joined(path) + " " + name + " " + o->get_default_str());
      std::unique_ptr<Program> given;
      ASSERT_NO_THROW(given = parse(path, {name, o->get_default_str()}));
      EXPECT_EQ(boundValues(commandAt(&given->app, path)), base);
      ++checked;
    }
  }
  EXPECT_GE(checked, 100);
}

}  // namespace
}  // namespace hw::app
