// The `walk` command.
#include "app/commands.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "app/viewer.h"
#include "session/bake.h"
#include "bench/bench_suite.h"
#include "session/export.h"
#include "core/json_util.h"
#include "bench/slurm.h"
#include "session/schedule_calibration.h"
#include "bench/schedule_oracle.h"
#include "bench/schedule_study.h"
#include "bench/stress.h"
#include "bench/sweep.h"
#include "session/planned_walk.h"
#include "session/presets.h"
#include "session/walk.h"
#include "report/schedule_plots.h"
#include "report/walk_plots.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "session/keyframe_planner.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "app/cli_common.h"

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
  // The preset's settings are the defaults; an option given replaces one.
  PresetCli pc;  // --preset, --mode and the LOD options the viewer and bake share
  const session::WalkOptions& defaults = pc.defaults;
  std::string compose = gapfill::composeModeName(defaults.inBetween.compose.mode);
  std::string fallback = "copy";
  bool renderHoles = defaults.renderHoles;
  double renderHolesBudget = defaults.renderHolesBudget;
  float blendSoftness = 0.05f;
  std::string texcoords = "projective";
  bool noRef = false;
  bool saveFrames = false;
  bool quiet = false;
  bool noSky = false;
  std::string layers = "fused";
  bool noSkipBg = false;
  bool noSkipPrev = false;
  double nearDistance = defaults.inBetween.nearDistance;
  std::string subdivide = warp::subdivisionName(defaults.warp.subdivision);
  std::string primitives = "indexed";
  bool cullBg = false;
  int subdivideCell = 16;
  int strips = 4;
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
  double keyframeCacheMb = 256;
  int keyframePrefetch = 2;
  std::size_t keyframeFlushTriangles = 8192;
  int keyframeWorkerNice = 0;
  int keyframeStepsPerFrame = 2;
  std::string keyframePacing = "time";
  double keyframeBudgetScale = 2.0;
  FrameBudgetCli fb;
  int staleAfter = 2;
  bool noFramePacing = false;
  bool pixelAge = false;
};

// The preset's options, then each option given on the command line; with
// --preset paper given, an option that departs from the paper is an error.
int presetAndGiven(WalkCli& o, session::WalkOptions* out) {
  session::Preset preset = session::Preset::Default;
  if (const int code = applyPresetCli(o.walk, o.pc, &preset, out); code != 0) return code;
  session::WalkOptions& wo = *out;
  auto given = [&](const char* name) { return o.walk->count(name) > 0; };
  if (given("--compose"))
    gapfill::parseComposeMode(o.compose.c_str(), &wo.inBetween.compose.mode);
  if (given("--near")) wo.inBetween.nearDistance = o.nearDistance;
  if (given("--fallback")) gapfill::parseFallback(o.fallback.c_str(), &wo.inBetween.fallback);
  if (given("--render-holes") || given("--no-render-holes")) wo.renderHoles = o.renderHoles;
  if (given("--render-holes-budget")) wo.renderHolesBudget = o.renderHolesBudget;
  if (given("--blend-softness")) wo.inBetween.compose.blendSoftness = o.blendSoftness;
  if (given("--subdivide"))
    wo.warp.subdivision = o.subdivide == "uniform"    ? warp::Subdivision::Uniform
                          : o.subdivide == "adaptive" ? warp::Subdivision::Adaptive
                                                      : warp::Subdivision::None;
  if (const int code = refusePaperDeparture(preset, wo); code != 0) return code;
  // An adaptive schedule plans keyframes for frames that are all warped.
  if (o.schedule == "adaptive") {
    if (given("--mode") && wo.mode != session::FrameMode::Hybrid)
      return failUsage("--mode " + o.pc.mode +
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
  wo.warp.texcoords = o.texcoords == "affine" ? warp::TexcoordMode::Affine : warp::TexcoordMode::Projective;
  wo.warp.skyBackdrop = !o.noSky;
  wo.inBetween.fusedLayers = o.layers == "fused";
  wo.inBetween.skipBackground = !o.noSkipBg;
  wo.inBetween.skipPrevious = !o.noSkipPrev;
  wo.warp.subdivideCellPx = o.subdivideCell;
  warp::parsePrimitives(o.primitives.c_str(), &wo.warp.primitives);
  wo.warp.cullBackground = o.cullBg;
  wo.depthMode = depthModeOf(o.walkC.depth);
  wo.reference = !o.noRef;
  wo.saveFrames = o.saveFrames;
  wo.strips = o.strips;
  wo.maxFrames = o.walkC.frames;
  wo.outDir = o.walkOut;
  wo.progress = !o.quiet;
  wo.keepFrames = false;  // only the summary is printed; frames go to report.json
  if (o.schedule == "adaptive" && o.walkPlan.minGap > o.walkPlan.maxGap)
    return fail("--min-gap " + std::to_string(o.walkPlan.minGap) + " exceeds --max-gap " +
                std::to_string(o.walkPlan.maxGap));
  wo.keyframeCacheBytes = static_cast<std::size_t>(o.keyframeCacheMb * 1024 * 1024);
  wo.keyframePrefetch = o.keyframePrefetch;
  wo.keyframeFlushTriangles = o.keyframeFlushTriangles;
  wo.keyframeWorkerNice = o.keyframeWorkerNice;
  wo.keyframeStepsPerFrame = o.keyframeStepsPerFrame;
  wo.keyframePacing = o.keyframePacing == "time"     ? session::WalkOptions::KeyframePacing::Time
                     : o.keyframePacing == "slices" ? session::WalkOptions::KeyframePacing::Slices
                     : o.keyframePacing == "steps"  ? session::WalkOptions::KeyframePacing::Steps
                                                  : session::WalkOptions::KeyframePacing::None;
  wo.keyframeBudgetScale = o.keyframeBudgetScale;
  const bool frameBudgetAuto = o.fb.isAuto();
  const double frameBudgetMs = o.fb.ms();
  wo.frameBudgetMs = frameBudgetMs;
  wo.frameBudgetAuto = frameBudgetAuto;
  wo.frameBudgetQuantile = o.fb.quantile;
  wo.frameBudgetWindow = o.fb.window;
  wo.staleAfter = o.staleAfter;
  wo.paceFrames = !o.noFramePacing;
  wo.pixelAge = o.pixelAge;
  auto in = loadInputs(o.walkC);
  if (!in) return fail(in.error().message);
  wo.glRenderer = in->context->renderer();
  wo.glVersion = in->context->version();
  if (!o.walkKeyframes.empty()) {  // baked keyframes (docs/keyframe-db.md)
    auto db = keyframe::KeyframeDb::open(o.walkKeyframes);
    if (!db) return fail(db.error().message);
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
  if (!o.walkKeyframes.empty() && o.schedule == "adaptive")
    return fail("--keyframes and --schedule adaptive: a baked database has its own keyframe schedule");
  std::optional<session::PlannedWalk> planned;  // adaptive: the plan and its predictions
  if (o.schedule != "adaptive")  // the calibration options only shape an adaptive plan
    for (const char* opt : {"--calibrate-spacing", "--calibration-window", "--plan-uncertainty",
                            "--verify-rounds", "--verify-optimism"})
      if (o.walk->count(opt) > 0)
        return fail(std::string(opt) + ": expected --schedule adaptive (it shapes the planned "
                    "schedule), got --schedule " + o.schedule);
  if (o.schedule == "adaptive") {
    const int frames = wo.maxFrames > 0 ? std::min(wo.maxFrames, in->path.frames) : in->path.frames;
    session::PlannedWalkOptions pw;
    if (auto e = plannedWalkOptions(o, frames, &pw); !e.empty()) return fail(e);
    auto p = session::planWalk(in->scene, o.walkC.scene, in->path, frames, wo, std::move(pw));
    if (!p) return fail(p.error().message);
    if (auto st = report::writePlannedWalkPlots(o.walkOut, *p); !st) return fail(st.error().message);
    wo.keyframeFrames = p->keyframes;
    planned = std::move(*p);
  }
  auto res = session::runWalk(in->scene, o.walkC.scene, in->path, wo);
  if (!res) return fail(res.error().message);
  if (!wo.outDir.empty()) {
    if (auto st = report::writeFrameTimes(wo.outDir + "/frame_times.png", *res, wo, o.walkC.scene);
        !st)
      return fail(st.error().message);
    if (auto st = report::writeStrips(wo.outDir, *res); !st) return fail(st.error().message);
  }
  if (planned)  // the planner's settings and cost go into the report's summary
    if (auto st = report::addPlannerToWalkReport(o.walkOut, *planned); !st)
      return fail(st.error().message);
  const json& s = res->report["summary"];
  auto num = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
  char threshold[64];
  if (wo.lod.tauParallaxPx > 0)
    std::snprintf(threshold, sizeof threshold, "tau-px %g", wo.lod.tauParallaxPx);
  else
    std::snprintf(threshold, sizeof threshold, "tau %g", wo.lod.tau);
  std::printf(
      "walk: %s (%zu triangles), %dx%d, %d frames (%d keyframes, %s schedule), %s, %s\n"
      "  in-between PSNR median %.2f dB (p5 %.2f), SSIM median %.4f\n"
      "  holes before fallback median %.4f%%, after %.4f%%; quads per keyframe median %.0f\n"
      "  in-between frame %.2f ms median (p95 %.2f) vs geometry %.2f ms (p95 %.2f)\n"
      "  every frame (%s keyframes) %.2f ms median, p95 %.2f (p95/median %.2f); "
      "%d keyframe stalls, %.1f ms waited\n",
      o.walkC.scene.c_str(), in->scene.triangleCount(), in->path.width, in->path.height,
      s["frames"].get<int>(), s["keyframes"].get<int>(), o.schedule.c_str(), threshold,
      s["criterion"].get<std::string>().c_str(), num(s["psnr"]["median"]), num(s["psnr"]["p5"]),
      num(s["ssim"]["median"]), 100 * num(s["holes_before_fallback"]["median"]),
      100 * num(s["holes_after_fallback"]["median"]), num(s["quads_per_keyframe"]["median"]),
      num(s["in_between_ms"]["median"]), num(s["in_between_ms"]["p95"]),
      num(s["reference_ms"]["median"]), num(s["reference_ms"]["p95"]),
      s["keyframe_acquisition"].get<std::string>().c_str(), num(s["frame_ms"]["median"]),
      num(s["frame_ms"]["p95"]), num(s["frame_ms_p95_over_median"]),
      s["keyframe_stalls"].get<int>(), num(s["keyframe_stall_ms_total"]));
  const json& byMode = s["frames_by_mode"];
  const json& ratio = s["frame_over_reference"];
  std::printf("  mode %s: %d frames drawn as geometry, %d warped, %d keyframes shown; "
              "frame / geometry time: median %.3f, p95 %.3f\n",
              s["mode"].get<std::string>().c_str(), byMode["geometry"].get<int>(),
              byMode["warp"].get<int>(), byMode["keyframe"].get<int>(),
              ratio.is_object() ? num(ratio["median"]) : std::nan(""),
              ratio.is_object() ? num(ratio["p95"]) : std::nan(""));
  if (frameBudgetAuto)
    std::printf("  frame budget auto: p%.0f of the last %d in-between frames' work, median %.1f ms\n",
                o.fb.quantile * 100, o.fb.window, num(s["frame_budget_ms"]));
  if (frameBudgetMs > 0 || frameBudgetAuto)
    std::printf(
        "  frame budget %.1f ms: %d frames refreshed (%.0f px median, %.2f ms median), stale "
        "pixels median %.0f; presented interval %.2f ms median, p95/median %.2f (work %.2f); "
        "%d frames over budget\n",
        num(s["frame_budget_ms"]), s["frames_refreshed"].get<int>(), num(s["refreshed_pixels"]["median"]),
        num(s["refresh_ms"]["median"]), num(s["stale_pixels"]["median"]),
        num(s["frame_interval_ms"]["median"]), num(s["frame_interval_ms_p95_over_median"]),
        num(s["frame_ms_p95_over_median"]), s["budget_overruns"].get<int>());
  std::printf("report: %s/report.json\n", o.walkOut.c_str());
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
  walk->add_option("--preset", o.pc.preset,
                   "Settings to start from: default (measured best on many scenes: --mode auto, "
                   "--tau-px 0.125, region-local planarity, merged strips, misfit leaves split, "
                   "keyframes built ahead, larger holes drawn by the geometry renderer) or paper "
                   "(Zheng et al. 1999 exactly: every frame warped, --tau 2^11, five-point "
                   "stencil, overlay, no merging, no near geometry, no subdivision, holes copied "
                   "from the previous frame); "
                   "options given replace the preset's, except that with paper an option "
                   "departing from the paper is an error (--tau may vary)")
      ->check(CLI::IsMember({"default", "paper"}))
      ->capture_default_str();
  walk->add_option("--mode", o.pc.mode,
                   "How frames are drawn: auto (per keyframe segment, warped or drawn as "
                   "geometry, whichever costs less as measured in this run; geometry when about "
                   "even), hybrid (every frame warped or a keyframe, the paper's) or geometry "
                   "(every frame drawn by the geometry renderer; no keyframes)")
      ->check(CLI::IsMember({"auto", "hybrid", "geometry"}))
      ->capture_default_str();
  walk->add_option("--tau", o.pc.tau,
                   "LOD threshold on |Δ²z'| in z' units (2^24 scale), '2^11' or '2048' form; "
                   "replaces --tau-px (the paper's threshold; --preset paper: 2^11)");
  walk->add_option("--tau-px", o.pc.tauPx,
                   "LOD threshold as parallax error: pixels per scene unit of camera motion (the "
                   "same meaning indoors and out); 0 = use --tau")
      ->check(CLI::NonNegativeNumber)
      ->excludes("--tau")
      ->capture_default_str();
  walk->add_option("--criterion", o.pc.criterion,
                   "Planarity test: five-point (paper's eq. 3) or per-axis-max (max(|Δ²x|,|Δ²y|))")
      ->check(CLI::IsMember({"five-point", "per-axis-max"}))
      ->capture_default_str();
  walk->add_option("--planarity", o.pc.planarity,
                   "Planarity test: stencil (paper: Δ² stencils reach across region borders) or "
                   "region-local (second differences only inside the region; no one-pixel strips "
                   "along edges)")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  walk->add_flag("--merge-strips,!--no-merge-strips", o.pc.mergeStrips,
                 "Merge adjacent coplanar leaves (within max(tau/4, 4) z' units) into larger "
                 "quads, or not")
      ->capture_default_str();
  walk->add_flag("--split-misfit,!--no-split-misfit", o.pc.splitMisfit,
                 "Cut a leaf that passed the planarity test but whose least-squares plane "
                 "misses its own pixels (by " +
                     misfitToleranceText() +
                     " z' units), or whose corners cross a crease; no mis-warped quads "
                     "(docs/quad-validation.md), more quads")
      ->capture_default_str();
  walk->add_option("--tau-gradient", o.pc.tauGradient, tauGradientHelp())->capture_default_str();
  walk->add_option("--compose", o.compose,
                   "Composition: overlay (paper: nearer keyframe in front), depth-merge "
                   "(per-pixel nearer of the two layers) or blend (where both layers see the same "
                   "surface, a mean weighted toward the keyframe that sees it sharper: closer "
                   "view direction, less magnified; else the nearer). depth-merge and blend use "
                   "separate layers whatever --layers says")
      ->check(CLI::IsMember({"overlay", "depth-merge", "blend"}))
      ->capture_default_str();
  walk->add_option("--blend-softness", o.blendSoftness,
                   "With --compose blend: view penalty difference (radians, or relative "
                   "magnification) over which the two weights change by a factor e")
      ->check(CLI::Range(1e-4, 10.0))
      ->capture_default_str();
  walk->add_option("--fallback", o.fallback,
                   "Pixels neither layer covers: copy (paper: the same pixel of the previous "
                   "frame) or reproject (the previous frame warped to this camera with its "
                   "depth; the same pixel only where that leaves nothing)")
      ->check(CLI::IsMember({"copy", "reproject"}))
      ->capture_default_str();
  walk->add_flag("--render-holes,!--no-render-holes", o.renderHoles,
                 "After the fallback, draw the larger holes with the geometry renderer: the "
                 "16x16-pixel tiles holding at least 8 hole pixels, as up to 12 tight rectangles "
                 "(the most holes first; scissored, the scene's clusters culled to each); "
                 "isolated cracks keep the fallback's pixels")
      ->capture_default_str();
  walk->add_option("--render-holes-budget", o.renderHolesBudget,
                   "With --render-holes and --mode auto: the hole pass may take up to this "
                   "fraction of a geometry frame's time (measured in this run); rectangles are "
                   "drawn, most holes first, while their estimated cost fits it and keeps the "
                   "frame below one geometry frame. 0 = no cap; --mode hybrid draws every "
                   "rectangle (frames independent of timings)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  walk->add_option("--texcoords", o.texcoords,
                   "Warp texture mapping: projective (exact for planar quads) or affine "
                   "(plain perspective-correct s,t; for comparison)")
      ->check(CLI::IsMember({"projective", "affine"}))
      ->capture_default_str();
  walk->add_flag("--no-sky-backdrop", o.noSky,
                 "Do not draw empty keyframe pixels (sky) as a backdrop at infinity; they then "
                 "count as holes, as in the paper");
  walk->add_option("--layers", o.layers,
                   "How the two warped layers are composed (overlay rule): fused (one render "
                   "target, background drawn only where the foreground left pixels empty, one "
                   "readback) or separate (the paper's two layers read back and composed on the "
                   "CPU). Depth-merge always uses separate")
      ->check(CLI::IsMember({"fused", "separate"}))
      ->capture_default_str();
  walk->add_flag("--no-skip-background", o.noSkipBg,
                 "Draw the background layer even when the foreground covers every pixel "
                 "(default: a coverage test skips it; the frame is identical)");
  walk->add_flag("--no-skip-previous", o.noSkipPrev,
                 "Run the previous-frame fill even when the layers leave no holes");
  walk->add_option("--near", o.nearDistance,
                   "Draw objects near the viewpoint directly (paper §3): scene clusters (a few "
                   "hundred triangles each) within this distance (scene units, e.g. metres) of a "
                   "keyframe's eye are left out of that keyframe, and each frame draws as "
                   "geometry the clusters within it of its own eye or of the keyframes it warps; "
                   "0 = off")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  walk->add_option("--subdivide", o.subdivide,
                   "Cut large quads into cells at upload (paper §2.1): none, uniform (every quad, "
                   "the paper's), adaptive (only quads whose corner depths differ by 1.5x or whose "
                   "pixels leave their plane by > 0.2 %); interior cell corners follow the "
                   "keyframe depth")
      ->check(CLI::IsMember({"none", "uniform", "adaptive"}))
      ->capture_default_str();
  walk->add_option("--primitives", o.primitives,
                   "How quads are drawn (same pixels, different vertex work): independent (6 "
                   "vertices per quad), indexed (4 vertices + 6 indices), shared (indexed, corners "
                   "identical between neighbouring quads stored once), points (indexed, 1x1 "
                   "leaves as one GL point each, sized to their footprint; not pixel-identical)")
      ->check(CLI::IsMember({"independent", "indexed", "shared", "points"}))
      ->capture_default_str();
  walk->add_flag("--cull-background", o.cullBg,
                 "Leave out background quads whose surfaces the foreground keyframe sees (they "
                 "mostly land under foreground pixels; lossy: cracks along edges then come from "
                 "the previous frame). Needs --primitives indexed or shared");
  walk->add_option("--subdivide-cell", o.subdivideCell, "Cell size for --subdivide, keyframe pixels")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  walk->add_flag("--no-reference", o.noRef,
                 "Skip the geometry reference render (no PSNR/SSIM; faster)");
  walk->add_flag("--save-frames", o.saveFrames, "Write every frame and hole mask as PNG");
  walk->add_option("--strips", o.strips,
                   "Number of reference|hybrid|diff×4|holes strips to write")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  walk->add_option("--out", o.walkOut, "Output directory")->capture_default_str();
  walk->add_flag("--quiet", o.quiet, "No progress line");
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
      ->check(CLI::Range(0.0, 1e6))
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
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  addPlannerOptions(walk, o.walkPlan, o.walkPredictor, o.walkPlanBy, false);
  walk->add_flag("--async-keyframes,!--sync-keyframes", o.pc.asyncKeyframes,
                 "Render and mesh keyframes ahead of need on a worker thread with a second "
                 "OSMesa context, or when first needed, in the frame that shows them (frames "
                 "are identical; only their timing changes)")
      ->capture_default_str();
  walk->add_option("--keyframe-cache-mb", o.keyframeCacheMb,
                   "Memory bound of the keyframe cache in MiB (colour + depth + quad mesh; the "
                   "two keyframes of the current bracket are always kept)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  walk->add_option("--keyframe-prefetch", o.keyframePrefetch,
                   "With --async-keyframes: keyframes past the current pair built ahead")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  walk->add_option("--keyframe-flush-triangles", o.keyframeFlushTriangles,
                   "With --async-keyframes: the worker flushes its keyframe render after about "
                   "this many triangles, so frames on the main context wait behind one piece of "
                   "it on llvmpipe's shared rasteriser threads (0 = one flush)")
      ->capture_default_str();
  walk->add_option("--keyframe-pacing", o.keyframePacing,
                   "With --async-keyframes: how the worker spreads a keyframe over the frames "
                   "before its need: time (each frame allows budget-scale x last build ms / frames "
                   "per keyframe of worker time, alongside the frame), slices (the same budget, "
                   "run at the end of each frame while the frame waits: the two never share the "
                   "CPUs; counted in the frame's time), steps (--keyframe-steps-per-frame steps "
                   "per frame) or none (as fast as it can); lifted while a frame waits")
      ->check(CLI::IsMember({"time", "slices", "steps", "none"}))
      ->capture_default_str();
  walk->add_option("--keyframe-budget-scale", o.keyframeBudgetScale,
                   "With --keyframe-pacing time or slices: the worker's time per frame as a multiple of its "
                   "even share (> 1 lets it get ahead)")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  walk->add_option("--keyframe-steps-per-frame", o.keyframeStepsPerFrame,
                   "With --keyframe-pacing steps: worker steps (a flushed piece of the render, the "
                   "readback, a mesh-build step) per frame")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  walk->add_option("--keyframe-worker-nice", o.keyframeWorkerNice,
                   "With --async-keyframes: nice increment of the worker thread (0-19)")
      ->check(CLI::Range(0, 19))
      ->capture_default_str();
  addFrameBudgetOptions(walk, o.fb,
                        "with time left after an in-between frame is composed, the region of "
                        "pixels carried over from earlier frames longest is re-rendered by the "
                        "geometry renderer if its estimated cost fits, and frames are presented "
                        "every this many ms");
  walk->add_option("--stale-after", o.staleAfter,
                   "With --frame-budget-ms: frames a pixel must have been carried over from the "
                   "previous frame before it counts for a refresh (at least 1)")
      ->check(wholeFrames(1, 255, "stale after"))
      ->capture_default_str();
  walk->add_flag("--no-frame-pacing", o.noFramePacing,
                 "With --frame-budget-ms: refresh within the budget but do not wait for it to "
                 "pass before the next frame");
  walk->add_flag("--pixel-age", o.pixelAge,
                 "Track and report per-pixel age (frames carried over from the previous frame) "
                 "without a budget (always on with --frame-budget-ms); frames are identical");

  setGroups(walk, {{"Essentials", {"--help", "--scene", "--path", "--out", "--save-frames", "--width",
                                   "--height", "--frames", "--strips", "--quiet", "--no-reference",
                                   "--preset", "--mode"}},
                   {"Level of detail", {"--tau", "--tau-px", "--criterion", "--planarity",
                                        "--merge-strips", "--no-merge-strips", "--split-misfit", "--no-split-misfit", "--tau-gradient", "--depth", "--subdivide",
                                        "--subdivide-cell", "--primitives"}},
                   {"Composition", {"--compose", "--blend-softness", "--fallback", "--render-holes", "--no-render-holes", "--render-holes-budget", "--layers", "--near", "--texcoords",
                                    "--no-sky-backdrop", "--no-skip-background",
                                    "--no-skip-previous", "--cull-background"}},
                   {"Keyframes", {"--keyframes", "--schedule", "--target-psnr", "--async-keyframes",
                                  "--sync-keyframes",
                                  "--keyframe-cache-mb", "--keyframe-prefetch", "--keyframe-pacing",
                                  "--keyframe-budget-scale"}},
                   {"Timing", {"--frame-budget-ms", "--frame-budget-quantile",
                               "--frame-budget-window", "--stale-after", "--no-frame-pacing",
                               "--pixel-age"}},
                   {"Studies", {"--calibrate-spacing", "--plan-uncertainty", "--calibration-window",
                                "--verify-rounds", "--verify-optimism", "--plan-by", "--min-gap",
                                "--max-gap", "--probe-size", "--candidate-stride",
                                "--frames-per-segment", "--predictor", "--keyframe-flush-triangles",
                                "--keyframe-steps-per-frame", "--keyframe-worker-nice"}}});
  addForceOption(walk);
  commands.push_back({walk, [state](int argc, char** argv) {
    return runInOutputDir(state->walk, state->walkOut, {"report.json"},
                          [&] { return run(*state, argc, argv); });
  }});
}

}  // namespace hw::app
