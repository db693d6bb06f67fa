#include "bench/schedule_oracle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <iterator>
#include <optional>
#include <utility>

#include "core/statistics.h"
#include "core/json_util.h"
#include "session/schedule_calibration.h"
#include "report/plot.h"
#include "core/check.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"

namespace hw::bench {

using namespace report;  // plots, tables and HTML of the studies
using session::WalkOptions;
using session::runWalk;
using session::fitJson;


using nlohmann::json;

SegmentTable::SegmentTable(int frames, int maxGap) : frames_(frames), maxGap_(maxGap) {
  HW_CHECK_GE(frames, 1);
  HW_CHECK_GE(maxGap, 1);
  psnr_.assign(static_cast<std::size_t>(frames) * static_cast<std::size_t>(maxGap) *
                   static_cast<std::size_t>(maxGap),
               std::nan(""));
}

std::size_t SegmentTable::index(int k0, int k1, int f) const {
  HW_CHECK(k0 >= 0 && k0 < k1 && k1 < frames_ && k1 - k0 <= maxGap_ && k0 < f && f < k1);
  const auto g = static_cast<std::size_t>(maxGap_);
  return (static_cast<std::size_t>(k0) * g + static_cast<std::size_t>(k1 - k0 - 1)) * g +
         static_cast<std::size_t>(f - k0 - 1);
}

void SegmentTable::set(int k0, int k1, int f, double psnrDb) { psnr_[index(k0, k1, f)] = psnrDb; }

double SegmentTable::at(int k0, int k1, int f) const { return psnr_[index(k0, k1, f)]; }

bool SegmentTable::complete() const {
  for (int k0 = 0; k0 < frames_; ++k0)
    for (int k1 = k0 + 2; k1 < frames_ && k1 - k0 <= maxGap_; ++k1)
      for (int f = k0 + 1; f < k1; ++f)
        if (std::isnan(at(k0, k1, f))) return false;
  return true;
}

Result<SchedulePsnr> schedulePsnr(const SegmentTable& table, const std::vector<int>& keyframes) {
  const int n = table.frames();
  if (keyframes.empty() || keyframes.front() != 0 || keyframes.back() != n - 1)
    return makeError("schedule: expected keyframes from 0 to " + std::to_string(n - 1));
  std::vector<double> v;
  for (std::size_t i = 1; i < keyframes.size(); ++i) {
    const int k0 = keyframes[i - 1], k1 = keyframes[i];
    if (k1 <= k0 || k1 - k0 > table.maxGap())
      return makeError("schedule: keyframes " + std::to_string(k0) + ", " + std::to_string(k1) +
                       ": expected increasing, at most " + std::to_string(table.maxGap()) +
                       " apart");
    for (int f = k0 + 1; f < k1; ++f) {
      const double p = table.at(k0, k1, f);
      if (std::isnan(p))
        return makeError("schedule: no PSNR for frame " + std::to_string(f) + " between " +
                         std::to_string(k0) + " and " + std::to_string(k1));
      v.push_back(p);
    }
  }
  SchedulePsnr s;
  s.inBetween = static_cast<int>(v.size());
  s.median = median(v);
  s.p5 = percentile(v, 5);
  std::sort(v.begin(), v.end());
  s.lowerMedian = v.empty() ? std::nan("") : v[(v.size() + 1) / 2 - 1];
  return s;
}

OracleSchedule fewestKeyframesForMedian(const SegmentTable& table, double targetDb) {
  OracleSchedule best;
  best.keyframes = session::fewestKeyframesForMedian(
      table.frames(), targetDb, 1, table.maxGap(),
      [&](int k0, int k1, int f) { return table.at(k0, k1, f); }, nullptr, &best.good);
  return best;
}

Result<SegmentTable> readSegmentTable(const std::string& text, const std::string& source,
                                      int frames, int maxGap) {
  SegmentTable t(frames, maxGap);
  std::size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string row = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    if (line == 1) {
      if (row != "k0,k1,frame,psnr")
        return makeError(source + ":1: expected the header 'k0,k1,frame,psnr', got '" + row + "'");
      continue;
    }
    if (row.empty()) continue;
    int k0 = 0, k1 = 0, f = 0, used = 0;
    double p = 0;
    if (std::sscanf(row.c_str(), "%d,%d,%d,%lf%n", &k0, &k1, &f, &p, &used) != 4 ||
        used != static_cast<int>(row.size()) || !std::isfinite(p))
      return makeError(source + ":" + std::to_string(line) +
                       ": expected 'k0,k1,frame,psnr' (integers, a finite dB value), got '" + row + "'");
    if (!(k0 >= 0 && k0 < f && f < k1 && k1 < frames && k1 - k0 <= maxGap))
      return makeError(source + ":" + std::to_string(line) + ": segment (" + std::to_string(k0) +
                       ", " + std::to_string(k1) + ") frame " + std::to_string(f) +
                       " is outside a " + std::to_string(frames) + "-frame path with gaps up to " +
                       std::to_string(maxGap));
    t.set(k0, k1, f, p);
  }
  if (line == 0) return makeError(source + ": empty, expected the header 'k0,k1,frame,psnr'");
  if (!t.complete())
    return makeError(source + ": incomplete: expected every frame of every segment up to " +
                     std::to_string(maxGap) + " frames apart on " + std::to_string(frames) +
                     " frames (--frames and --max-gap of the run that wrote it)");
  return t;
}

namespace {

std::vector<int> fixedSchedule(int frames, int every) {
  std::vector<int> k;
  for (int i = 0; i < frames; i += every) k.push_back(i);
  if (k.back() != frames - 1) k.push_back(frames - 1);
  return k;
}

std::string exact(double v) {  // round-trips through %lf
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string fmt(double v, int digits = 3) {
  if (!std::isfinite(v)) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

}  // namespace

Result<json> runScheduleOracle(const scenes::Scene& scene, const std::string& sceneLabel,
                               const scenes::CameraPath& path, const ScheduleOracleOptions& opt) {
  if (opt.maxGap < 2) return makeError("schedule oracle: --max-gap must be >= 2, got " + std::to_string(opt.maxGap));
  for (int s : opt.fixedSpacings)
    if (s < 1 || s > opt.maxGap)
      return makeError("schedule oracle: fixed spacing " + std::to_string(s) +
                       " outside 1.." + std::to_string(opt.maxGap) + " (--max-gap)");
  if (std::find(opt.fixedSpacings.begin(), opt.fixedSpacings.end(), opt.referenceSpacing) ==
      opt.fixedSpacings.end())
    return makeError("schedule oracle: reference spacing " + std::to_string(opt.referenceSpacing) +
                     " is not one of the fixed spacings");
  Stopwatch all;
  const int frames =
      opt.walk.maxFrames > 0 ? std::min(opt.walk.maxFrames, path.frames) : path.frames;
  if (frames < 3) return makeError("schedule oracle: the path has " + std::to_string(frames) + " frames, expected >= 3");
  std::optional<SegmentTable> loaded;  // before the output exists: a bad table leaves nothing
  if (!opt.tableCsv.empty()) {
    auto text = readFile(opt.tableCsv);
    if (!text) return text.error();
    auto t = readSegmentTable(*text, opt.tableCsv, frames, opt.maxGap);
    if (!t) return t.error();
    loaded = std::move(*t);
  }
  HW_TRY(ensureWritableDir(opt.outDir));
  SegmentTable table = loaded ? std::move(*loaded) : SegmentTable(frames, opt.maxGap);
  const int walks = opt.tableCsv.empty() ? opt.maxGap * (opt.maxGap + 1) / 2 - 1 : 0;
  int walkNo = 0;
  double referenceWalkMedian = std::nan("");
  for (int g = 2; g <= opt.maxGap && opt.tableCsv.empty(); ++g)
    for (int o = 0; o < g; ++o) {
      ++walkNo;
      if (opt.progress) {
        const double el = all.ms() / 1000.0;
        std::fprintf(stderr, "\rschedule-oracle %s: walk %d/%d (gap %d, offset %d), elapsed %.0f s, ETA %.0f s   ",
                     sceneLabel.c_str(), walkNo, walks, g, o, el,
                     walkNo > 1 ? el / (walkNo - 1) * (walks - walkNo + 1) : 0.0);
        std::fflush(stderr);
      }
      std::vector<int> keys{0};
      for (int k = o; k < frames; k += g)
        if (k > 0) keys.push_back(k);
      if (keys.back() != frames - 1) keys.push_back(frames - 1);
      WalkOptions w = opt.walk;
      w.outDir.clear();
      w.keepFrames = true;
      w.progress = false;
      w.strips = 0;
      w.reference = true;
      w.maxFrames = frames;
      w.keyframeFrames = keys;
      auto res = runWalk(scene, sceneLabel, path, w);
      if (!res) return res.error();
      for (const json& f : res->report["frames"]) {
        if (f["is_keyframe"].get<bool>()) continue;
        const int k0 = f["keyframes"][0].get<int>(), k1 = f["keyframes"][1].get<int>();
        const double p = f["psnr"].is_number() ? f["psnr"].get<double>() : 99.0;  // as the walk
        if (k1 - k0 <= opt.maxGap) table.set(k0, k1, f["index"].get<int>(), p);
      }
      if (g == opt.referenceSpacing && o == 0 && res->report["summary"]["psnr"]["median"].is_number())
        referenceWalkMedian = res->report["summary"]["psnr"]["median"].get<double>();
    }
  if (opt.progress && walks > 0) std::fprintf(stderr, "\n");
  if (!table.complete()) return makeError("schedule oracle: the walks left segments unmeasured");
  const double tableMs = all.ms();

  json fixedRows = json::array();
  double refMedian = std::nan(""), refKf = std::nan("");
  std::vector<double> fx, fmed, ox, omed;
  for (int s : opt.fixedSpacings) {
    const std::vector<int> keys = fixedSchedule(frames, s);
    auto fp = schedulePsnr(table, keys);
    if (!fp) return fp.error();
    // More than half of the fixed schedule's frames reach its lower median;
    // the oracle must do as well (its interpolated median then also >= it).
    const OracleSchedule o = fewestKeyframesForMedian(table, fp->lowerMedian);
    json row = {{"spacing", s},
                {"fixed_keyframes", keys.size()},
                {"fixed_keyframes_per_100", 100.0 * static_cast<double>(keys.size()) / frames},
                {"fixed_psnr_median", fp->median},
                {"fixed_psnr_lower_median", fp->lowerMedian},
                {"fixed_psnr_p5", fp->p5}};
    if (!o.keyframes.empty()) {
      auto op = schedulePsnr(table, o.keyframes);
      if (!op) return op.error();
      row["oracle_keyframes"] = o.keyframes.size();
      row["oracle_keyframes_per_100"] = 100.0 * static_cast<double>(o.keyframes.size()) / frames;
      row["oracle_psnr_median"] = op->median;
      row["oracle_psnr_p5"] = op->p5;
      row["keyframe_reduction"] =
          1.0 - static_cast<double>(o.keyframes.size()) / static_cast<double>(keys.size());
      row["oracle_schedule"] = o.keyframes;
    } else {
      row["oracle_keyframes"] = nullptr;
      row["keyframe_reduction"] = nullptr;
    }
    if (s == opt.referenceSpacing) {
      refMedian = fp->median;
      refKf = row["fixed_keyframes_per_100"].get<double>();
    }
    fixedRows.push_back(row);
  }
  // The oracle's curve: fewest keyframes for targets across the fixed range.
  json oracleRows = json::array();
  {
    double lo = 1e9, hi = -1e9;
    for (const json& r : fixedRows) {
      lo = std::min(lo, r["fixed_psnr_median"].get<double>());
      hi = std::max(hi, r["fixed_psnr_median"].get<double>());
    }
    int lastK = -1;
    for (double t = std::floor((lo - 2.0) * 4) / 4; t <= hi + 2.0; t += 0.25) {
      const OracleSchedule o = fewestKeyframesForMedian(table, t);
      if (o.keyframes.empty()) break;
      const int k = static_cast<int>(o.keyframes.size());
      if (k == lastK) continue;
      lastK = k;
      auto op = schedulePsnr(table, o.keyframes);
      if (!op) return op.error();
      oracleRows.push_back({{"target", t},
                            {"keyframes", k},
                            {"keyframes_per_100", 100.0 * k / frames},
                            {"psnr_median", op->median},
                            {"psnr_p5", op->p5}});
      ox.push_back(100.0 * k / frames);
      omed.push_back(op->median);
    }
  }
  for (const json& r : fixedRows) {
    fx.push_back(r["fixed_keyframes_per_100"].get<double>());
    fmed.push_back(r["fixed_psnr_median"].get<double>());
  }
  // The planner on the same table.
  json plannerRows = json::array();
  // Per planner curve: keyframes per 100 frames and median, for the plot.
  struct Curve {
    std::string group;      // the predictor: "" = opt.plannerOptions', else "probe-psnr 64 px"
    std::string criterion;  // "worst", …, "walk-median, fit on this table"
    Series points;
  };
  std::vector<Curve> curves;
  double inSampleBestKf = std::nan("");
  std::string featureCsv =
      "k0,k1,frame,psnr,rel_distance,angle_deg,hole_fraction,stretch,disagreement_mse\n";
  json inSampleFit = nullptr;
  std::string probeCsv = "k0,k1,frame,psnr,probe_mse,rel_distance\n";
  double plannerBestKf = std::nan("");
  std::string plannerBestCriterion;
  double refLower = std::nan("");
  for (const json& r : fixedRows)
    if (r["spacing"].get<int>() == opt.referenceSpacing) refLower = r["fixed_psnr_lower_median"].get<double>();
  // The probe predictors' results (opt.probePsnrSize > 0).
  json probePredictors = json::array();
  if (opt.planner) {
    keyframe::RenderOptions ropt;
    ropt.depthMode = opt.walk.depthMode;
    auto rr = keyframe::GeometryRenderer::create(scene, ropt);
    if (!rr) return rr.error();
    session::KeyframeProbe probe(**rr, [&](int i) { return path.cameraAt(i); },
                                  opt.plannerOptions.probeSize, opt.plannerOptions.probeError);
    const int gmax = std::min(opt.plannerOptions.maxGap, opt.maxGap);
    // One plan per target with `base` (predictor, criterion, fit) on `pr`,
    // scored on the table; returns the fewest keyframes per 100 frames
    // reaching the reference. One call per (group, criterion).
    auto sweepTargets = [&](session::KeyframeProbe& pr, const session::PlannerOptions& base,
                            const std::string& group, const std::string& criterion,
                            double step) -> Result<double> {
      const std::string label = group.empty() ? criterion : group + ", " + criterion;
      Series* curve = &curves.emplace_back(Curve{group, criterion, Series{}}).points;
      double best = std::nan("");
      for (double t = opt.plannerTargetMin; t <= opt.plannerTargetMax + 1e-9; t += step) {
        session::PlannerOptions po = base;
        po.targetPsnrDb = t;
        po.maxGap = gmax;
        po.minGap = std::min(po.minGap, po.maxGap);
        auto plan = session::planAdaptiveSchedule(pr, frames, po);
        if (!plan) return plan.error();
        auto sp = schedulePsnr(table, plan->keyframes);
        if (!sp) return sp.error();
        const double kf = 100.0 * static_cast<double>(plan->keyframes.size()) / frames;
        plannerRows.push_back({{"criterion", label},
                               {"predictor", session::predictorName(base.predictor)},
                               {"target", t},
                               {"keyframes", plan->keyframes.size()},
                               {"keyframes_per_100", kf},
                               {"psnr_median", sp->median},
                               {"psnr_lower_median", sp->lowerMedian},
                               {"psnr_p5", sp->p5}});
        curve->x.push_back(kf);
        curve->y.push_back(sp->median);
        if (sp->lowerMedian >= refLower && !(kf >= best)) best = kf;
      }
      return best;
    };
    const session::PlanCriterion criteria[] = {session::PlanCriterion::WorstFrame,
                                                session::PlanCriterion::SegmentMedian,
                                                session::PlanCriterion::WalkMedian};
    if (!opt.probePsnrOnly) {
      for (session::PlanCriterion c : criteria) {
        session::PlannerOptions po = opt.plannerOptions;
        po.criterion = c;
        auto best =
            sweepTargets(probe, po, "", session::planCriterionName(c), opt.plannerTargetStep);
        if (!best) return best.error();
        if (!(*best >= plannerBestKf)) {
          plannerBestKf = *best;
          plannerBestCriterion = session::planCriterionName(c);
        }
      }
      // The same predictor fitted on this table (in-sample: the path's own
      // measured PSNRs), walk-median: what the features can rank once the
      // fit's scale is right for the scene.
      std::vector<session::FrameFeatures> feats;
      std::vector<double> measured;
      for (int k0 = 0; k0 < frames; ++k0)
        for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= gmax; ++k1)
          for (int f = k0 + 1; f < k1; ++f) {
            auto ft = probe.features(k0, k1, f);
            if (!ft) return ft.error();
            feats.push_back(*ft);
            measured.push_back(table.at(k0, k1, f));
            featureCsv += std::to_string(k0) + "," + std::to_string(k1) + "," + std::to_string(f) +
                          "," + exact(table.at(k0, k1, f)) + "," + exact(ft->relDistance) + "," +
                          exact(ft->angleDeg) + "," + exact(ft->holeFraction) + "," +
                          exact(ft->stretch) + "," + exact(ft->disagreementMse) + "\n";
          }
      const session::PsnrFit fit =
          session::fitPredictor(feats, measured, opt.plannerOptions.predictor);
      if (std::isfinite(fit.intercept) && std::isfinite(fit.slope)) {
        inSampleFit = fitJson(fit);
        session::PlannerOptions po = opt.plannerOptions;
        po.criterion = session::PlanCriterion::WalkMedian;
        po.useDefaultFit = false;
        po.fit = fit;
        auto best =
            sweepTargets(probe, po, "", "walk-median, fit on this table", opt.plannerTargetStep);
        if (!best) return best.error();
        inSampleBestKf = *best;
      }
    }
    // The probe predictors (the probes warped and compared with the frame's
    // own probe; + distance), on their own probes: the same three criteria
    // with the default fit, and walk-median with a fit on this table.
    if (opt.probePsnrSize > 0) {
      session::KeyframeProbe pp(**rr, [&](int i) { return path.cameraAt(i); }, opt.probePsnrSize,
                                 opt.probeError);
      std::vector<double> meas;
      for (int k0 = 0; k0 < frames; ++k0)
        for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= gmax; ++k1)
          for (int f = k0 + 1; f < k1; ++f) meas.push_back(table.at(k0, k1, f));
      for (session::Predictor pred : session::kProbePredictors) {
        session::PlannerOptions base = opt.plannerOptions;
        base.predictor = pred;
        base.probeSize = opt.probePsnrSize;
        base.probeError = opt.probeError;
        const std::string tag = std::string(session::predictorName(pred)) + " " +
                                std::to_string(opt.probePsnrSize) + " px";
        json rows = json::array();
        // The cost of one walk-median plan over the whole path from scratch
        // (every frame's probe, every warp and comparison up to the max gap).
        double planMs = 0, planRenderMs = 0;
        {
          session::PlannerOptions po = base;
          po.criterion = session::PlanCriterion::WalkMedian;
          po.maxGap = gmax;
          po.minGap = std::min(po.minGap, po.maxGap);
          po.targetPsnrDb = refLower;
          auto plan = session::planAdaptiveSchedule(**rr, [&](int i) { return path.cameraAt(i); },
                                                     frames, po);
          if (!plan) return plan.error();
          planMs = plan->planMs;
          planRenderMs = plan->probeRenderMs;
        }
        double bestKf = std::nan("");
        std::string bestCrit;
        for (session::PlanCriterion c : criteria) {
          session::PlannerOptions po = base;
          po.criterion = c;
          auto best =
              sweepTargets(pp, po, tag, session::planCriterionName(c), opt.probeTargetStep);
          if (!best) return best.error();
          rows.push_back({{"criterion", session::planCriterionName(c)},
                          {"keyframes_per_100", finiteOrNull(*best)}});
          if (!(*best >= bestKf)) bestKf = *best, bestCrit = session::planCriterionName(c);
        }
        // Every table entry's regressors (the walk-median plans above
        // memoised them all).
        std::vector<session::FrameFeatures> pf;
        const bool first = pred == session::kProbePredictors[0];
        for (int k0 = 0; k0 < frames; ++k0)
          for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= gmax; ++k1)
            for (int f = k0 + 1; f < k1; ++f) {
              auto ff = session::predictorFeatures(pp, pred, k0, k1, f);
              if (!ff) return ff.error();
              if (pred == session::Predictor::ProbePsnr) {  // it reads probeMse alone
                auto d = pp.relDistance(k0, k1, f);
                if (!d) return d.error();
                ff->relDistance = *d;
              }
              pf.push_back(*ff);
              if (first)
                probeCsv += std::to_string(k0) + "," + std::to_string(k1) + "," +
                            std::to_string(f) + "," + exact(table.at(k0, k1, f)) + "," +
                            exact(ff->probeMse) + "," + exact(ff->relDistance) + "\n";
            }
        std::vector<double> predDefault, predIn;
        const session::PsnrFit dfit = session::defaultFit(pred);
        const session::PsnrFit ifit = session::fitPredictor(pf, meas, pred);
        for (const auto& ff : pf) {
          predDefault.push_back(session::predictPsnr(dfit, ff, pred));
          predIn.push_back(session::predictPsnr(ifit, ff, pred));
        }
        double inKf = std::nan("");
        if (ifit.finite()) {
          session::PlannerOptions po = base;
          po.criterion = session::PlanCriterion::WalkMedian;
          po.useDefaultFit = false;
          po.fit = ifit;
          auto best =
              sweepTargets(pp, po, tag, "walk-median, fit on this table", opt.probeTargetStep);
          if (!best) return best.error();
          inKf = *best;
        }
        double rmse = 0;
        for (std::size_t i = 0; i < meas.size(); ++i)
          rmse += (predDefault[i] - meas[i]) * (predDefault[i] - meas[i]);
        rmse = std::sqrt(rmse / static_cast<double>(std::max<std::size_t>(1, meas.size())));
        probePredictors.push_back(
            {{"predictor", session::predictorName(pred)},
             {"probe_size", opt.probePsnrSize},
             {"hole_mse", opt.probeError.holeMse},
             {"blur_radius", opt.probeError.blurRadius},
             {"shift_tolerance", opt.probeError.shiftTolerance},
             {"previous_fill", opt.probeError.previousFill},
             {"supersample", opt.probeError.supersample},
             {"target_step", opt.probeTargetStep},
             {"criteria", rows},
             {"keyframes_per_100", finiteOrNull(bestKf)},
             {"criterion", bestCrit},
             {"reduction", finiteOrNull(1.0 - bestKf / refKf)},
             {"default_fit", fitJson(dfit)},
             {"default_fit_rmse_db", finiteOrNull(rmse)},
             {"spearman", finiteOrNull(spearman(predIn, meas))},
             {"in_sample_fit", fitJson(ifit)},
             {"in_sample_keyframes_per_100", finiteOrNull(inKf)},
             {"in_sample_reduction", finiteOrNull(1.0 - inKf / refKf)},
             {"walk_median_plan_ms", planMs},
             {"walk_median_plan_probe_render_ms", planRenderMs}});
      }
    }
  }
  json headline = {{"reference_spacing", opt.referenceSpacing},
                   {"reference_psnr_lower_median", refLower},
                   {"planner_keyframes_per_100", finiteOrNull(plannerBestKf)},
                   {"planner_criterion", plannerBestCriterion},
                   {"planner_reduction", finiteOrNull(1.0 - plannerBestKf / refKf)},
                   {"planner_in_sample_fit", inSampleFit},
                   {"planner_in_sample_keyframes_per_100", finiteOrNull(inSampleBestKf)},
                   {"planner_in_sample_reduction", finiteOrNull(1.0 - inSampleBestKf / refKf)},
                   {"reference_keyframes_per_100", refKf},
                   {"reference_psnr_median", refMedian},
                   {"reference_walk_psnr_median", finiteOrNull(referenceWalkMedian)},
                   {"goal_reduction", 0.30},
                   {"probe_predictors", probePredictors}};
  for (const json& r : fixedRows)
    if (r["spacing"].get<int>() == opt.referenceSpacing) {
      headline["oracle_keyframes_per_100"] = r.value("oracle_keyframes_per_100", json(nullptr));
      headline["best_possible_reduction"] = r["keyframe_reduction"];
      headline["goal_reachable"] =
          r["keyframe_reduction"].is_number() && r["keyframe_reduction"].get<double>() >= 0.30;
    }
  json doc = {{"scene", sceneLabel},
              {"frames", frames},
              {"max_gap", opt.maxGap},
              {"walks", walks},
              {"table_ms", tableMs},
              {"width", path.width},
              {"height", path.height},
              {"tau", opt.walk.lod.tau},
              {"machine", machineInfo(opt.walk.glRenderer, opt.walk.glVersion)},
              {"headline", headline},
              {"table_from", opt.tableCsv.empty() ? json("walks") : json(opt.tableCsv)},
              {"fixed", fixedRows},
              {"oracle", oracleRows},
              {"planner", plannerRows}};
  std::string csv =
      "spacing,fixed_keyframes,fixed_keyframes_per_100,fixed_psnr_median,fixed_psnr_p5,"
      "oracle_keyframes,oracle_keyframes_per_100,oracle_psnr_median,oracle_psnr_p5,keyframe_reduction\n";
  auto num = [](const json& j, const char* k) {
    return j.contains(k) && j[k].is_number() ? j[k].get<double>() : std::nan("");
  };
  for (const json& r : fixedRows)
    csv += std::to_string(r["spacing"].get<int>()) + "," + fmt(num(r, "fixed_keyframes"), 0) + "," +
           fmt(num(r, "fixed_keyframes_per_100"), 2) + "," + fmt(num(r, "fixed_psnr_median")) + "," +
           fmt(num(r, "fixed_psnr_p5")) + "," + fmt(num(r, "oracle_keyframes"), 0) + "," +
           fmt(num(r, "oracle_keyframes_per_100"), 2) + "," + fmt(num(r, "oracle_psnr_median")) +
           "," + fmt(num(r, "oracle_psnr_p5")) + "," + fmt(num(r, "keyframe_reduction")) + "\n";
  {
    Series fs, os;
    fs.label = "fixed schedule (every N frames)";
    fs.x = fx, fs.y = fmed;
    os.label = "best possible schedule (oracle)";
    os.x = ox, os.y = omed;
    const auto& pal = plotPalette();
    fs.colour = pal[0];
    os.colour = pal[2];
    std::vector<Series> series{fs, os};
    // Colour = predictor, marker = plan criterion (the fit-on-this-table
    // plans joined by a line): one legend row per predictor and per
    // criterion, from point-less series, instead of one per curve (14 with
    // the probe predictors: taller and wider than the plot).
    const std::size_t groupColour[] = {1, 3, 4, 5, 6, 7, 8, 9};
    const std::string criteria[] = {"worst", "median", "walk-median",
                                    "walk-median, fit on this table"};
    const Marker criterionMarker[] = {Marker::kCircle, Marker::kSquare, Marker::kDiamond,
                                      Marker::kDiamond};
    std::vector<std::string> groups;
    std::vector<Series> legend;
    for (const Curve& c : curves) {
      auto g = std::find(groups.begin(), groups.end(), c.group);
      if (g == groups.end()) {
        g = groups.insert(g, c.group);
        Series entry;
        entry.label =
            "planner, " + (c.group.empty()
                               ? std::string(session::predictorName(opt.plannerOptions.predictor))
                               : c.group);
        entry.markers = false;
        entry.colour =
            pal[groupColour[std::min<std::size_t>(groups.size() - 1, std::size(groupColour) - 1)]];
        legend.push_back(entry);
      }
      const std::size_t k = static_cast<std::size_t>(
          std::find(std::begin(criteria), std::end(criteria), c.criterion) - std::begin(criteria));
      HW_CHECK_LT(k, std::size(criteria));
      Series p = c.points;
      p.colour = legend[static_cast<std::size_t>(g - groups.begin())].colour;
      p.marker = criterionMarker[k];
      p.lines = k == 3;
      series.push_back(p);
    }
    const Rgba8 kNeutral{80, 80, 80, 255};
    for (std::size_t k = 0; k < std::size(criteria); ++k) {
      bool used = false;
      for (const Curve& c : curves) used = used || c.criterion == criteria[k];
      if (!used) continue;
      Series entry;
      entry.label = "plan by " + criteria[k];
      entry.colour = kNeutral;
      entry.marker = criterionMarker[k];
      entry.lines = k == 3;
      legend.push_back(entry);
    }
    series.insert(series.end(), legend.begin(), legend.end());
    PlotOptions po;
    po.title = "Median in-between PSNR vs keyframes: " + sceneLabel + " (" + std::to_string(frames) +
               " frames, " + std::to_string(path.width) + "x" + std::to_string(path.height) + ")";
    po.xLabel = "keyframes per 100 frames";
    po.yLabel = "median in-between PSNR (dB)";
    po.width = 900;
    po.height = 560;
    HW_TRY(writePlot(opt.outDir + "/oracle.png", series, po));
  }
  HW_TRY(writeFileAtomic(opt.outDir + "/oracle.csv", csv));
  {
    // The whole table, so any other schedule can be scored without walking.
    std::string seg = "k0,k1,frame,psnr\n";
    for (int k0 = 0; k0 < frames; ++k0)
      for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= opt.maxGap; ++k1)
        for (int f = k0 + 1; f < k1; ++f)
          seg += std::to_string(k0) + "," + std::to_string(k1) + "," + std::to_string(f) + "," +
                 exact(table.at(k0, k1, f)) + "\n";
    HW_TRY(writeFileAtomic(opt.outDir + "/segments.csv", seg));
  }
  // The planner's features of every (k0, k1, frame) next to its PSNR.
  if (opt.planner && !opt.probePsnrOnly)
    HW_TRY(writeFileAtomic(opt.outDir + "/features.csv", featureCsv));
  // The probe-psnr predictor's low-resolution error of every entry.
  if (opt.planner && opt.probePsnrSize > 0)
    HW_TRY(writeFileAtomic(opt.outDir + "/probe_error.csv", probeCsv));
  HW_TRY(writeFileAtomic(opt.outDir + "/oracle.json", doc.dump(1)));
  return doc;
}

}  // namespace hw::bench
