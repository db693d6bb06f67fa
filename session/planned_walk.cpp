#include "session/planned_walk.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe.h"

namespace hw::session {
namespace {

using nlohmann::json;

// What the calibration leaves for the plan: the error model's name and
// spread, and the report's calibration block.
struct Calibrated {
  std::string uncertaintyModel;
  double uncertaintyDb = 0;
  std::string targetSource = "given";
  json calibrationJ = nullptr;
  MeasuredSegments measured;  // the calibration walks' segments
};

// Walks the calibration spacings, refits the predictor on their frames and
// sets options.plan's fit, path offsets, error model and (fixed:G) target.
Status calibrate(const scenes::Scene& scene, const std::string& sceneLabel,
                 const scenes::CameraPath& path, int frames, const WalkOptions& walk,
                 KeyframeProbe& probe, PlannedWalkOptions& options, PlannedWalk& out,
                 Calibrated& c) {
  PlannerOptions& plan = options.plan;
  Stopwatch calSw;
  auto cal = runCalibrationWalks(scene, sceneLabel, path, frames, options.calibrationSpacings,
                                 walk, walk.progress);
  if (!cal) return cal.error();
  c.measured = cal->measured;
  auto fit = calibratePredictor(probe, plan.predictor, cal->samples);
  if (!fit) return fit.error();
  plan.useDefaultFit = false;
  plan.fit = fit->fit;
  // The residuals the error model takes: the fit's, or with a window what
  // is left after the path offsets (each sample's offset computed without
  // its own calibration segment, as for a segment the calibration did not
  // walk).
  std::vector<double> residuals;
  std::vector<int> sampleFrames, sampleSegment;  // segment: held out together
  for (std::size_t i = 0; i < cal->samples.size(); ++i) {
    const auto& s = cal->samples[i];
    residuals.push_back(s.psnrDb - fit->predictedDb[i]);
    sampleFrames.push_back(s.frame);
    const bool same =
        i > 0 && cal->spacing[i] == cal->spacing[i - 1] && s.k0 == cal->samples[i - 1].k0;
    sampleSegment.push_back(i == 0 ? 0 : sampleSegment.back() + (same ? 0 : 1));
  }
  double residualSd = fit->residualStdDb;
  json windowJ = nullptr;
  const double window = options.calibrationWindowFrames;
  if (window > 0) {
    auto offsets =
        smoothResidualsAlongPath(frames, sampleFrames, residuals, window, 2.0, sampleSegment);
    plan.frameOffsetDb = offsets.offsetDb;
    residuals = offsets.heldOutResidualsDb;
    residualSd = offsets.heldOutRmsDb;
    const auto [lo, hi] = std::minmax_element(offsets.offsetDb.begin(), offsets.offsetDb.end());
    windowJ = {{"frames", window},
               {"prior_samples", 2.0},
               {"held_out_residual_rms_db", residualSd},
               {"offset_min_db", lo == offsets.offsetDb.end() ? 0.0 : *lo},
               {"offset_max_db", hi == offsets.offsetDb.end() ? 0.0 : *hi}};
  }
  if (options.uncertainty == PlanUncertainty::Normal) {
    c.uncertaintyDb = residualSd;
    c.uncertaintyModel = "normal";
  } else if (options.uncertainty == PlanUncertainty::Empirical ||
             options.uncertainty == PlanUncertainty::Auto) {
    plan.error.setResiduals(std::move(residuals));
    c.uncertaintyDb = residualSd;
    c.uncertaintyModel = "empirical";
  }
  for (const auto& w : cal->walks)
    if (w.spacing == options.targetSpacing) {
      if (!std::isfinite(w.psnrMedian))
        return makeError("--target-psnr fixed:" + std::to_string(options.targetSpacing) +
                         ": the calibration walk has no finite PSNR median");
      plan.targetPsnrDb = w.psnrMedian;
      c.targetSource = "fixed:" + std::to_string(options.targetSpacing);
    }
  c.calibrationJ = calibrationJson(*cal, *fit);
  c.calibrationJ["window"] = windowJ;
  c.calibrationJ["ms"] = calSw.ms();
  std::fprintf(stderr, "calibrated %s on %d in-between frames: residual sd %.2f dB, Spearman %.3f",
               predictorName(plan.predictor), fit->samples, fit->residualStdDb, fit->spearman);
  if (window > 0)
    std::fprintf(stderr, "; along the path (%g frames): %.2f dB left", window, residualSd);
  if (options.targetSpacing > 0)
    std::fprintf(stderr, "; target %.2f dB (%s)", plan.targetPsnrDb, c.targetSource.c_str());
  std::fprintf(stderr, "\n");
  out.calibrationOffsetDb = plan.frameOffsetDb;
  out.calibrationFit = std::move(*fit);
  out.calibration = std::move(*cal);
  return {};
}

// Verification rounds after the plan: measure the segments it picks, plan
// again; sets out.keyframes, out.verified and options.plan's path offsets.
Result<json> verify(const scenes::Scene& scene, const std::string& sceneLabel,
                    const scenes::CameraPath& path, int frames, const WalkOptions& walk,
                    KeyframeProbe& probe, const PlanResult& plan, bool empiricalError,
                    PlannedWalkOptions& options, MeasuredSegments& measured, PlannedWalk& out) {
  PlannerOptions& po = options.plan;
  Stopwatch vsw;
  Status failure;
  const PsnrFit fitUsed = plan.fit;
  const FramePredictor raw = [&](int k0, int k1, int f) {
    if (!failure.ok()) return -std::numeric_limits<double>::infinity();
    auto ft = predictorFeatures(probe, po.predictor, k0, k1, f);
    if (!ft) {
      failure = ft.error();
      return -std::numeric_limits<double>::infinity();
    }
    return predictPsnr(fitUsed, *ft, po.predictor);
  };
  PlanSearch search;
  search.minGap = po.minGap;
  search.maxGap = po.maxGap;
  search.error = po.error;
  VerifyOptions verifyOpt;
  verifyOpt.maxRounds = options.verifyRounds;
  verifyOpt.windowFrames = options.calibrationWindowFrames;
  verifyOpt.empiricalError = empiricalError;
  verifyOpt.optimismDb = options.verifyOptimismDb;
  int round = 0;
  const auto measure = [&](const std::vector<std::pair<int, int>>& segs, MeasuredSegments& m) {
    int n = 0;
    for (const auto& sg : segs) n += sg.second - sg.first - 1;
    ++round;
    if (options.progress)
      std::fprintf(stderr,
                   "verify round %d/%d: walking %zu planned segments (%d in-between frames)\n",
                   round, options.verifyRounds, segs.size(), n);
    return measureSegments(scene, sceneLabel, path, frames, segs, walk, m);
  };
  const std::size_t before = measured.size();
  auto v = planVerified(frames, po.targetPsnrDb, search, raw, measured, measure, verifyOpt);
  if (!failure.ok()) return failure.error();
  if (!v) return v.error();
  out.keyframes = v->keyframes;
  po.frameOffsetDb = v->offsetDb;
  if (options.targetSpacing > 0)
    out.referenceKeyframes = static_cast<int>(
        keyframe::KeyframeSchedule{frames, options.targetSpacing, {}}.keyframes().size());
  out.referenceLabel = "fixed every " + std::to_string(options.targetSpacing) + " frames";
  json rounds = json::array();
  int framesMeasured = 0;
  for (const auto& r : v->rounds) {
    framesMeasured += r.framesMeasured;
    rounds.push_back({{"keyframes", r.keyframes}, {"unmeasured_segments", r.unmeasured},
                      {"frames_measured", r.framesMeasured},
                      {"guaranteed_keyframes", r.guaranteedKeyframes},
                      {"held_out_residual_rms_db", r.heldOutRmsDb}});
  }
  json verifyJ = {{"max_rounds", options.verifyRounds},
                  {"optimism_db", options.verifyOptimismDb},
                  {"rounds", rounds},
                  {"converged", v->converged},
                  {"median_guaranteed", v->guaranteed},
                  {"planned_keyframes", plan.keyframes.size()},
                  {"keyframes", v->keyframes.size()},
                  {"good_frames", v->guaranteed ? json(v->good) : json(nullptr)},
                  {"frames_measured", framesMeasured},
                  {"segments_measured", measured.size() - before},
                  {"ms", vsw.ms()}};
  std::fprintf(stderr,
               "verified: %zu keyframes (planned %zu) after %zu rounds, %d in-between frames "
               "measured in %.0f ms; %s\n",
               v->keyframes.size(), plan.keyframes.size(), v->rounds.size() - 1, framesMeasured,
               vsw.ms(),
               v->guaranteed ? "its median guaranteed by measured frames"
                             : "no guaranteed schedule: the last plan, its median predicted");
  out.verified = std::move(*v);
  return verifyJ;
}

}  // namespace

Result<PlannedWalk> planWalk(const scenes::Scene& scene, const std::string& sceneLabel,
                             const scenes::CameraPath& path, int frames, const WalkOptions& walk,
                             PlannedWalkOptions options) {
  PlannerOptions& plan = options.plan;
  const bool calibrated = !options.calibrationSpacings.empty();
  if (options.targetSpacing > 0 &&
      std::find(options.calibrationSpacings.begin(), options.calibrationSpacings.end(),
                options.targetSpacing) == options.calibrationSpacings.end())
    return makeError("planned walk: the target's spacing " +
                     std::to_string(options.targetSpacing) + " is not a calibration spacing");
  if (!calibrated && (options.verifyRounds > 0 || options.calibrationWindowFrames > 0 ||
                      options.uncertainty == PlanUncertainty::Empirical ||
                      options.uncertainty == PlanUncertainty::Normal))
    return makeError("planned walk: verify rounds, a calibration window and a calibrated error "
                     "model need calibration spacings");
  Calibrated c;
  c.uncertaintyDb = options.uncertainty == PlanUncertainty::Given ? options.uncertaintyDb : 0.0;
  c.uncertaintyModel = c.uncertaintyDb > 0 ? "normal" : "none";
  keyframe::RenderOptions ropt;
  ropt.depthMode = walk.depthMode;
  auto probeRenderer = keyframe::GeometryRenderer::create(scene, ropt);
  if (!probeRenderer) return probeRenderer.error();
  const auto cameraOf = [&](int i) { return path.cameraAt(i); };
  KeyframeProbe probe(**probeRenderer, cameraOf, plan.probeSize, plan.probeError);
  PlannedWalk out;
  out.predictor = plan.predictor;
  if (calibrated)
    HW_TRY(calibrate(scene, sceneLabel, path, frames, walk, probe, options, out, c));
  if (c.uncertaintyModel == "normal") plan.error.sigmaDb = c.uncertaintyDb;
  auto planned = planAdaptiveSchedule(probe, frames, plan);
  if (!planned) return planned.error();
  out.keyframes = planned->keyframes;
  json verifyJ = nullptr;
  if (options.verifyRounds > 0) {
    auto v = verify(scene, sceneLabel, path, frames, walk, probe, *planned,
                    c.uncertaintyModel == "empirical", options, c.measured, out);
    if (!v) return v.error();
    verifyJ = std::move(*v);
  }
  auto predicted = predictSchedule(probe, plan.predictor, planned->fit, out.keyframes,
                                   plan.frameOffsetDb);
  if (!predicted) return predicted.error();
  out.predicted = std::move(*predicted);
  out.targetPsnrDb = plan.targetPsnrDb;
  out.planner = {{"predictor", predictorName(plan.predictor)},
                 {"criterion", planCriterionName(plan.criterion)},
                 {"target_psnr", plan.targetPsnrDb},
                 {"target_source", c.targetSource},
                 {"uncertainty", c.uncertaintyModel},
                 {"uncertainty_db", c.uncertaintyDb},
                 {"calibration", c.calibrationJ},
                 {"min_gap", plan.minGap},
                 {"max_gap", plan.maxGap},
                 {"probe_size", plan.probeSize},
                 {"candidate_stride", plan.candidateStride},
                 {"frames_per_segment", plan.framesPerSegment},
                 {"fit", fitJson(planned->fit)},
                 {"plan_ms", planned->planMs},
                 {"probe_render_ms", planned->probeRenderMs},
                 {"probes", planned->probes},
                 {"evaluations", planned->evaluations},
                 {"verify", verifyJ}};
  std::fprintf(stderr,
               "planned %zu keyframes for %d frames in %.0f ms (%d probes, %.0f ms rendering them)\n",
               planned->keyframes.size(), frames, planned->planMs, planned->probes,
               planned->probeRenderMs);
  return out;
}

}  // namespace hw::session
