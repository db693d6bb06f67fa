#include "report/walk_plots.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "report/plot.h"

namespace hw::report {

Status writeFrameTimes(const std::string& pngPath, const session::WalkResult& result,
                       const session::WalkOptions& opt, const std::string& sceneLabel) {
  const session::FrameTimes& t = result.frameTimes;
  Series work{"in-between frame: work (ms.frame)"}, built{"frame that built/uploaded a keyframe"},
      key{"keyframe shown"}, reference{"geometry frame, same camera (reference_ms)"},
      interval{"presented interval (ms.interval)"}, budget{"budget"};
  const Rgba8 kBlue{31, 119, 180, 255}, kRed{214, 39, 40, 255}, kGreen{44, 160, 44, 255},
      kGrey{110, 110, 110, 255}, kOrange{255, 127, 14, 255}, kPurple{148, 103, 189, 255};
  work.colour = kBlue;
  built.colour = kRed;
  key.colour = kGreen;
  reference.colour = kGrey;
  interval.colour = kOrange;
  budget.colour = kPurple;
  bool anyBudget = false;
  for (std::size_t i = 0; i < t.frame.size(); ++i) {
    const double x = t.frame[i];
    // In-between frames as one line, broken where a keyframe frame sits.
    work.x.push_back(x);
    work.y.push_back(t.keyframe[i] ? std::nan("") : t.workMs[i]);
    if (t.keyframe[i]) key.x.push_back(x), key.y.push_back(t.workMs[i]);
    if (t.builtKeyframe[i]) built.x.push_back(x), built.y.push_back(t.workMs[i]);
    reference.x.push_back(x);
    reference.y.push_back(t.referenceMs[i]);
    interval.x.push_back(x);
    interval.y.push_back(t.intervalMs[i]);
    if (t.budgetMs[i] > 0) {
      anyBudget = true;
      budget.x.push_back(x);
      budget.y.push_back(t.budgetMs[i]);
    }
  }
  work.markers = false;
  reference.markers = false;
  key.lines = built.lines = interval.lines = false;
  key.marker = Marker::kDiamond;
  built.marker = Marker::kSquare;
  interval.marker = Marker::kCircle;
  budget.markers = false;
  const bool budgetOn = opt.frameBudgetMs > 0 || opt.frameBudgetAuto;
  char budgetLabel[64] = "";
  if (opt.frameBudgetAuto)
    std::snprintf(budgetLabel, sizeof budgetLabel, ", auto budget (p%g of %d frames)",
                  opt.frameBudgetQuantile * 100, opt.frameBudgetWindow);
  else if (budgetOn)
    std::snprintf(budgetLabel, sizeof budgetLabel, ", budget %.1f ms", opt.frameBudgetMs);
  PlotOptions po;
  po.title = "Frame times: " + sceneLabel +
             (opt.asyncKeyframes && !opt.keyframeSource ? ", async keyframes" : "") + budgetLabel;
  po.xLabel = "frame";
  po.yLabel = "ms (log)";
  po.logY = true;
  po.width = 1000;
  po.height = 480;
  std::vector<Series> series{work, key, built};
  if (opt.reference) series.push_back(reference);
  if (budgetOn && opt.paceFrames) series.push_back(interval);
  if (anyBudget) series.push_back(budget);
  return writePlot(pngPath, series, po);
}

}  // namespace hw::report
