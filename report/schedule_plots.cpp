#include "report/schedule_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/file_io.h"
#include "core/timer.h"
#include "report/plot.h"

namespace hw::report {

using nlohmann::json;
using session::CalibrationWalk;

Status writeVerifyPlot(const std::string& outDir, const session::VerifiedPlan& plan,
                       int referenceKeyframes, const std::string& referenceLabel) {
  Series planned, guaranteed, reference;
  planned.label = "the round's plan (measured + predicted)";
  guaranteed.label = "guaranteed by measured frames";
  double x = 0;
  for (const session::VerifyRound& r : plan.rounds) {
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
                        const session::PredictorCalibration& fit, session::Predictor predictor,
                        const std::vector<double>& frameOffsetDb) {
  std::string csv = "spacing,k0,k1,frame,psnr,predicted,offset\n";
  char line[200];
  for (std::size_t i = 0; i < cal.samples.size(); ++i) {
    const auto& s = cal.samples[i];
    std::snprintf(line, sizeof line, "%d,%d,%d,%d,%.4f,%.4f,%.4f\n", cal.spacing[i], s.k0, s.k1,
                  s.frame, s.psnrDb, i < fit.predictedDb.size() ? fit.predictedDb[i] : std::nan(""),
                  session::pathOffsetAt(frameOffsetDb, s.frame));
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
                session::predictorName(predictor), fit.residualStdDb, fit.spearman);
  po.title = title;
  po.xLabel = "predicted PSNR of the in-between frame, dB";
  po.yLabel = "measured PSNR, dB";
  return writePlot(outDir + "/calibration.png", series, po);
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


Status writePlannedWalkPlots(const std::string& outDir, const session::PlannedWalk& planned) {
  if (planned.calibration) {
    HW_TRY(ensureWritableDir(outDir));
    HW_TRY(writeCalibration(outDir, *planned.calibration, planned.calibrationFit,
                            planned.predictor, planned.calibrationOffsetDb));
  }
  if (planned.verified)
    HW_TRY(writeVerifyPlot(outDir, *planned.verified, planned.referenceKeyframes,
                           planned.referenceLabel));
  return {};
}

Status addPlannerToWalkReport(const std::string& outDir, const session::PlannedWalk& planned) {
  using nlohmann::json;
  const std::string path = outDir + "/report.json";
  auto text = readFile(path);
  if (!text) return text.error();
  json report = json::parse(*text, nullptr, false);
  if (report.is_discarded()) return makeError("cannot parse " + path);
  report["summary"]["keyframe_schedule"] = "adaptive";
  auto predMedian =
      writePlannedFrames(outDir, planned.predicted, report["frames"], planned.targetPsnrDb,
                         report["summary"]["keyframe_frames"].get<std::vector<int>>());
  if (!predMedian) return predMedian.error();
  json planner = planned.planner;
  planner["predicted_psnr_median"] = std::isfinite(*predMedian) ? json(*predMedian) : json(nullptr);
  report["summary"]["planner"] = planner;
  return writeFileAtomic(path, report.dump(1));
}

}  // namespace hw::report
