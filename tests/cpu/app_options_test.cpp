// The option tables of walk, bake and view (app/options/walk_options.h):
// every default --help shows is the one a run gets, a preset's value is kept
// unless its option is given, and help lines fit in 100 columns.
#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli_common.h"
#include "app/options/walk_options.h"
#include "session/presets.h"

namespace hw::app {
namespace {

using session::Preset;
using session::WalkOptions;

struct Parsed {
  CLI::App app{"test"};
  WalkOptionSet set;
};

std::unique_ptr<Parsed> parse(const WalkRows& rows, const std::string& line) {
  auto p = std::make_unique<Parsed>();
  p->app.formatter(std::make_shared<GroupedHelp>());
  addWalkOptionSet(&p->app, &p->set, rows, "preset");
  p->app.parse(line);
  return p;
}

WalkOptions resolve(const WalkRows& rows, const std::string& line) {
  auto p = parse(rows, line);
  Preset preset = Preset::Default;
  WalkOptions out;
  resolveWalkOptions(&p->app, p->set, &preset, &out);
  return out;
}

// Every row's value as shown, one line each: two option structs agree on
// everything the command line sets when these are equal.
std::string shown(const WalkRows& rows, const WalkOptions& o) {
  std::string s;
  for (const auto& r : rows) s += r.name + "=" + r.show(o) + "\n";
  return s;
}

// The line of `help` that starts with option `name`.
std::string optionLine(const std::string& help, const std::string& name) {
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);)
    if ((line + " ").rfind("  " + name + " ", 0) == 0 || line.rfind("  " + name + ",", 0) == 0)
      return line;
  ADD_FAILURE() << name << " not in the help";
  return {};
}

struct Command {
  const char* name;
  WalkRows (*rows)();
};
const Command kCommands[] = {{"walk", walkRows}, {"bake", bakeRows}, {"view", viewRows}};

TEST(AppOptions, NoOptionGivenIsThePreset) {
  for (const Command& c : kCommands) {
    const WalkRows rows = c.rows();
    SCOPED_TRACE(c.name);
    EXPECT_EQ(shown(rows, resolve(rows, "")), shown(rows, session::presetOptions(Preset::Default)));
    EXPECT_EQ(shown(rows, resolve(rows, "--preset paper")),
              shown(rows, session::presetOptions(Preset::Paper)));
    // The presets differ where they should, so the comparison above can fail.
    EXPECT_NE(shown(rows, session::presetOptions(Preset::Default)),
              shown(rows, session::presetOptions(Preset::Paper)));
  }
}

// The default --help shows, given back on the command line, changes nothing:
// it is the value a run without the option gets.
TEST(AppOptions, ShownDefaultIsTheRealDefault) {
  const WalkOptions def = session::presetOptions(Preset::Default);
  for (const Command& c : kCommands) {
    const WalkRows rows = c.rows();
    const std::string help = parse(rows, "")->app.help();
    const std::string none = shown(rows, resolve(rows, ""));
    for (const auto& r : rows) {
      SCOPED_TRACE(std::string(c.name) + " " + r.name);
      const std::string v = r.show(def);
      std::string given;
      const std::string line = optionLine(help, r.name);
      if (!r.flag && v.empty()) {  // no default: another option is in effect (--tau-px)
        EXPECT_EQ(line.find('='), std::string::npos) << line;
        continue;
      }
      if (!r.flag) {
        given = r.name + " " + v;
        EXPECT_NE((line + " ").find("=" + v + " "), std::string::npos) << line;
      } else if (!r.negation.empty()) {
        given = v == "on" ? r.name : r.negation;
        EXPECT_NE(line.find(r.name + ", " + r.negation + " (default: " + v + ")"), std::string::npos)
            << line;
      } else {
        EXPECT_EQ(v, "off") << "a lone flag is off unless given";
        EXPECT_NE(shown(rows, resolve(rows, r.name)), none) << "the flag changes nothing";
        continue;
      }
      EXPECT_EQ(shown(rows, resolve(rows, given)), none) << given;
    }
  }
}

// With --preset paper, an option not given keeps the paper's value; one
// given replaces only what it sets.
TEST(AppOptions, PresetKeptUnlessGiven) {
  const WalkOptions paper = session::presetOptions(Preset::Paper);
  for (const Command& c : kCommands) {
    const WalkRows commandRows = c.rows();
    for (const auto& r : commandRows) {
      SCOPED_TRACE(std::string(c.name) + " " + r.name);
      // Every other option of the command keeps the paper's value.
      std::string given;
      if (!r.flag) given = r.name + " " + r.show(paper);
      else if (!r.negation.empty()) given = r.show(paper) == "on" ? r.name : r.negation;
      else continue;  // a lone flag only ever departs from the preset
      EXPECT_EQ(shown(commandRows, resolve(commandRows, "--preset paper " + given)),
                shown(commandRows, paper));
    }
  }
  const WalkRows rows = walkRows();
  const WalkOptions o = resolve(rows, "--preset paper --near 2 --no-render-holes");
  EXPECT_EQ(o.inBetween.nearDistance, 2.0);
  EXPECT_FALSE(o.renderHoles);
  EXPECT_EQ(o.lod.tau, paper.lod.tau);
  EXPECT_EQ(o.mode, paper.mode);
  const WalkOptions t = resolve(rows, "--tau 2^12");
  EXPECT_EQ(t.lod.tau, 4096.0);
  EXPECT_EQ(t.lod.tauParallaxPx, 0.0) << "--tau replaces the default --tau-px";
  EXPECT_EQ(resolve(rows, "--keyframe-cache-mb 64").keyframeCacheBytes, std::size_t{64} << 20);
  EXPECT_TRUE(resolve(rows, "--frame-budget-ms auto").frameBudgetAuto);
}

TEST(AppOptions, BadValuesAreParseErrors) {
  const WalkRows rows = walkRows();
  for (const char* line : {"--tau 2^x", "--tau -5", "--tau-gradient steep", "--mode fast",
                           "--keyframe-cache-mb 0", "--frame-budget-ms soon"}) {
    SCOPED_TRACE(line);
    EXPECT_THROW(parse(rows, line), CLI::ParseError);
  }
}

TEST(AppOptions, HelpFitsInOneHundredColumns) {
  for (const Command& c : kCommands) {
    std::istringstream lines(parse(c.rows(), "")->app.help());
    for (std::string line; std::getline(lines, line);) {
      int cols = 0;
      for (unsigned char ch : line) cols += (ch & 0xC0) != 0x80;
      EXPECT_LE(cols, GroupedHelp::kHelpColumns) << c.name << ": " << line;
      EXPECT_EQ(line.find("{false}"), std::string::npos) << line;
    }
  }
}

TEST(AppOptions, ClosestName) {
  const std::vector<std::string> known = {"--frames", "--frame-stats", "--tau", "--tau-px"};
  EXPECT_EQ(closestName("--frmaes", known), "--frames");
  EXPECT_EQ(closestName("--tua", known), "--tau");
  EXPECT_EQ(closestName("--warp-speed", known), "");
  EXPECT_EQ(closestName("wlak", {"walk", "view", "bake"}), "walk");
}

}  // namespace
}  // namespace hw::app
