#include "session/planner_calibration.h"

#include <cmath>
#include <string>

#include "core/statistics.h"

namespace hw::session {

Result<PredictorCalibration> calibratePredictor(KeyframeProbe& probe, Predictor p,
                                                const std::vector<CalibrationSample>& samples) {
  std::vector<FrameFeatures> features;
  std::vector<double> measured;
  features.reserve(samples.size());
  measured.reserve(samples.size());
  for (const CalibrationSample& s : samples) {
    if (!(s.k0 < s.frame && s.frame < s.k1))
      return makeError("predictor calibration: expected k0 < frame < k1, got (" +
                       std::to_string(s.k0) + ", " + std::to_string(s.frame) + ", " +
                       std::to_string(s.k1) + ")");
    auto f = predictorFeatures(probe, p, s.k0, s.k1, s.frame);
    if (!f) return f.error();
    features.push_back(*f);
    measured.push_back(s.psnrDb);
  }
  PredictorCalibration c;
  c.fit = fitPredictor(features, measured, p);
  const int params = predictorRegressors(p) + 1;
  std::vector<double> pr, me;
  double ss = 0;
  c.predictedDb.assign(samples.size(), std::nan(""));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double v = predictPsnr(c.fit, features[i], p);
    if (!std::isfinite(v) || !std::isfinite(measured[i])) continue;
    c.predictedDb[i] = v;
    pr.push_back(v), me.push_back(measured[i]);
    ss += (measured[i] - v) * (measured[i] - v);
  }
  c.samples = static_cast<int>(pr.size());
  if (!c.fit.finite() || c.samples <= params)
    return makeError("predictor calibration (" + std::string(predictorName(p)) + "): expected more than " +
                     std::to_string(params) + " measured in-between frames with distinct predictor "
                     "values, got " + std::to_string(samples.size()) + " frames that do not determine a fit");
  c.residualStdDb = std::sqrt(ss / (c.samples - params));
  c.spearman = spearman(pr, me);
  return c;
}

PathOffsets smoothResidualsAlongPath(int frames, const std::vector<int>& sampleFrames,
                                     const std::vector<double>& residualsDb, double widthFrames,
                                     double prior, const std::vector<int>& sampleGroup) {
  PathOffsets out;
  out.offsetDb.assign(static_cast<std::size_t>(std::max(frames, 0)), 0.0);
  out.heldOutResidualsDb.assign(residualsDb.size(), std::nan(""));
  const std::size_t n = std::min(sampleFrames.size(), residualsDb.size());
  const bool smooth = widthFrames > 0 && std::isfinite(widthFrames);
  const bool grouped = sampleGroup.size() >= n;
  auto groupOf = [&](std::size_t i) { return grouped ? sampleGroup[i] : sampleFrames[i]; };
  // Σ w r and Σ w at frame f, leaving out the samples of group `skip` (none
  // when held is false).
  auto sums = [&](int f, bool held, int skip, double* wr, double* w) {
    *wr = 0, *w = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if ((held && groupOf(i) == skip) || !std::isfinite(residualsDb[i])) continue;
      const double d = (sampleFrames[i] - f) / widthFrames;
      if (d * d > 25) continue;
      const double wi = std::exp(-0.5 * d * d);
      *wr += wi * residualsDb[i], *w += wi;
    }
  };
  double wr = 0, w = 0;
  if (smooth)
    for (int f = 0; f < frames; ++f) {
      sums(f, false, 0, &wr, &w);
      out.offsetDb[static_cast<std::size_t>(f)] = (w + prior) > 0 ? wr / (w + prior) : 0.0;
    }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(residualsDb[i])) continue;
    double off = 0;
    if (smooth) {
      sums(sampleFrames[i], true, groupOf(i), &wr, &w);
      off = (w + prior) > 0 ? wr / (w + prior) : 0;
    }
    out.heldOutResidualsDb[i] = residualsDb[i] - off;
  }
  double ss = 0;
  int m = 0;
  for (double r : out.heldOutResidualsDb)
    if (std::isfinite(r)) ss += r * r, ++m;
  out.heldOutRmsDb = m > 0 ? std::sqrt(ss / m) : 0.0;
  return out;
}

FramePredictor withPathOffsets(FramePredictor predict, std::vector<double> offsetDb) {
  if (offsetDb.empty()) return predict;
  return [predict = std::move(predict), off = std::move(offsetDb)](int k0, int k1, int f) {
    return predict(k0, k1, f) + pathOffsetAt(off, f);
  };
}

}  // namespace hw::session
