#include "bench/schedule_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>

#include "report/html_report.h"
#include "core/statistics.h"
#include "core/json_util.h"
#include "session/schedule_calibration.h"
#include "report/plot.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"

namespace hw::bench {

using namespace report;  // plots, tables and HTML of the studies
using session::WalkOptions;
using session::runWalk;
using session::fitJson;

namespace {

using session::Predictor;
using nlohmann::json;

// Per in-between frame of a walk: its bracketing keyframes and measured PSNR.
struct FrameSample {
  int frame = 0, k0 = 0, k1 = 0;
  double psnr = 0;  // identical frames (+inf) count as 99 dB, as in the walk summary
  session::FrameFeatures features;
};

struct Run {
  std::string schedule;  // "fixed" or "adaptive"
  double param = 0;      // keyframe_every, or target PSNR dB
  std::vector<int> keyframes;
  json summary;
  double kfPer100 = 0, psnrMedian = 0, psnrP5 = 0;
  double planMs = std::nan(""), probeRenderMs = std::nan("");
  long evaluations = 0;
  int probes = 0;
  double predictedMin = std::nan(""), predictedMedian = std::nan("");
  std::vector<FrameSample> samples;
};

// x at which the piecewise-linear curve (xs ascending) first reaches y ≥ target,
// scanning from the left; NaN if never. `bounded` is set when the first point
// already reaches it (the answer is then an upper bound).
double firstCrossing(const std::vector<double>& xs, const std::vector<double>& ys, double target,
                     bool* bounded) {
  *bounded = false;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (!(ys[i] >= target)) continue;
    if (i == 0) {
      *bounded = true;
      return xs[0];
    }
    const double t = (target - ys[i - 1]) / (ys[i] - ys[i - 1]);
    return xs[i - 1] + t * (xs[i] - xs[i - 1]);
  }
  return std::nan("");
}

// y of the piecewise-linear curve at x (xs ascending); NaN outside.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  for (std::size_t i = 0; i + 1 < xs.size(); ++i)
    if (x >= xs[i] && x <= xs[i + 1]) {
      if (xs[i + 1] == xs[i]) return 0.5 * (ys[i] + ys[i + 1]);
      const double t = (x - xs[i]) / (xs[i + 1] - xs[i]);
      return ys[i] + t * (ys[i + 1] - ys[i]);
    }
  if (xs.size() == 1 && x == xs[0]) return ys[0];
  return std::nan("");
}

}  // namespace

Result<json> runScheduleStudy(const scenes::Scene& scene, const std::string& sceneLabel,
                              const scenes::CameraPath& path, const ScheduleStudyOptions& opt) {
  if (opt.fixedSpacings.empty()) return makeError("schedule study: no fixed spacings");
  HW_TRY(ensureWritableDir(opt.outDir));
  Stopwatch all;
  const int frames =
      opt.walk.maxFrames > 0 ? std::min(opt.walk.maxFrames, path.frames) : path.frames;
  const json machine = machineInfo(opt.walk.glRenderer, opt.walk.glVersion);
  auto say = [&](const std::string& s) {
    if (opt.progress)
      std::fprintf(stderr, "schedule-study %s: %s\n", sceneLabel.c_str(), s.c_str());
  };

  keyframe::RenderOptions ropt;
  ropt.depthMode = opt.walk.depthMode;
  auto probeRendererR = keyframe::GeometryRenderer::create(scene, ropt);
  if (!probeRendererR) return probeRendererR.error();
  auto cameraOf = [&](int i) { return path.cameraAt(i); };
  // One probe cache for the correlation part (its cost is not a plan's cost),
  // with the cold plans' probe options so both see the same probes.
  session::KeyframeProbe probe(**probeRendererR, cameraOf, opt.planner.probeSize,
                                opt.planner.probeError);

  auto walk = [&](const scenes::CameraPath& p, const std::vector<int>& keys, Run& run) -> Status {
    WalkOptions w = opt.walk;
    w.outDir.clear();
    w.keepFrames = true;
    w.progress = opt.progress;
    w.strips = 0;
    w.maxFrames = frames;
    w.keyframeFrames = keys;
    auto res = runWalk(scene, sceneLabel, p, w);
    if (!res) return res.error();
    run.summary = res->report["summary"];
    run.keyframes = run.summary["keyframe_frames"].get<std::vector<int>>();
    run.kfPer100 = 100.0 * static_cast<double>(run.keyframes.size()) / frames;
    run.psnrMedian = numberOrNan(run.summary["psnr"]["median"]);
    run.psnrP5 = numberOrNan(run.summary["psnr"]["p5"]);
    for (const json& f : res->report["frames"]) {
      if (f["is_keyframe"].get<bool>()) continue;
      FrameSample s;
      s.frame = f["index"].get<int>();
      s.k0 = f["keyframes"][0].get<int>();
      s.k1 = f["keyframes"][1].get<int>();
      s.psnr = f["psnr"].is_number() ? f["psnr"].get<double>() : 99.0;
      auto feat = probe.features(s.k0, s.k1, s.frame);
      if (!feat) return feat.error();
      s.features = *feat;
      // The probe predictors' regressor (features() leaves it NaN).
      auto mse = probe.probeError(s.k0, s.k1, s.frame);
      if (!mse) return mse.error();
      s.features.probeMse = *mse;
      run.samples.push_back(s);
    }
    return {};
  };

  // 1. Fixed schedules.
  std::vector<Run> fixedRuns;
  for (int every : opt.fixedSpacings) {
    if (every < 1)
      return makeError("schedule study: spacing must be >= 1, got " + std::to_string(every));
    say("fixed, a keyframe every " + std::to_string(every) + " frames");
    scenes::CameraPath p = path;
    p.keyframeEvery = every;
    Run run;
    run.schedule = "fixed";
    run.param = every;
    HW_TRY(walk(p, {}, run));
    fixedRuns.push_back(std::move(run));
  }

  // 2. Which cheap predictor follows the measured PSNR: pooled over all fixed
  // walks, and within the reference spacing alone (per-frame variation only).
  const Run* refRun = &fixedRuns.front();
  for (const Run& r : fixedRuns)
    if (std::abs(r.param - opt.referenceSpacing) < std::abs(refRun->param - opt.referenceSpacing))
      refRun = &r;
  // Correlation of the fitted prediction (least squares on these walks) with
  // the measured PSNR: positive = useful. For one-regressor predictors the
  // rank correlation equals that of the feature itself, sign flipped.
  json correlation = json::array();
  std::string csvCorr =
      "predictor,pearson_pooled,spearman_pooled,pearson_ref,spearman_ref,fit_intercept,"
      "fit_slope,fit_slope2,samples\n";
  Predictor best = opt.planner.predictor;
  double bestRho = -1;
  std::map<Predictor, session::PsnrFit> fits;
  std::vector<session::FrameFeatures> feats;
  std::vector<double> measured;
  for (const Run& r : fixedRuns)
    for (const FrameSample& s : r.samples) feats.push_back(s.features), measured.push_back(s.psnr);
  std::vector<Predictor> candidates(std::begin(session::kAllPredictors),
                                    std::end(session::kAllPredictors));
  candidates.insert(candidates.end(), std::begin(session::kProbePredictors),
                    std::end(session::kProbePredictors));
  for (Predictor pr : candidates) {
    const session::PsnrFit pf = session::fitPredictor(feats, measured, pr);
    fits[pr] = pf;
    std::vector<double> x, y, xr, yr;
    for (const Run& r : fixedRuns)
      for (const FrameSample& s : r.samples) {
        x.push_back(session::predictPsnr(pf, s.features, pr));
        y.push_back(s.psnr);
        if (&r == refRun) xr.push_back(x.back()), yr.push_back(s.psnr);
      }
    const double pp = pearson(x, y), sp = spearman(x, y);
    const double pref = pearson(xr, yr), sref = spearman(xr, yr);
    correlation.push_back({{"predictor", session::predictorName(pr)},
                           {"pearson_pooled", finiteOrNull(pp)},
                           {"spearman_pooled", finiteOrNull(sp)},
                           {"pearson_reference_spacing", finiteOrNull(pref)},
                           {"spearman_reference_spacing", finiteOrNull(sref)},
                           {"fit", fitJson(pf)},
                           {"samples", x.size()}});
    csvCorr += std::string(session::predictorName(pr)) + "," + fmt(pp, 3) + "," + fmt(sp, 3) +
               "," + fmt(pref, 3) + "," + fmt(sref, 3) + "," + fmt(pf.intercept, 3) + "," +
               fmt(pf.slope, 3) + "," + fmt(pf.slope2, 3) + "," + std::to_string(x.size()) + "\n";
    // A feature whose fit rises with it (PSNR up as quality drops) is not a
    // usable predictor, whatever its correlation.
    if (std::isfinite(sp) && sp > bestRho && pf.slope < 0 && pf.slope2 <= 0)
      bestRho = sp, best = pr;
  }
  session::PlannerOptions planner = opt.planner;
  if (opt.autoPredictor) {
    planner.predictor = best;
    planner.useDefaultFit = false;
    planner.fit = fits[best];
  }
  const session::PsnrFit fit =
      planner.useDefaultFit ? session::defaultFit(planner.predictor) : planner.fit;
  say(std::string("predictor ") + session::predictorName(planner.predictor) + ": PSNR = " +
      fmt(fit.intercept) + " + " + fmt(fit.slope) + " * x + " + fmt(fit.slope2) + " * x2");
  auto predictedStats = [&](Run& r) {
    std::vector<double> v;
    for (const FrameSample& s : r.samples)
      v.push_back(session::predictPsnr(fit, s.features, planner.predictor));
    r.predictedMin = percentile(v, 0);
    r.predictedMedian = median(v);
  };
  for (Run& r : fixedRuns) predictedStats(r);

  // 3. Planned schedules: at the given targets, or, per fixed run, at the
  // target whose plan has the same number of keyframes (found by bisection on
  // the shared probe; plans are monotone in the target for nested predictors).
  std::vector<double> targets = opt.targets;
  if (targets.empty()) {
    std::vector<double> predictedAll;
    for (const Run& r : fixedRuns)
      for (const FrameSample& s : r.samples)
        predictedAll.push_back(session::predictPsnr(fit, s.features, planner.predictor));
    const double lo0 = percentile(predictedAll, 0) - 10, hi0 = percentile(predictedAll, 100) + 10;
    for (const Run& r : fixedRuns) {
      const int want = static_cast<int>(r.keyframes.size());
      double lo = lo0, hi = hi0, bestT = lo0;
      int bestCount = -1;
      for (int it = 0; it < 24; ++it) {
        const double mid = 0.5 * (lo + hi);
        session::PlannerOptions po = planner;
        po.targetPsnrDb = mid;
        auto plan = session::planAdaptiveSchedule(probe, frames, po);
        if (!plan) return plan.error();
        const int got = static_cast<int>(plan->keyframes.size());
        if (bestCount < 0 || std::abs(got - want) < std::abs(bestCount - want) ||
            (std::abs(got - want) == std::abs(bestCount - want) && got < bestCount))
          bestCount = got, bestT = mid;
        if (got == want) break;
        (got < want ? lo : hi) = mid;
      }
      say("target " + fmt(bestT) + " dB gives " + std::to_string(bestCount) +
          " keyframes (fixed every " + fmt(r.param, 0) + ": " + std::to_string(want) + ")");
      targets.push_back(bestT);
    }
  }
  std::vector<Run> adaptiveRuns;
  for (double target : targets) {
    say("adaptive, target " + fmt(target) + " dB");
    session::PlannerOptions po = planner;
    po.targetPsnrDb = target;
    // A cold plan (fresh probe): its time is what a walk would pay.
    auto plan = session::planAdaptiveSchedule(**probeRendererR, cameraOf, frames, po);
    if (!plan) return plan.error();
    Run run;
    run.schedule = "adaptive";
    run.param = target;
    run.planMs = plan->planMs;
    run.probeRenderMs = plan->probeRenderMs;
    run.evaluations = plan->evaluations;
    run.probes = plan->probes;
    HW_TRY(walk(path, plan->keyframes, run));
    predictedStats(run);
    adaptiveRuns.push_back(std::move(run));
  }

  // 4. Curves and the headline.
  auto curve = [](std::vector<const Run*> runs, std::vector<double>& x, std::vector<double>& med,
                  std::vector<double>& p5) {
    std::sort(runs.begin(), runs.end(),
              [](const Run* a, const Run* b) { return a->kfPer100 < b->kfPer100; });
    for (const Run* r : runs)
      x.push_back(r->kfPer100), med.push_back(r->psnrMedian), p5.push_back(r->psnrP5);
  };
  std::vector<const Run*> fp, ap;
  for (const Run& r : fixedRuns) fp.push_back(&r);
  for (const Run& r : adaptiveRuns) ap.push_back(&r);
  std::vector<double> fx, fmed, fp5, ax, amed, ap5;
  curve(fp, fx, fmed, fp5);
  curve(ap, ax, amed, ap5);
  bool bounded = false;
  const double refPsnr = refRun->psnrMedian, refKf = refRun->kfPer100;
  const double adaptiveKf = firstCrossing(ax, amed, refPsnr, &bounded);
  const double reduction = 1.0 - adaptiveKf / refKf;
  const double medAtEqual = interpolate(ax, amed, refKf), p5AtEqual = interpolate(ax, ap5, refKf);
  // The same at the reference's 5th percentile (the floor a worst-frame plan targets).
  bool boundedP5 = false;
  const double adaptiveKfP5 = firstCrossing(ax, ap5, refRun->psnrP5, &boundedP5);
  json headline = {{"reference_spacing", refRun->param},
                   {"reference_keyframes_per_100", refKf},
                   {"reference_psnr_median", refPsnr},
                   {"reference_psnr_p5", refRun->psnrP5},
                   {"adaptive_keyframes_per_100_at_reference_median", finiteOrNull(adaptiveKf)},
                   {"adaptive_keyframes_is_upper_bound", bounded},
                   {"keyframe_reduction", finiteOrNull(reduction)},
                   {"goal_reduction", 0.30},
                   {"goal_met", std::isfinite(reduction) && reduction >= 0.30},
                   {"adaptive_keyframes_per_100_at_reference_p5", finiteOrNull(adaptiveKfP5)},
                   {"adaptive_keyframes_at_p5_is_upper_bound", boundedP5},
                   {"keyframe_reduction_at_p5", finiteOrNull(1.0 - adaptiveKfP5 / refKf)},
                   {"adaptive_psnr_median_at_reference_count", finiteOrNull(medAtEqual)},
                   {"adaptive_psnr_p5_at_reference_count", finiteOrNull(p5AtEqual)},
                   {"psnr_median_gain_at_equal_count", finiteOrNull(medAtEqual - refPsnr)},
                   {"psnr_p5_gain_at_equal_count", finiteOrNull(p5AtEqual - refRun->psnrP5)}};

  json runsJson = json::array();
  std::string csvRuns =
      "schedule,keyframe_every,target_psnr,keyframes,keyframes_per_100,psnr_median,psnr_p5,"
      "predicted_min,predicted_median,in_between_ms_median,plan_ms,probe_render_ms,"
      "probes,evaluations\n";
  for (const std::vector<Run>* group : {&fixedRuns, &adaptiveRuns})
    for (const Run& r : *group) {
      const bool fixed = r.schedule == "fixed";
      runsJson.push_back({{"schedule", r.schedule},
                          {"keyframe_every", fixed ? json(r.param) : json(nullptr)},
                          {"target_psnr", fixed ? json(nullptr) : json(r.param)},
                          {"keyframes", r.keyframes.size()},
                          {"keyframes_per_100", r.kfPer100},
                          {"keyframe_frames", r.keyframes},
                          {"psnr", r.summary["psnr"]},
                          {"ssim", r.summary["ssim"]},
                          {"holes_before_fallback", r.summary["holes_before_fallback"]},
                          {"in_between_ms", r.summary["in_between_ms"]},
                          {"predicted_psnr_min", finiteOrNull(r.predictedMin)},
                          {"predicted_psnr_median", finiteOrNull(r.predictedMedian)},
                          {"plan_ms", finiteOrNull(r.planMs)},
                          {"probe_render_ms", finiteOrNull(r.probeRenderMs)},
                          {"probes", r.probes},
                          {"evaluations", r.evaluations}});
      csvRuns += r.schedule + "," + (fixed ? fmt(r.param, 0) : "") + "," +
                 (fixed ? "" : fmt(r.param)) + "," + std::to_string(r.keyframes.size()) + "," +
                 fmt(r.kfPer100) + "," + fmt(r.psnrMedian) + "," + fmt(r.psnrP5) + "," +
                 fmt(r.predictedMin) + "," + fmt(r.predictedMedian) + "," +
                 fmt(numberOrNan(r.summary["in_between_ms"]["median"])) + "," + fmt(r.planMs, 1) +
                 "," + fmt(r.probeRenderMs, 1) + "," + std::to_string(r.probes) + "," +
                 std::to_string(r.evaluations) + "\n";
    }

  {
    Series fm, am, f5, a5;
    fm.label = "fixed, median";
    fm.x = fx, fm.y = fmed;
    am.label = "adaptive, median";
    am.x = ax, am.y = amed;
    f5.label = "fixed, 5th percentile";
    f5.x = fx, f5.y = fp5;
    a5.label = "adaptive, 5th percentile";
    a5.x = ax, a5.y = ap5;
    const auto& pal = plotPalette();
    fm.colour = f5.colour = pal[0];
    am.colour = a5.colour = pal[1];
    f5.marker = a5.marker = Marker::kSquare;
    fm.marker = am.marker = Marker::kCircle;
    PlotOptions po;
    po.title = "Keyframe schedules: " + sceneLabel + " (" + std::to_string(frames) + " frames)";
    po.xLabel = "keyframes per 100 frames";
    po.yLabel = "in-between PSNR (dB)";
    po.width = 900;
    po.height = 560;
    HW_TRY(writePlot(opt.outDir + "/schedule.png", {fm, am, f5, a5}, po));
    Series sc;
    sc.label = std::string("fixed-schedule frames, ") + session::predictorName(planner.predictor);
    sc.lines = false;
    for (const Run& r : fixedRuns)
      for (const FrameSample& s : r.samples) {
        sc.x.push_back(session::predictPsnr(fit, s.features, planner.predictor));
        sc.y.push_back(s.psnr);
      }
    Series line;
    line.label = "measured = predicted";
    line.markers = false;
    if (!sc.x.empty()) {
      const auto [lo, hi] = std::minmax_element(sc.x.begin(), sc.x.end());
      line.x = {*lo, *hi};
      line.y = {*lo, *hi};
    }
    PlotOptions pp;
    pp.title = "Predicted vs measured PSNR: " + sceneLabel;
    pp.xLabel =
        std::string("predicted PSNR, ") + session::predictorName(planner.predictor) + " (dB)";
    pp.yLabel = "measured in-between PSNR (dB)";
    HW_TRY(writePlot(opt.outDir + "/predictor.png", {sc, line}, pp));
  }

  const auto& s0 = fixedRuns.front().summary;
  json doc = {
      {"scene", s0["scene"]},
      {"resolution", s0["resolution"]},
      {"frames", frames},
      {"walk",
       {{"tau", s0["tau"]},
        {"tau_parallax_px", s0["tau_parallax_px"]},
        {"criterion", s0["criterion"]},
        {"planarity", s0["planarity"]},
        {"merge_strips", s0["merge_strips"]},
        {"depth_mode", s0["depth_mode"]},
        {"compose_mode", s0["compose_mode"]},
        {"sky_backdrop", s0["sky_backdrop"]}}},
      {"planner",
       {{"predictor", session::predictorName(planner.predictor)},
        {"predictor_chosen_by_correlation", opt.autoPredictor},
        {"fit", fitJson(fit)},
        {"criterion", session::planCriterionName(planner.criterion)},
        {"min_gap", planner.minGap},
        {"max_gap", planner.maxGap},
        {"probe_size", planner.probeSize},
        {"candidate_stride", planner.candidateStride},
        {"frames_per_segment", planner.framesPerSegment},
        {"targets_psnr", targets}}},
      {"correlation", correlation},
      {"runs", runsJson},
      {"headline", headline},
      {"machine", machine},
      {"elapsed_s", all.ms() / 1000.0},
      {"note",
       "PSNR is over in-between frames only (keyframes are exact), as in the walk "
       "summary. Times are wall clock on a shared 2-vCPU VM (llvmpipe): noisy."}};
  HW_TRY(writeFileAtomic(opt.outDir + "/schedule.json", doc.dump(1)));
  HW_TRY(writeFileAtomic(opt.outDir + "/runs.csv", csvRuns));
  HW_TRY(writeFileAtomic(opt.outDir + "/correlation.csv", csvCorr));
  {
    std::string csv =
        "schedule,param,frame,k0,k1,psnr,rel_distance,angle_deg,hole_fraction,stretch,"
        "disagreement_mse,probe_mse\n";
    for (const std::vector<Run>* group : {&fixedRuns, &adaptiveRuns})
      for (const Run& r : *group)
        for (const FrameSample& s : r.samples)
          csv += r.schedule + "," + fmt(r.param) + "," + std::to_string(s.frame) + "," +
                 std::to_string(s.k0) + "," + std::to_string(s.k1) + "," + fmt(s.psnr, 3) + "," +
                 fmt(s.features.relDistance, 5) + "," + fmt(s.features.angleDeg, 4) + "," +
                 fmt(s.features.holeFraction, 6) + "," + fmt(s.features.stretch, 5) + "," +
                 fmt(s.features.disagreementMse, 3) + "," + fmt(s.features.probeMse, 3) + "\n";
    HW_TRY(writeFileAtomic(opt.outDir + "/frames.csv", csv));
  }

  HtmlReport page("Keyframe schedules: fixed vs error-driven (" + sceneLabel + ")");
  page.paragraph("Scene " + sceneLabel + ", " + std::to_string(frames) +
                 " frames. Planner: predictor " + session::predictorName(planner.predictor) +
                 ", criterion " + session::planCriterionName(planner.criterion) + ", gaps " +
                 std::to_string(planner.minGap) + ".." + std::to_string(planner.maxGap) +
                 " frames, probes " + std::to_string(planner.probeSize) + " px. " +
                 doc["note"].get<std::string>());
  page.images({"schedule.png", "predictor.png"});
  std::vector<std::vector<std::string>> rows;
  for (const json& r : runsJson)
    rows.push_back({r["schedule"].get<std::string>(),
                    r["keyframe_every"].is_null() ? "" : fmt(numberOrNan(r["keyframe_every"]), 0),
                    r["target_psnr"].is_null() ? "" : fmt(numberOrNan(r["target_psnr"])),
                    std::to_string(r["keyframes"].get<std::size_t>()),
                    fmt(numberOrNan(r["keyframes_per_100"]), 1),
                    fmt(numberOrNan(r["psnr"]["median"])), fmt(numberOrNan(r["psnr"]["p5"])),
                    fmt(numberOrNan(r["plan_ms"]), 0)});
  page.table({"schedule", "every", "target dB", "keyframes", "per 100", "PSNR median", "PSNR p5",
              "plan ms"},
             rows);
  std::vector<std::vector<std::string>> crow;
  for (const json& c : correlation)
    crow.push_back({c["predictor"].get<std::string>(), fmt(numberOrNan(c["pearson_pooled"]), 3),
                    fmt(numberOrNan(c["spearman_pooled"]), 3),
                    fmt(numberOrNan(c["pearson_reference_spacing"]), 3),
                    fmt(numberOrNan(c["spearman_reference_spacing"]), 3)});
  page.heading("Predictors: correlation with measured PSNR (fixed walks)");
  page.table({"predictor", "Pearson, all spacings", "Spearman, all", "Pearson, reference spacing",
              "Spearman, reference"},
             crow);
  page.heading("Headline");
  page.preformatted(headline.dump(1));
  HW_TRY(page.write(opt.outDir + "/index.html"));
  return doc;
}

}  // namespace hw::bench
