#include "session/keyframe_planner.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/timer.h"

namespace hw::session {

Result<PlanResult> planAdaptiveSchedule(keyframe::GeometryRenderer& renderer,
                                        const std::function<Camera(int)>& cameraOf, int frames,
                                        const PlannerOptions& opt) {
  if (opt.probeSize < 4 || opt.probeError.supersample < 1 || opt.probeError.supersample > 8 ||
      opt.probeError.blurRadius < 0 || opt.probeError.shiftTolerance < 0 ||
      !(opt.probeError.holeMse >= 0))
    return makeError("keyframe planner: expected probe size >= 4, supersample 1..8, blur radius >= 0"
                     ", shift tolerance >= 0 and hole MSE >= 0, got " +
                     std::to_string(opt.probeSize) + ", " +
                     std::to_string(opt.probeError.supersample) + ", " +
                     std::to_string(opt.probeError.blurRadius) + ", " +
                     std::to_string(opt.probeError.shiftTolerance) + ", " +
                     std::to_string(opt.probeError.holeMse));
  Stopwatch sw;
  KeyframeProbe probe(renderer, cameraOf, opt.probeSize, opt.probeError);
  auto r = planAdaptiveSchedule(probe, frames, opt);
  if (r) r->planMs = sw.ms();
  return r;
}

Result<PlanResult> planAdaptiveSchedule(KeyframeProbe& probe, int frames,
                                        const PlannerOptions& opt) {
  if (opt.minGap < 1 || opt.maxGap < opt.minGap)
    return makeError("keyframe planner: gaps must satisfy 1 <= min-gap <= max-gap, got min " +
                     std::to_string(opt.minGap) + ", max " + std::to_string(opt.maxGap));
  if (!std::isfinite(opt.targetPsnrDb))
    return makeError("keyframe planner: target PSNR must be finite");
  if (frames < 1) return makeError("keyframe planner: no frames to plan");
  if (!(std::isfinite(opt.error.sigmaDb) && opt.error.sigmaDb >= 0))
    return makeError("keyframe planner: expected an uncertainty >= 0 dB, got " +
                     std::to_string(opt.error.sigmaDb));
  if (!opt.useDefaultFit && !opt.fit.finite())
    return makeError("keyframe planner: the predictor's fit has a non-finite coefficient");
  for (double v : opt.frameOffsetDb)
    if (!std::isfinite(v)) return makeError("keyframe planner: a path offset of the prediction is not finite");
  if (opt.candidateStride < 1 || opt.framesPerSegment < 0)
    return makeError("keyframe planner: candidate stride must be >= 1 and frames per segment >= 0");
  Stopwatch sw;
  const double renderBefore = probe.renderMs();
  const int probesBefore = probe.probesRendered();
  PlanResult r;
  r.fit = opt.useDefaultFit ? defaultFit(opt.predictor) : opt.fit;
  Status failure;
  const FramePredictor predict = withPathOffsets(
      [&](int k0, int k1, int i) {
        if (!failure.ok()) return -std::numeric_limits<double>::infinity();
        auto f = predictorFeatures(probe, opt.predictor, k0, k1, i);
        if (!f) {
          failure = f.error();
          return -std::numeric_limits<double>::infinity();
        }
        return predictPsnr(r.fit, *f, opt.predictor);
      },
      opt.frameOffsetDb);
  PlanSearch search;
  search.minGap = opt.minGap;
  search.maxGap = opt.maxGap;
  search.criterion = opt.criterion;
  search.candidateStride = opt.candidateStride;
  search.framesPerSegment = opt.framesPerSegment;
  search.error = opt.error;
  r.keyframes = planKeyframes(frames, opt.targetPsnrDb, search, predict, &r.evaluations);
  if (!failure.ok()) return failure.error();
  r.planMs = sw.ms();
  r.probeRenderMs = probe.renderMs() - renderBefore;
  r.probes = probe.probesRendered() - probesBefore;
  return r;
}

}  // namespace hw::session
