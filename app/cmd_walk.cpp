// The `walk` command.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/option_checks.h"
#include "app/viewer.h"
#include "app/walk_plots.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/json_util.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "report/walk_page.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "session/bake.h"
#include "session/export.h"
#include "session/keyframe_planner.h"
#include "session/planned_walk.h"
#include "session/presets.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"

// The planner moved to session/; WalkCli's field still names it keyframe::
// (the option definitions are being edited on main: rename there, then drop this).
namespace hw::keyframe {
using session::PlannerOptions;
}  // namespace hw::keyframe

namespace hw::app {
namespace {

using nlohmann::json;

struct WalkCli {
  CLI::App* walk = nullptr;
  Common walkC;
  std::string walkOut = "out/walk";
  // --preset and every option bound to session::WalkOptions (app/options/
  // walk_options.h): the preset's settings are the defaults; an option given
  // replaces one.
  PresetCli pc;
  bool quiet = false;
  std::string walkKeyframes;
  std::string schedule = "fixed";
  std::string walkPredictor = "holes+distance";
  std::string walkPlanBy = "worst";
  keyframe::PlannerOptions walkPlan;
  std::string walkTarget = "24";
  std::string walkCalibrate;
  std::string walkUncertainty = "auto";
  double walkCalWindow = 0;
  int walkVerifyRounds = 0;
  double walkVerifyOptimism = 1.0;
};

// The preset's options, then each option given on the command line; with
// --preset paper given, an option that departs from the paper is an error.
int presetAndGiven(WalkCli& o, session::WalkOptions* out) {
  session::Preset preset = session::Preset::Default;
  if (const int code = applyPresetCli(o.walk, o.pc, &preset, out); code != 0) return code;
  session::WalkOptions& wo = *out;
  auto given = [&](const char* name) { return o.walk->count(name) > 0; };
  if (const int code = refusePaperDeparture(preset, wo); code != 0) return code;
  // An adaptive schedule plans keyframes for frames that are all warped.
  if (o.schedule == "adaptive") {
    if (given("--mode") && wo.mode != session::FrameMode::Hybrid)
      return failUsage(std::string("--mode ") + session::frameModeName(wo.mode) +
                       ": --schedule adaptive plans keyframes for warped frames; expected "
                       "--mode hybrid (or no --mode)");
    wo.mode = session::FrameMode::Hybrid;
  }
  return 0;
}

// The adaptive schedule's options as session::PlannedWalkOptions; a message
// naming the option when one is out of range (empty: fine).
std::string plannedWalkOptions(WalkCli& o, int frames, session::PlannedWalkOptions* out) {
  session::PlannedWalkOptions& pw = *out;
  session::parsePredictor(o.walkPredictor.c_str(), &o.walkPlan.predictor);
  session::parsePlanCriterion(o.walkPlanBy.c_str(), &o.walkPlan.criterion);
  if (!o.walkCalibrate.empty())
    if (auto e = parseSpacings(o.walkCalibrate, 0, "", &pw.calibrationSpacings, "--calibrate-spacing");
        !e.empty())
      return e;
  // --target-psnr: dB, or fixed:G (a calibration walk's measured median).
  const std::string targetHelp =
      "--target-psnr: expected a PSNR in dB or fixed:G with G a whole number of frames >= 2, got '" +
      o.walkTarget + "'";
  if (o.walkTarget.rfind("fixed:", 0) == 0) {
    const std::string g = o.walkTarget.substr(6);
    char* end = nullptr;
    const long v = g.empty() ? 0 : std::strtol(g.c_str(), &end, 10);
    if (g.empty() || *end != '\0' || v < 2 || v > (1 << 20)) return targetHelp;
    pw.targetSpacing = static_cast<int>(v);
    auto& cs = pw.calibrationSpacings;
    if (std::find(cs.begin(), cs.end(), pw.targetSpacing) == cs.end()) cs.push_back(pw.targetSpacing);
  } else if (!parseFiniteDouble(o.walkTarget, &o.walkPlan.targetPsnrDb)) {
    return targetHelp;
  }
  // --plan-uncertainty: auto/empirical/normal (from the calibration) or a
  // standard deviation in dB.
  const std::string& u = o.walkUncertainty;
  pw.uncertainty = u == "auto"        ? session::PlanUncertainty::Auto
                   : u == "empirical" ? session::PlanUncertainty::Empirical
                   : u == "normal"    ? session::PlanUncertainty::Normal
                                      : session::PlanUncertainty::Given;
  if (pw.uncertainty == session::PlanUncertainty::Given &&
      (!parseFiniteDouble(u, &pw.uncertaintyDb) || pw.uncertaintyDb < 0))
    return "--plan-uncertainty: expected a standard deviation >= 0 in dB, auto, empirical or "
           "normal, got '" + u + "'";
  const bool calibrated = !pw.calibrationSpacings.empty();
  if ((u == "empirical" || u == "normal") && !calibrated)
    return "--plan-uncertainty " + u +
           ": expected --calibrate-spacing or --target-psnr fixed:G (the calibration's "
           "residuals are its error model), got neither";
  if (o.walkCalWindow > 0 && !calibrated)
    return "--calibration-window: expected --calibrate-spacing or --target-psnr fixed:G (the "
           "window smooths the calibration's residuals), got neither";
  if (o.walk->count("--verify-optimism") > 0 && o.walkVerifyRounds == 0)
    return "--verify-optimism: expected --verify-rounds 1 or more (it shapes the verified "
           "plan's search), got --verify-rounds 0";
  if (o.walkVerifyRounds > 0 && !calibrated)
    return "--verify-rounds: expected --calibrate-spacing or --target-psnr fixed:G (the "
           "verified plan starts from the calibration's measured segments), got neither";
  if (o.walkVerifyRounds > 0 && o.walkPlan.criterion != session::PlanCriterion::WalkMedian)
    return "--verify-rounds: expected --plan-by walk-median (it counts measured frames "
           "against the walk's median), got --plan-by " + o.walkPlanBy;
  for (int g : pw.calibrationSpacings)
    if (g < 2 || g > frames - 1)
      return std::string(g == pw.targetSpacing ? "--target-psnr fixed:G" : "--calibrate-spacing") +
             ": a calibration walk needs keyframes 2.." + std::to_string(frames - 1) +
             " frames apart on this " + std::to_string(frames) + "-frame walk, got " +
             std::to_string(g);
  pw.plan = o.walkPlan;
  pw.calibrationWindowFrames = o.walkCalWindow;
  pw.verifyRounds = o.walkVerifyRounds;
  pw.verifyOptimismDb = o.walkVerifyOptimism;
  pw.progress = !o.quiet;
  return "";
}

int run(WalkCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
  session::WalkOptions wo;
  if (const int code = presetAndGiven(o, &wo); code != 0) return code;
  wo.depthMode = depthModeOf(o.walkC.depth);
  wo.maxFrames = o.walkC.frames;
  wo.outDir = o.walkOut;
  wo.progress = !o.quiet;
  wo.keepFrames = false;  // only the summary is printed; frames go to report.json
  if (o.schedule == "adaptive" && o.walkPlan.minGap > o.walkPlan.maxGap)
    return fail("--min-gap " + std::to_string(o.walkPlan.minGap) + " exceeds --max-gap " +
                std::to_string(o.walkPlan.maxGap));
  if (!o.walkKeyframes.empty() && o.schedule == "adaptive")
    return failUsage("--keyframes and --schedule adaptive: a baked database has its own keyframe schedule");
  if (o.schedule != "adaptive")  // the calibration options only shape an adaptive plan
    for (const char* opt : {"--calibrate-spacing", "--calibration-window", "--plan-uncertainty",
                            "--verify-rounds", "--verify-optimism"})
      if (o.walk->count(opt) > 0)
        return fail(std::string(opt) + ": expected --schedule adaptive (it shapes the planned "
                    "schedule), got --schedule " + o.schedule);
  // The database is opened before the scene loads: a wrong folder fails at once.
  std::optional<keyframe::KeyframeDb> db;
  if (!o.walkKeyframes.empty()) {  // baked keyframes (docs/keyframe-db.md)
    auto d = keyframe::KeyframeDb::open(o.walkKeyframes);
    if (!d) return fail(d.error().message);
    db.emplace(std::move(*d));
  }
  auto in = loadInputs(o.walkC);
  if (!in) return fail(in.error().message);
  wo.glRenderer = in->context->renderer();
  wo.glVersion = in->context->version();
  if (db) {
    const int frames = session::bakeFrames(in->path, o.walkC.frames);
    if (auto st = db->checkMatches(session::bakeProvenance(o.walkC.scene, in->scene.triangleCount(), in->path,
                                                         frames, wo.lod, wo.depthMode));
        !st)
      return fail(st.error().message);
    if (auto st = db->checkSchedule(session::bakeKeyframeList(in->path, frames)); !st)
      return fail(st.error().message);
    db->setExpectation({[p = in->path](int f) { return p.cameraAt(f); }, wo.depthMode});
    if (auto st = db->checkFiles(); !st) return fail(st.error().message);
    wo.keyframeFrames = db->keyframeFrames();
    wo.keyframeSource = keyframe::makeKeyframeDbSource(std::make_shared<keyframe::KeyframeDb>(std::move(*db)));
  }
  std::optional<session::PlannedWalk> planned;  // adaptive: the plan and its predictions
  if (o.schedule == "adaptive") {
    const int frames = wo.maxFrames > 0 ? std::min(wo.maxFrames, in->path.frames) : in->path.frames;
    session::PlannedWalkOptions pw;
    if (auto e = plannedWalkOptions(o, frames, &pw); !e.empty()) return fail(e);
    auto p = session::planWalk(in->scene, o.walkC.scene, in->path, frames, wo, std::move(pw));
    if (!p) return fail(p.error().message);
    if (auto st = writePlannedWalkPlots(o.walkOut, *p); !st) return fail(st.error().message);
    wo.keyframeFrames = p->keyframes;
    planned = std::move(*p);
  }
  // Auto's pinned choices: named by every option that shapes the walk (not
  // the outputs) and the scene as given.
  wo.modePinDir = session::defaultModePinDir();
  wo.modePinContext = "scene=" + o.walkC.scene + "\nkeyframes=" + o.walkKeyframes +
                      "\nschedule=" + o.schedule + "\n";
  for (const auto& row : walkRows())
    if (row.name != "--save-frames" && row.name != "--strips" && row.name != "--auto-pin")
      wo.modePinContext += row.name + "=" + row.show(wo) + "\n";
  auto res = session::runWalk(in->scene, o.walkC.scene, in->path, wo);
  if (!res) return fail(res.error().message);
  if (!wo.outDir.empty()) {
    if (auto st = writeFrameTimes(wo.outDir + "/frame_times.png", *res, wo, o.walkC.scene);
        !st)
      return fail(st.error().message);
    if (auto st = writeStrips(wo.outDir, *res); !st) return fail(st.error().message);
  }
  if (planned)  // the planner's settings and cost go into the report's summary
    if (auto st = addPlannerToWalkReport(o.walkOut, *planned); !st)
      return fail(st.error().message);
  json written = res->report["summary"];  // with the planner's fields once written
  if (!wo.outDir.empty())  // index.html and psnr_along_path.png, from report.json
    if (auto st = report::writeWalkPage(wo.outDir, &written); !st) return fail(st.error().message);
  const report::WalkSummaryText summary = report::walkSummaryText(written);
  std::printf("%s\n", summary.headline.c_str());
  for (const std::string& line : summary.details) std::printf("  %s\n", line.c_str());
  std::printf("report: %s/report.json, page %s/index.html\n", o.walkOut.c_str(), o.walkOut.c_str());
  return 0;
}

}  // namespace

void addWalkCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<WalkCli>();
  WalkCli& o = *state;
  // walk
  auto* walk = o.walk = app.add_subcommand(
      "walk", "The main job: a hybrid walkthrough along a camera path, measured against the "
              "geometry renderer; writes report.json, strips and (optionally) frames");
  addCommon(walk, o.walkC);
  addWalkOptionSet(walk, &o.pc, walkRows(),
                   "Settings to start from: default (measured best on many scenes: --mode auto, "
                   "--tau-px " +
                       formatOptionNumber(
                           session::presetOptions(session::Preset::Default).lod.tauParallaxPx) +
                       ", region-local planarity, merged strips, misfit leaves split, "
                   "keyframes built ahead, larger holes drawn by the geometry renderer) or paper "
                   "(Zheng et al. 1999 exactly: every frame warped, --tau 2^11, five-point "
                   "stencil, overlay, no merging, no near geometry, no subdivision, holes copied "
                   "from the previous frame); "
                   "options given replace the preset's, except that with paper an option "
                   "departing from the paper is an error (--tau may vary)");
  walk->add_option("--out", o.walkOut, "Output directory")->capture_default_str();
  walk->add_flag("--quiet", o.quiet, "No progress line");
  walk->add_flag_callback(
      "--help-markdown",
      [] {
        std::fputs(walkOptionsMarkdown().c_str(), stdout);
        throw CLI::Success();
      },
      "Print the option reference as Markdown (docs/walk-options.md) and exit");
  walk->add_option("--keyframes", o.walkKeyframes,
                   "Read keyframes and quad meshes from this database (written by 'hybridwalk bake' "
                   "with the same scene, path, --frames, --depth and LOD options) instead of rendering "
                   "them; the next keyframe is read ahead on a background thread");
  walk->add_option("--schedule", o.schedule,
                   "Keyframes: fixed (every keyframe_every frames of the path) or adaptive "
                   "(error-driven: planned ahead along the path, a new keyframe where the "
                   "predictor says an in-between frame would fall below --target-psnr)")
      ->check(CLI::IsMember({"fixed", "adaptive"}))
      ->capture_default_str();
  walk->add_option("--target-psnr", o.walkTarget,
                   "Adaptive schedule: the in-between PSNR to reach, dB, as --plan-by says (predicted; "
                   "the predictor's default fit comes from the built-in indoor scene at 512x512, so "
                   "on other scenes the dB are only ordered, unless --calibrate-spacing refits it "
                   "here), or fixed:G = the measured median of the calibration walk with keyframes "
                   "every G frames (G is added to --calibrate-spacing)")
      ->capture_default_str();
  walk->add_option("--calibrate-spacing", o.walkCalibrate,
                   "Adaptive schedule: first walk the path with keyframes every G frames (a "
                   "comma-separated list, e.g. 20 or 10,20; each a full walk with reference "
                   "frames, no output), refit the predictor to their measured in-between PSNRs, "
                   "and plan with that fit: the target is then in measured dB of this scene, "
                   "path and resolution. Writes calibration.csv and calibration.png. Empty = the "
                   "default fit")
      ->capture_default_str();
  walk->add_option("--plan-uncertainty", o.walkUncertainty,
                   "Adaptive schedule, --plan-by walk-median: the predictor's error model; each "
                   "in-between frame counts as its probability of reaching the target instead of "
                   "0 or 1. empirical = the calibration frames' residuals (measured - predicted) "
                   "as the error distribution; normal = a normal error with their standard "
                   "deviation; a number = a normal error of that standard deviation, dB (0 = the "
                   "plain count); auto = empirical with --calibrate-spacing, else 0")
      ->capture_default_str();
  walk->add_option("--calibration-window", o.walkCalWindow,
                   "Adaptive schedule with --calibrate-spacing: also correct each frame's "
                   "prediction by the calibration residuals near it along the path (a Gaussian "
                   "of this many frames standard deviation, shrunk toward 0 by 2 samples' "
                   "weight; the error model then takes the residuals left, each calibration "
                   "segment's computed without its own samples), frames; 0 = off")
      ->check(numberRange(0.0, 1e6))
      ->capture_default_str();
  walk->add_option("--verify-rounds", o.walkVerifyRounds,
                   "Adaptive schedule, --plan-by walk-median, with a calibration: measure what the "
                   "plan picks. Each round walks the planned segments not measured yet (at this "
                   "resolution, with reference frames, no output), counts their frames exactly, "
                   "corrects the predictions near them (--calibration-window) and plans again, "
                   "aiming one keyframe below the best schedule whose median measured frames "
                   "alone guarantee; it stops when the plan is all measured, needs no fewer "
                   "keyframes, or the rounds run out. The walk runs that guaranteed schedule "
                   "(its median is at least the target); verify.png shows the rounds. Rounds, "
                   "0 = off")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  walk->add_option("--verify-optimism", o.walkVerifyOptimism,
                   "With --verify-rounds: added to the unmeasured frames' predictions while "
                   "searching, dB, so segments that may beat their prediction get measured too; "
                   "costs measuring rounds, never the target (the schedule walked is guaranteed by "
                   "measured frames). 1 dB reached the fewest keyframes on all four 512x512 paths "
                   "measured, 0.5 dB on two (docs/results/2026-12-02/verified_plan)")
      ->check(numberRange(0.0, 100.0))
      ->capture_default_str();
  addPlannerOptions(walk, o.walkPlan, o.walkPredictor, o.walkPlanBy, false);
  setGroups(walk, {{"Essentials", {"--help", "--help-markdown", "--scene", "--path", "--out", "--width", "--height",
                                   "--frames", "--quiet"}},
                   {"Level of detail", {"--depth"}},
                   {"Keyframes", {"--keyframes", "--keyframe-every", "--schedule", "--target-psnr"}},
                   {"Studies", {"--calibrate-spacing", "--plan-uncertainty", "--calibration-window",
                                "--verify-rounds", "--verify-optimism", "--plan-by", "--min-gap",
                                "--max-gap", "--probe-size", "--candidate-stride",
                                "--frames-per-segment", "--predictor"}}});
  addForceOption(walk);
  commands.push_back({walk, [state](int argc, char** argv) {
    return runInOutputDir(state->walk, state->walkOut, {"report.json"},
                          [&] { return run(*state, argc, argv); });
  }});
}

}  // namespace hw::app
