#pragma once
// What the subcommands share: option groups bound to their structs (one
// place for each default), value parsers with the messages users see, the
// scene + path + GL context loader, and exit codes.
#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/chunked_runs.h"
#include "core/depth.h"
#include "core/gl/context.h"
#include "core/output_dir.h"
#include "core/result.h"
#include "session/keyframe_planner.h"
#include "session/presets.h"
#include "app/options/walk_options.h"
#include "keyframe/lod_builder.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "scenes/scene.h"

namespace hw::app {

constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

// "hybridwalk: error: MSG" on stderr; returns kExitRuntime.
int fail(const std::string& msg);
// The same for options that cannot go together or a value out of its set;
// returns kExitUsage.
int failUsage(const std::string& msg);
// A command line CLI11 refused: --help and --version print and return 0;
// anything else is "hybridwalk: error: ..." (an unknown option with "did you
// mean --X?" when a known one is close) and kExitUsage.
int reportParseError(const CLI::App& app, const CLI::ParseError& e);
// The name of `known` closest to `typed` (few edits), or "" when none is close.
std::string closestName(const std::string& typed, const std::vector<std::string>& known);

// "2048", "2^11", "1e3" → value (finite, >= 0); false otherwise.
bool parseTau(const std::string& s, double* out);
// A whole string that is one finite number (strtod syntax).
bool parseFiniteDouble(const std::string& s, double* out);
// "4,6,2^3" → values (each as parseTau); false on a bad element.
bool parseList(const std::string& s, std::vector<double>* out);
// --tau-gradient (LodOptions::tauGradient): its help text and its parse.
std::string suggestedTauGradient();
std::string tauGradientHelp();
// "max(tau/D, F)": the automatic split-misfit tolerance in z' units
// (keyframe::kMisfitTauDivisor, keyframe::kMergeNoiseFloor).
std::string misfitToleranceText();
bool parseTauGradient(const std::string& s, double* out, std::string* err);

// LOD options shared by the schedule commands (schedule-study, schedule-oracle).
struct StudyLod {
  std::string tau = "2^11", planarity = "region-local";
  bool noMerge = false;
};

struct Common {
  std::string scene = "indoor";
  std::string path;  // empty: the scene's default path
  std::string depth = depthModeName(kDefaultDepthMode);
  int frames = 0;  // stop after this many frames (0 = all)
  int width = 0, height = 0;  // frame size, pixels (0 = the path's)
  int keyframeEvery = 0;      // frames between keyframes (0 = the path's keyframe_every)
  scenes::DefaultPathOptions pathOptions;  // --speed, --eye-height
};

// --preset and the options that replace what a preset sets (walk, bake,
// view): the option set of app/options/walk_options.h, bound to a
// session::WalkOptions that starts as the Default preset's, so --help shows
// the default; an option is read only when it is given.
using PresetCli = WalkOptionSet;
// The options of the preset named by `o`, then each option of `o` given on
// `c`'s command line (values were checked while parsing). Returns 0.
int applyPresetCli(const CLI::App* c, const PresetCli& o, session::Preset* preset,
                   session::WalkOptions* out);
// With --preset paper, the first setting of `wo` that departs from the paper
// (session::differenceFromPaper) as a usage error naming the option: exit 2.
// `spelledAs` maps an option to the one the user typed when another sets the
// same thing (view: --mode given as --geometry). 0 when `wo` is the paper's
// or the preset is not paper.
int refusePaperDeparture(session::Preset preset, const session::WalkOptions& wo,
                         const std::function<std::string(const std::string&)>& spelledAs = {});

struct Loaded {
  scenes::Scene scene;
  scenes::CameraPath path;
  std::unique_ptr<gl::Context> context;
};

// Chunked runs (bake, sweep): --slurm / --workers, docs/slurm.md.
struct DistributeCli {
  DistributeOptions d;
  int chunk = -1;  // hidden: run one chunk (what a worker or array task runs)
};

void addStudyLodOptions(CLI::App* c, StudyLod& o);
// --tau in z' units as a text ('2^11' or '2048'), checked while parsing (a
// bad value is a usage error), for the commands outside the walk's option
// table (lod, schedule-study, schedule-oracle).
CLI::Option* addTauText(CLI::App* c, std::string& tau);
// Empty on success, else the message for the user.
std::string applyStudyLod(const StudyLod& o, keyframe::LodOptions* lod);
// --spacings: comma-separated whole frame counts from 1 to maxSpacing (0 = no
// bound, named by maxName in the message). Empty on success, else the message.
std::string parseSpacings(const std::string& text, int maxSpacing, const std::string& maxName,
                          std::vector<int>* out, const std::string& option = "--spacings");
// Keyframe schedule options of walk and schedule-study.
void addPlannerOptions(CLI::App* c, session::PlannerOptions& p, std::string& predictor,
                       std::string& planBy, bool withAuto);
// A whole number of frames in [lo, hi].
CLI::Validator wholeFrames(long lo, long hi, const std::string& name);
// --scene, --path, --depth, --frames (and the size overrides) of every command
// on a path, and addGlOptions.
void addCommon(CLI::App* c, Common& o);
// --scene, --path and --keyframe-every (addCommon's; the viewer's too).
void addScenePath(CLI::App* c, Common& o);
// --gl auto|egl|osmesa and --gl-device N: the headless OpenGL backend of a
// command that renders (they set gl::setHeadlessOptions when given; default
// HYBRIDWALK_GL, else auto; docs/gpu.md). A --gl value outside the set is a
// usage error (exit 2); a device out of range fails at context creation.
void addGlOptions(CLI::App* c);
// --force on `c` (docs/output-folders.md): write into an output folder that is
// not empty and not hybridwalk's, owned by another command, or a symlink.
void addForceOption(CLI::App* c);
// --max-memory SIZE: the run's memory budget (core/memory_budget.h); part of addCommon.
void addMaxMemoryOption(CLI::App* c);
// Claims the output folder `dir` for the command `c` for the whole run
// (core/output_dir.h), with --force if `c` has it and it was given.
// `summaries`: files that describe the others (report.json), removed unless
// the command calls commit() once everything is written (OutputDir::provisional).
Result<std::unique_ptr<OutputDir>> claimOutputDir(const CLI::App* c, const std::string& dir,
                                                  const std::vector<std::string>& summaries = {});
// Runs `body` (a command) holding its output folder `dir` (claimOutputDir); the
// summaries stay only when it returns 0.
int runInOutputDir(const CLI::App* c, const std::string& dir,
                   const std::vector<std::string>& summaries, const std::function<int()>& body);
// The scene, its camera path (--path or the scene's default) and a headless
// GL context; the cheap inputs are validated first.
Result<Loaded> loadInputs(const Common& o);
DepthMode depthModeOf(const std::string& s);
void addDistribute(CLI::App* c, DistributeCli& o, const char* unit);

// --help with the option groups in a fixed order: Essentials, Options, Level of
// detail, Composition, Keyframes, Timing, Studies (then any other). Set on the
// top-level app before its subcommands are added; they inherit it.
// Lines are wrapped at kHelpColumns; a flag pair shows its names and its
// default ("--merge-strips, --no-merge-strips (default: on)").
class GroupedHelp : public CLI::Formatter {
 public:
  static constexpr int kHelpColumns = 100;
  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override;
  std::string make_option(const CLI::Option* opt, bool isPositional) const override;
  std::string make_option_name(const CLI::Option* opt, bool isPositional) const override;
  std::string make_description(const CLI::App* app) const override;
  std::string make_subcommand(const CLI::App* sub) const override;
};
// `text` wrapped at `width` columns (UTF-8 code points), every line after
// the first indented by `indent`, the first starting at column `used`.
std::string wrapText(const std::string& text, int indent, int used, int width);
// Puts each named option (long name, e.g. "--tau") of `c` into its group;
// "--help" may be named too. A name `c` does not have is our bug (checked).
void setGroups(CLI::App* c,
               const std::vector<std::pair<std::string, std::vector<std::string>>>& groups);

}  // namespace hw::app
