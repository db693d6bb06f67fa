#include "app/walk_plots.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/file_io.h"
#include "report/schedule_plots.h"
#include "report/walk_plots.h"
#include "session/frame_mode.h"
#include "session/planner_calibration.h"
#include "session/planner_predictors.h"

namespace hw::app {
namespace {

report::DrawnAs drawnAs(session::FrameKind k) {
  switch (k) {
    case session::FrameKind::Geometry: return report::DrawnAs::Geometry;
    case session::FrameKind::Warp: return report::DrawnAs::Warp;
    case session::FrameKind::Keyframe: return report::DrawnAs::Keyframe;
  }
  return report::DrawnAs::Geometry;
}

report::CalibrationPlot calibrationPlot(const session::PlannedWalk& planned) {
  const session::ScheduleCalibration& cal = *planned.calibration;
  const session::PredictorCalibration& fit = planned.calibrationFit;
  report::CalibrationPlot plot;
  for (std::size_t i = 0; i < cal.samples.size(); ++i) {
    const session::CalibrationSample& s = cal.samples[i];
    plot.points.push_back({cal.spacing[i], s.k0, s.k1, s.frame, s.psnrDb,
                           i < fit.predictedDb.size() ? fit.predictedDb[i] : std::nan(""),
                           session::pathOffsetAt(planned.calibrationOffsetDb, s.frame)});
  }
  for (const session::CalibrationWalk& w : cal.walks) plot.walkSpacings.push_back(w.spacing);
  plot.predictor = session::predictorName(planned.predictor);
  plot.residualStdDb = fit.residualStdDb;
  plot.spearman = fit.spearman;
  return plot;
}

report::VerifyPlot verifyPlot(const session::PlannedWalk& planned) {
  const session::VerifiedPlan& v = *planned.verified;
  report::VerifyPlot plot;
  for (const session::VerifyRound& r : v.rounds)
    plot.rounds.push_back({r.keyframes, r.guaranteedKeyframes, r.framesMeasured});
  plot.keyframes = v.keyframes.size();
  plot.guaranteed = v.guaranteed;
  plot.referenceKeyframes = planned.referenceKeyframes;
  plot.referenceLabel = planned.referenceLabel;
  return plot;
}

}  // namespace

Status writeFrameTimes(const std::string& pngPath, const session::WalkResult& result,
                       const session::WalkOptions& opt, const std::string& sceneLabel) {
  const session::FrameTimes& t = result.frameTimes;
  report::FrameTimesData data{t.frame, {}, t.builtKeyframe, t.workMs, t.intervalMs,
                              t.budgetMs, t.referenceMs, t.floorMs};
  for (session::FrameKind k : t.kind) data.kind.push_back(drawnAs(k));
  const bool budgetOn = opt.frameBudgetMs > 0 || opt.frameBudgetAuto;
  char budgetLabel[64] = "";
  if (opt.frameBudgetAuto)
    std::snprintf(budgetLabel, sizeof budgetLabel, ", auto budget (p%g of %d frames)",
                  opt.frameBudgetQuantile * 100, opt.frameBudgetWindow);
  else if (budgetOn)
    std::snprintf(budgetLabel, sizeof budgetLabel, ", budget %.1f ms", opt.frameBudgetMs);
  report::FrameTimesLook look;
  look.title = "Frame times: " + sceneLabel + ", mode " + session::frameModeName(opt.mode) +
               (opt.asyncKeyframes && !opt.keyframeSource ? ", async keyframes" : "") + budgetLabel;
  look.reference = opt.reference;
  look.interval = budgetOn && opt.paceFrames;
  return report::writeFrameTimes(pngPath, data, look);
}

Status writeStrips(const std::string& outDir, const session::WalkResult& result) {
  return report::writeStrips(outDir, result.strips, result.report["summary"]["strips"]);
}

Status writePlannedWalkPlots(const std::string& outDir, const session::PlannedWalk& planned) {
  if (planned.calibration) {
    HW_TRY(ensureWritableDir(outDir));
    HW_TRY(report::writeCalibration(outDir, calibrationPlot(planned)));
  }
  if (planned.verified) HW_TRY(report::writeVerifyPlot(outDir, verifyPlot(planned)));
  return {};
}

Status addPlannerToWalkReport(const std::string& outDir, const session::PlannedWalk& planned) {
  std::vector<report::PlannedPoint> predicted;
  for (const session::PlannedFrame& p : planned.predicted)
    predicted.push_back({p.frame, p.k0, p.k1, p.predictedDb});
  return report::addPlannerToWalkReport(outDir, predicted, planned.targetPsnrDb, planned.planner);
}

}  // namespace hw::app
