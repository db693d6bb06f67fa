// The `study` command.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/viewer.h"
#include "bench/schedule_study.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/json_util.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/short_number.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "session/bake.h"
#include "session/export.h"
#include "session/keyframe_planner.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct ScheduleStudyCli {
  CLI::App* studyCmd = nullptr;
  Common studyC;
  std::string studyOut = "out/schedule";
  std::string studySpacings = "4,6,8,10,15,20";
  std::string studyTargets;
  std::string studyPredictor = "auto";
  std::string studyPlanBy = "worst";
  StudyLod studyLod;
  bool studyQuiet = false;
  int studyRef = 10;
  session::PlannerOptions studyPlan;
};

int run(ScheduleStudyCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    bench::ScheduleStudyOptions so;
    if (std::string e = parseSpacings(o.studySpacings, 0, "", &so.fixedSpacings); !e.empty()) return fail(e);
    if (!o.studyTargets.empty() && !parseList(o.studyTargets, &so.targets))
      return fail("--targets: expected comma-separated dB values like 28,30,32, got '" + o.studyTargets + "'");
    for (double t : so.targets)
      if (!(t > 0 && t <= 200))
        return fail("--targets: expected PSNR targets above 0 and at most 200 dB, got " +
                    shortNumber(t));
    if (o.studyPlan.minGap > o.studyPlan.maxGap)
      return fail("--min-gap " + std::to_string(o.studyPlan.minGap) + " exceeds --max-gap " +
                  std::to_string(o.studyPlan.maxGap));
    if (std::string e = applyStudyLod(o.studyLod, &so.walk.lod); !e.empty()) return fail(e);
    so.walk.depthMode = depthModeOf(o.studyC.depth);
    so.walk.maxFrames = o.studyC.frames;
    so.referenceSpacing = o.studyRef;
    session::parsePlanCriterion(o.studyPlanBy.c_str(), &o.studyPlan.criterion);
    so.planner = o.studyPlan;
    so.autoPredictor = o.studyPredictor == "auto";
    if (!so.autoPredictor) session::parsePredictor(o.studyPredictor.c_str(), &so.planner.predictor);
    so.outDir = o.studyOut;
    so.progress = !o.studyQuiet;
    auto in = loadInputs(o.studyC);
    if (!in) return fail(in.error().message);
    so.walk.glRenderer = in->context->renderer();
    so.walk.glVersion = in->context->version();
    auto res = bench::runScheduleStudy(in->scene, o.studyC.scene, in->path, so);
    if (!res) return fail(res.error().message);
    const json& h = (*res)["headline"];
    auto n = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
    std::printf("schedule-study: predictor %s; fixed every %g: %.1f keyframes/100 frames, median %.2f dB;\n"
                "  adaptive at that median: %s%.1f keyframes/100 (%+.0f %% vs fixed; goal -30 %%); at equal count "
                "median %+.2f dB, p5 %+.2f dB;\n  at its p5 (%.2f dB): %s%.1f keyframes/100 (%+.0f %% vs fixed)\n  open %s/index.html\n",
                (*res)["planner"]["predictor"].get<std::string>().c_str(), n(h["reference_spacing"]),
                n(h["reference_keyframes_per_100"]), n(h["reference_psnr_median"]),
                h["adaptive_keyframes_is_upper_bound"].get<bool>() ? "<= " : "",
                n(h["adaptive_keyframes_per_100_at_reference_median"]),
                -100 * n(h["keyframe_reduction"]), n(h["psnr_median_gain_at_equal_count"]),
                n(h["psnr_p5_gain_at_equal_count"]), n(h["reference_psnr_p5"]),
                h["adaptive_keyframes_at_p5_is_upper_bound"].get<bool>() ? "<= " : "",
                n(h["adaptive_keyframes_per_100_at_reference_p5"]),
                -100 * n(h["keyframe_reduction_at_p5"]), o.studyOut.c_str());
    return 0;
}

}  // namespace

void addScheduleStudyCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<ScheduleStudyCli>();
  ScheduleStudyCli& o = *state;
  // schedule-study
  auto* studyCmd = o.studyCmd = app.add_subcommand(
      "schedule-study",
      "Fixed vs error-driven keyframe schedules: the walk with a keyframe every N frames, the "
      "predictors' correlation with its measured PSNR, then planned schedules at several "
      "target PSNRs; keyframes per 100 frames vs median/p5 in-between PSNR. Writes "
      "schedule.json, runs.csv, correlation.csv, schedule.png, predictor.png, index.html");
  addCommon(studyCmd, o.studyC);
  addStudyLodOptions(studyCmd, o.studyLod);
  studyCmd->add_option("--spacings", o.studySpacings, "Fixed schedules: keyframe_every values, frames")
      ->capture_default_str();
  studyCmd->add_option("--reference-spacing", o.studyRef,
                       "Fixed spacing the headline compares with, frames")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  studyCmd->add_option("--targets", o.studyTargets,
                       "Target PSNRs of the adaptive runs, dB, comma-separated (default: per fixed "
                       "spacing, the target whose plan has as many keyframes)");
  addPlannerOptions(studyCmd, o.studyPlan, o.studyPredictor, o.studyPlanBy, true);
  studyCmd->add_option("--out", o.studyOut, "Output directory")->capture_default_str();
  studyCmd->add_flag("--quiet", o.studyQuiet, "No progress lines");

  commands.push_back({studyCmd, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
