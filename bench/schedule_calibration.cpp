#include "bench/schedule_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "bench/plot.h"
#include "core/file_io.h"
#include "core/timer.h"
#include "keyframe/keyframe_cache.h"

namespace hw::bench {

using nlohmann::json;

namespace {

// A walk that only measures: no output, the reference on, nothing that
// depends on timing (a budget's refreshes) or on a baked database.
WalkOptions measuringWalk(const WalkOptions& base, int frames, bool progress) {
  WalkOptions o = base;
  o.outDir.clear();
  o.saveFrames = false;
  o.strips = 0;
  o.keepFrames = true;
  o.reference = true;
  o.progress = progress;
  o.maxFrames = frames;
  o.keyframeSource = {};
  o.asyncKeyframes = false;
  o.frameBudgetMs = 0;
  o.frameBudgetAuto = false;
  o.onlySegments.clear();
  return o;
}

// The walk report's in-between frames into `out` by segment (a null PSNR:
// identical to the reference, counted kProbePsnrCap as the walk counts it).
void addMeasured(const json& frames, keyframe::MeasuredSegments& out) {
  for (const json& f : frames) {
    if (f["is_keyframe"].get<bool>()) continue;
    const int k0 = f["keyframes"][0].get<int>(), k1 = f["keyframes"][1].get<int>();
    const int i = f["index"].get<int>();
    auto& v = out[{k0, k1}];
    v.resize(static_cast<std::size_t>(std::max(k1 - k0 - 1, 0)), std::nan(""));
    if (i > k0 && i < k1)
      v[static_cast<std::size_t>(i - k0 - 1)] =
          f["psnr"].is_number() ? f["psnr"].get<double>() : keyframe::kProbePsnrCap;
  }
}

}  // namespace

Status measureSegments(const scenes::Scene& scene, const std::string& sceneLabel,
                       const scenes::CameraPath& path, int frames,
                       const std::vector<std::pair<int, int>>& segments, const WalkOptions& base,
                       keyframe::MeasuredSegments& out) {
  if (segments.empty()) return {};
  WalkOptions o = measuringWalk(base, frames, false);
  o.onlySegments = segments;
  o.keyframeFrames.clear();
  for (const auto& [a, b] : segments) o.keyframeFrames.push_back(a), o.keyframeFrames.push_back(b);
  o.keyframeFrames.push_back(0);
  o.keyframeFrames.push_back(frames - 1);
  std::sort(o.keyframeFrames.begin(), o.keyframeFrames.end());
  o.keyframeFrames.erase(std::unique(o.keyframeFrames.begin(), o.keyframeFrames.end()),
                         o.keyframeFrames.end());
  auto res = runWalk(scene, sceneLabel, path, o);
  if (!res) return res.error();
  keyframe::MeasuredSegments got;
  addMeasured(res->report["frames"], got);
  for (const auto& s : segments) {
    if (s.second - s.first < 2) continue;  // no in-between frame
    const auto it = got.find(s);
    if (it == got.end())
      return makeError("measuring segments: the walk did not reach segment (" +
                       std::to_string(s.first) + ", " + std::to_string(s.second) + ")");
    out[s] = it->second;
  }
  return {};
}

Result<ScheduleCalibration> runCalibrationWalks(const scenes::Scene& scene,
                                                const std::string& sceneLabel,
                                                const scenes::CameraPath& path, int frames,
                                                const std::vector<int>& spacings,
                                                const WalkOptions& base, bool progress) {
  if (frames < 3 || frames > path.frames)
    return makeError("calibration walks: expected 3.." + std::to_string(path.frames) +
                     " frames, got " + std::to_string(frames));
  ScheduleCalibration cal;
  for (std::size_t w = 0; w < spacings.size(); ++w) {
    const int g = spacings[w];
    if (g < 2 || g > frames - 1)
      return makeError("calibration walks: a spacing leaves no in-between frame or exceeds the path: "
                       "expected 2.." + std::to_string(frames - 1) + " frames, got " + std::to_string(g));
    WalkOptions o = measuringWalk(base, frames, progress);
    o.keyframeFrames = keyframe::KeyframeSchedule{frames, g, {}}.keyframes();
    if (progress)
      std::fprintf(stderr, "calibration walk %zu/%zu: keyframes every %d frames\n", w + 1,
                   spacings.size(), g);
    Stopwatch sw;
    auto res = runWalk(scene, sceneLabel, path, o);
    if (!res) return res.error();
    CalibrationWalk cw;
    cw.spacing = g;
    cw.keyframes = static_cast<int>(o.keyframeFrames.size());
    cw.walkMs = sw.ms();
    addMeasured(res->report["frames"], cal.measured);
    for (const json& f : res->report["frames"]) {
      if (f["is_keyframe"].get<bool>()) continue;
      ++cw.inBetween;
      // Identical to the reference (PSNR +inf, null in the report): no error
      // to fit; a stand-in like the walk's 99 dB would pull the line.
      if (!f["psnr"].is_number()) continue;
      keyframe::CalibrationSample s;
      s.k0 = f["keyframes"][0].get<int>();
      s.k1 = f["keyframes"][1].get<int>();
      s.frame = f["index"].get<int>();
      s.psnrDb = f["psnr"].get<double>();
      cal.samples.push_back(s);
      cal.spacing.push_back(g);
    }
    const json& med = res->report["summary"]["psnr"]["median"];
    cw.psnrMedian = med.is_number() ? med.get<double>() : std::nan("");
    cal.walks.push_back(cw);
  }
  return cal;
}

Status writeVerifyPlot(const std::string& outDir, const keyframe::VerifiedPlan& plan,
                       int referenceKeyframes, const std::string& referenceLabel) {
  Series planned, guaranteed, reference;
  planned.label = "the round's plan (measured + predicted)";
  guaranteed.label = "guaranteed by measured frames";
  double x = 0;
  for (const keyframe::VerifyRound& r : plan.rounds) {
    planned.x.push_back(x);
    planned.y.push_back(r.keyframes);
    guaranteed.x.push_back(x);
    guaranteed.y.push_back(r.guaranteedKeyframes > 0 ? r.guaranteedKeyframes : std::nan(""));
    x += r.framesMeasured;
  }
  std::vector<Series> series{planned, guaranteed};
  if (referenceKeyframes > 0 && x > 0) {
    reference.label = referenceLabel;
    reference.markers = false;
    reference.colour = Rgba8{90, 90, 90, 255};
    reference.x = {0, x};
    reference.y = {static_cast<double>(referenceKeyframes),
                   static_cast<double>(referenceKeyframes)};
    series.push_back(reference);
  }
  PlotOptions po;
  char title[200];
  std::snprintf(title, sizeof title, "verified plan: %zu keyframes after %zu rounds%s",
                plan.keyframes.size(), plan.rounds.size() - 1,
                plan.guaranteed ? " (median guaranteed)" : " (not guaranteed)");
  po.title = title;
  po.xLabel = "in-between frames measured before the round";
  po.yLabel = "keyframes";
  return writePlot(outDir + "/verify.png", series, po);
}

Status writeCalibration(const std::string& outDir, const ScheduleCalibration& cal,
                        const keyframe::PredictorCalibration& fit, keyframe::Predictor predictor,
                        const std::vector<double>& frameOffsetDb) {
  std::string csv = "spacing,k0,k1,frame,psnr,predicted,offset\n";
  char line[200];
  for (std::size_t i = 0; i < cal.samples.size(); ++i) {
    const auto& s = cal.samples[i];
    std::snprintf(line, sizeof line, "%d,%d,%d,%d,%.4f,%.4f,%.4f\n", cal.spacing[i], s.k0, s.k1,
                  s.frame, s.psnrDb, i < fit.predictedDb.size() ? fit.predictedDb[i] : std::nan(""),
                  keyframe::pathOffsetAt(frameOffsetDb, s.frame));
    csv += line;
  }
  if (auto st = writeFileAtomic(outDir + "/calibration.csv", csv); !st) return st;
  std::vector<Series> series;
  double lo = 1e9, hi = -1e9;
  for (const CalibrationWalk& w : cal.walks) {
    Series s;
    s.label = "every " + std::to_string(w.spacing) + " frames";
    s.lines = false;
    for (std::size_t i = 0; i < cal.samples.size(); ++i) {
      if (cal.spacing[i] != w.spacing || i >= fit.predictedDb.size()) continue;
      const double x = fit.predictedDb[i], y = cal.samples[i].psnrDb;
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      s.x.push_back(x), s.y.push_back(y);
      lo = std::min({lo, x, y}), hi = std::max({hi, x, y});
    }
    series.push_back(std::move(s));
  }
  if (hi > lo) {
    Series diag;
    diag.label = "measured = predicted";
    diag.markers = false;
    diag.colour = Rgba8{90, 90, 90, 255};
    diag.x = {lo, hi};
    diag.y = {lo, hi};
    series.push_back(std::move(diag));
  }
  PlotOptions po;
  char title[200];
  std::snprintf(title, sizeof title, "%s refit: residual sd %.2f dB, Spearman %.3f",
                keyframe::predictorName(predictor), fit.residualStdDb, fit.spearman);
  po.title = title;
  po.xLabel = "predicted PSNR of the in-between frame, dB";
  po.yLabel = "measured PSNR, dB";
  return writePlot(outDir + "/calibration.png", series, po);
}

Result<std::vector<PlannedFrame>> predictSchedule(keyframe::KeyframeProbe& probe,
                                                  keyframe::Predictor predictor,
                                                  const keyframe::PsnrFit& fit,
                                                  const std::vector<int>& keyframes,
                                                  const std::vector<double>& frameOffsetDb) {
  std::vector<PlannedFrame> out;
  for (std::size_t j = 1; j < keyframes.size(); ++j)
    for (int f = keyframes[j - 1] + 1; f < keyframes[j]; ++f) {
      auto ff = keyframe::predictorFeatures(probe, predictor, keyframes[j - 1], keyframes[j], f);
      if (!ff) return ff.error();
      out.push_back({f, keyframes[j - 1], keyframes[j],
                     keyframe::predictPsnr(fit, *ff, predictor) + keyframe::pathOffsetAt(frameOffsetDb, f)});
    }
  return out;
}

Result<double> writePlannedFrames(const std::string& outDir, const std::vector<PlannedFrame>& planned,
                                  const json& reportFrames, double targetDb,
                                  const std::vector<int>& keyframes) {
  std::vector<double> measuredAt;  // by frame index; NaN where not in the report
  for (const json& f : reportFrames) {
    const int i = f["index"].get<int>();
    if (i < 0) continue;
    if (static_cast<std::size_t>(i) >= measuredAt.size())
      measuredAt.resize(static_cast<std::size_t>(i) + 1, std::nan(""));
    measuredAt[static_cast<std::size_t>(i)] = f["psnr"].is_number() ? f["psnr"].get<double>() : 99.0;
  }
  std::string csv = "frame,k0,k1,predicted,measured\n";
  char line[160];
  Series pred, meas, keys, target;
  pred.label = "predicted (planner)";
  meas.label = "measured (walk)";
  keys.label = "keyframes";
  target.label = "target";
  pred.markers = meas.markers = false;
  keys.lines = false;
  target.markers = false;
  target.colour = Rgba8{90, 90, 90, 255};
  std::vector<double> predicted;
  int lastFrame = 0;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    const PlannedFrame& p = planned[i];
    const double m = static_cast<std::size_t>(p.frame) < measuredAt.size()
                         ? measuredAt[static_cast<std::size_t>(p.frame)]
                         : std::nan("");
    std::snprintf(line, sizeof line, "%d,%d,%d,%.4f,%.4f\n", p.frame, p.k0, p.k1, p.predictedDb, m);
    csv += line;
    // A segment's line ends at its keyframe (a NaN point breaks it).
    if (i > 0 && planned[i - 1].k1 != p.k1) {
      pred.x.push_back(std::nan("")), pred.y.push_back(std::nan(""));
      meas.x.push_back(std::nan("")), meas.y.push_back(std::nan(""));
    }
    pred.x.push_back(p.frame), pred.y.push_back(p.predictedDb);
    meas.x.push_back(p.frame), meas.y.push_back(m < 99.0 ? m : std::nan(""));
    if (std::isfinite(p.predictedDb)) predicted.push_back(p.predictedDb);
    lastFrame = std::max(lastFrame, p.k1);
  }
  if (auto st = writeFileAtomic(outDir + "/planned.csv", csv); !st) return st.error();
  for (int k : keyframes) keys.x.push_back(k), keys.y.push_back(targetDb);
  target.x = {0.0, static_cast<double>(lastFrame)};
  target.y = {targetDb, targetDb};
  PlotOptions po;
  po.width = 1000;
  po.height = 420;
  po.title = std::to_string(keyframes.size()) +
             " keyframes planned: in-between PSNR, predicted vs measured";
  po.xLabel = "frame";
  po.yLabel = "PSNR, dB";
  if (auto st = writePlot(outDir + "/planned.png", {meas, pred, target, keys}, po); !st) return st.error();
  return median(std::move(predicted));  // NaN when empty
}

json calibrationJson(const ScheduleCalibration& cal, const keyframe::PredictorCalibration& fit) {
  json walks = json::array();
  for (const CalibrationWalk& w : cal.walks)
    walks.push_back({{"spacing", w.spacing},
                     {"keyframes", w.keyframes},
                     {"in_between", w.inBetween},
                     {"psnr_median", std::isfinite(w.psnrMedian) ? json(w.psnrMedian) : json(nullptr)},
                     {"walk_ms", w.walkMs}});
  return {{"walks", walks},
          {"samples", fit.samples},
          {"residual_std_db", fit.residualStdDb},
          {"spearman", std::isfinite(fit.spearman) ? json(fit.spearman) : json(nullptr)}};
}

}  // namespace hw::bench
