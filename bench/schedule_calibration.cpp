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
    for (const json& f : res->report["frames"]) {
      if (f["is_keyframe"].get<bool>()) continue;
      keyframe::CalibrationSample s;
      s.k0 = f["keyframes"][0].get<int>();
      s.k1 = f["keyframes"][1].get<int>();
      s.frame = f["index"].get<int>();
      s.psnrDb = f["psnr"].is_number() ? f["psnr"].get<double>() : 99.0;  // identical, as the walk
      cal.samples.push_back(s);
      cal.spacing.push_back(g);
      ++cw.inBetween;
    }
    const json& med = res->report["summary"]["psnr"]["median"];
    cw.psnrMedian = med.is_number() ? med.get<double>() : std::nan("");
    cal.walks.push_back(cw);
  }
  return cal;
}

Status writeCalibration(const std::string& outDir, const ScheduleCalibration& cal,
                        const keyframe::PredictorCalibration& fit, keyframe::Predictor predictor) {
  std::string csv = "spacing,k0,k1,frame,psnr,predicted\n";
  char line[160];
  for (std::size_t i = 0; i < cal.samples.size(); ++i) {
    const auto& s = cal.samples[i];
    std::snprintf(line, sizeof line, "%d,%d,%d,%d,%.4f,%.4f\n", cal.spacing[i], s.k0, s.k1, s.frame,
                  s.psnrDb, i < fit.predictedDb.size() ? fit.predictedDb[i] : std::nan(""));
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
      if (!std::isfinite(x) || !std::isfinite(y) || y >= 99.0) continue;
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
  std::snprintf(title, sizeof title, "%s refitted on %d frames: residual sd %.2f dB, Spearman %.3f",
                keyframe::predictorName(predictor), fit.samples, fit.residualStdDb, fit.spearman);
  po.title = title;
  po.xLabel = "predicted PSNR of the in-between frame, dB";
  po.yLabel = "measured PSNR, dB";
  return writePlot(outDir + "/calibration.png", series, po);
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
