#pragma once
// The option tables of session::WalkOptions (app/options/option_table.h):
// walk, bake and view register their rows from here, so each option, its
// help, its unit and its group are written once, and its default is read
// from the Default preset (session/presets.h).
#include <CLI/CLI.hpp>

#include <string>

#include "app/options/option_table.h"
#include "session/presets.h"
#include "session/walk.h"

namespace hw::app {

using WalkRows = OptionRows<session::WalkOptions>;

// The frame mode and the LOD rows walk, bake and view share (--mode, --tau,
// --tau-px, --criterion, --planarity, --merge-strips, --split-misfit,
// --tau-gradient).
WalkRows modeRows();
WalkRows lodRows();
// Every row of `walk` (the shared ones included), in --help order.
WalkRows walkRows();
// The rows of `bake` (the LOD) and of `view` (mode, LOD, hole pass,
// keyframe worker, frame pacing; the viewer's own help where it differs).
WalkRows bakeRows();
WalkRows viewRows();

// --preset and the rows of one command, bound to `parsed` (which starts as
// the Default preset's options, the defaults --help shows).
struct WalkOptionSet {
  std::string preset = session::presetName(session::Preset::Default);
  session::WalkOptions parsed = session::presetOptions(session::Preset::Default);
  WalkRows rows;
};
// Registers --preset (with `presetHelp`) and `rows` on `c`.
void addWalkOptionSet(CLI::App* c, WalkOptionSet* s, WalkRows rows, const std::string& presetHelp);
// The preset's options, then every option of `s` given on `c`'s command line.
void resolveWalkOptions(const CLI::App* c, const WalkOptionSet& s, session::Preset* preset,
                        session::WalkOptions* out);
// The rows as Markdown tables, one per group (docs/walk-options.md).
std::string walkOptionsMarkdown();

}  // namespace hw::app
