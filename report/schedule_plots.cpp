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

Status writeVerifyPlot(const std::string& outDir, const VerifyPlot& plan) {
  Series planned, guaranteed, reference;
  planned.label = "the round's plan (measured + predicted)";
  guaranteed.label = "guaranteed by measured frames";
  double x = 0;
  for (const VerifyRoundPoint& r : plan.rounds) {
    planned.x.push_back(x);
    planned.y.push_back(r.keyframes);
    guaranteed.x.push_back(x);
    guaranteed.y.push_back(r.guaranteedKeyframes > 0 ? r.guaranteedKeyframes : std::nan(""));
    x += r.framesMeasured;
  }
  std::vector<Series> series{planned, guaranteed};
  if (plan.referenceKeyframes > 0 && x > 0) {
    reference.label = plan.referenceLabel;
    reference.markers = false;
    reference.colour = Rgba8{90, 90, 90, 255};
    reference.x = {0, x};
    reference.y = {static_cast<double>(plan.referenceKeyframes),
                   static_cast<double>(plan.referenceKeyframes)};
    series.push_back(reference);
  }
  PlotOptions po;
  char title[200];
  std::snprintf(title, sizeof title, "verified plan: %zu keyframes after %zu rounds%s",
                plan.keyframes, plan.rounds.size() - 1,
                plan.guaranteed ? " (median guaranteed)" : " (not guaranteed)");
  po.title = title;
  po.xLabel = "in-between frames measured before the round";
  po.yLabel = "keyframes";
  return writePlot(outDir + "/verify.png", series, po);
}


Status writeCalibration(const std::string& outDir, const CalibrationPlot& cal) {
  std::string csv = "spacing,k0,k1,frame,psnr,predicted,offset\n";
  char line[200];
  for (const CalibrationPoint& s : cal.points) {
    std::snprintf(line, sizeof line, "%d,%d,%d,%d,%.4f,%.4f,%.4f\n", s.spacing, s.k0, s.k1,
                  s.frame, s.psnrDb, s.predictedDb, s.offsetDb);
    csv += line;
  }
  if (auto st = writeFileAtomic(outDir + "/calibration.csv", csv); !st) return st;
  std::vector<Series> series;
  double lo = 1e9, hi = -1e9;
  for (int spacing : cal.walkSpacings) {
    Series s;
    s.label = "every " + std::to_string(spacing) + " frames";
    s.lines = false;
    for (const CalibrationPoint& p : cal.points) {
      if (p.spacing != spacing) continue;
      const double x = p.predictedDb, y = p.psnrDb;
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
                cal.predictor.c_str(), cal.residualStdDb, cal.spearman);
  po.title = title;
  po.xLabel = "predicted PSNR of the in-between frame, dB";
  po.yLabel = "measured PSNR, dB";
  return writePlot(outDir + "/calibration.png", series, po);
}


Result<double> writePlannedFrames(const std::string& outDir, const std::vector<PlannedPoint>& planned,
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
    const PlannedPoint& p = planned[i];
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


Status addPlannerToWalkReport(const std::string& outDir, const std::vector<PlannedPoint>& predicted,
                              double targetPsnrDb, const json& plannerSummary) {
  const std::string path = outDir + "/report.json";
  auto text = readFile(path);
  if (!text) return text.error();
  json report = json::parse(*text, nullptr, false);
  if (report.is_discarded()) return makeError("cannot parse " + path);
  report["summary"]["keyframe_schedule"] = "adaptive";
  auto predMedian =
      writePlannedFrames(outDir, predicted, report["frames"], targetPsnrDb,
                         report["summary"]["keyframe_frames"].get<std::vector<int>>());
  if (!predMedian) return predMedian.error();
  json planner = plannerSummary;
  planner["predicted_psnr_median"] = std::isfinite(*predMedian) ? json(*predMedian) : json(nullptr);
  report["summary"]["planner"] = planner;
  return writeFileAtomic(path, report.dump(1));
}

}  // namespace hw::report
