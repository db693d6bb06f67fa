#pragma once
// Calibrating the planner's predictor on measured frames of the scene
// itself, and correcting predictions by the residuals near a frame along the
// path.
#include <cstddef>
#include <vector>

#include "core/result.h"
#include "session/planner_probe.h"
#include "session/planner_search.h"

namespace hw::session {

// A measured in-between frame: the PSNR (dB, against the geometry renderer)
// of `frame` warped from keyframes k0 < frame < k1 at full resolution.
struct CalibrationSample {
  int k0 = 0, k1 = 0, frame = 0;
  double psnrDb = 0;
};
// The predictor refitted to measured frames of this scene, path and
// resolution (the default fits come from the indoor scene, and a target's dB
// do not carry over to another scene or resolution: see defaultFit).
struct PredictorCalibration {
  PsnrFit fit;
  double residualStdDb = 0;  // of measured − predicted, n − (regressors + 1) dof
  double spearman = 0;       // rank correlation, predicted vs measured
  int samples = 0;           // used (finite)
  std::vector<double> predictedDb;  // per input sample, with `fit` (NaN when not finite)
};
// Least squares of the predictor's regressors on `samples`. Errors: probe
// failures, and too few usable samples or regressor values too alike to fit
// (what was got is said).
Result<PredictorCalibration> calibratePredictor(KeyframeProbe& probe, Predictor p,
                                                const std::vector<CalibrationSample>& samples);

// The calibration's residuals smoothed along the path. The predictor's
// errors are offsets shared by neighbouring frames (what its low-resolution
// probes miss: fine texture, alpha-tested foliage; on forza about 20
// segment-level offsets of 1-2 dB decide the walk's median), so calibration
// frames near a frame say how far off its prediction is:
//   offset(f) = Σ w_i r_i / (Σ w_i + prior),  w_i = exp(−½((f_i − f) / width)²)
// over the calibration frames f_i and their residuals r_i (measured −
// predicted; non-finite ones skipped). `prior`, in samples, pulls an offset
// made of few or distant samples toward 0. Weights below exp(−12.5) (5
// widths) are dropped.
struct PathOffsets {
  std::vector<double> offsetDb;  // per frame 0..frames−1, dB (0 when width is 0)
  // Per sample: r_i minus its frame's offset computed without the samples of
  // its own group: the error left after the correction, as a segment the
  // calibration did not walk would have it (NaN where r_i is not finite).
  std::vector<double> heldOutResidualsDb;
  double heldOutRmsDb = 0;  // root mean square of the finite held-out residuals (0 when none)
};
// sampleGroup[i]: samples with the same value are held out together (the
// planner passes one group per calibration segment: a frame's neighbours in
// its own segment share its error, so leaving out only the frame would
// understate what is left); empty = one group per frame.
PathOffsets smoothResidualsAlongPath(int frames, const std::vector<int>& sampleFrames,
                                     const std::vector<double>& residualsDb, double widthFrames,
                                     double prior = 2.0, const std::vector<int>& sampleGroup = {});

// offsetDb[frame], or 0 for a frame outside it (also when it is empty).
inline double pathOffsetAt(const std::vector<double>& offsetDb, int frame) {
  return frame >= 0 && static_cast<std::size_t>(frame) < offsetDb.size()
             ? offsetDb[static_cast<std::size_t>(frame)]
             : 0.0;
}
// `predict` with pathOffsetAt(offsetDb, frame) added.
FramePredictor withPathOffsets(FramePredictor predict, std::vector<double> offsetDb);

}  // namespace hw::session
