#pragma once
// The planner's predictors: cheap features of an in-between frame and its
// two keyframes, the regressors taken from them, and the PSNR fits.
#include <limits>
#include <utility>
#include <vector>

namespace hw::session {

// Cheap per-frame features of an in-between frame and its two keyframes.
struct FrameFeatures {
  // min over the two keyframes of |E − E_k| / (median eye depth of keyframe k):
  // translation relative to the scene depth (parallax ∝ this), unitless.
  double relDistance = 0;
  double angleDeg = 0;  // view direction vs the nearer keyframe's, degrees
  // Probe pixels of the frame covered by neither keyframe's forward splat
  // (sky counts as covered: the warp draws it as a backdrop), fraction.
  double holeFraction = 0;
  // Foreground keyframe's pixels: mean |log2(area in the frame / area in the
  // keyframe)|; 0 = no magnification or minification.
  double stretch = 0;
  // Where both keyframes land at the same depth (within 5 %): mean squared
  // RGB difference between the two warped probes, (0–255)² units.
  double disagreementMse = 0;
  // The warp itself at probe resolution: both keyframe probes forward-splatted
  // into the frame's own probe camera and composed like the walk (nearer
  // keyframe in front, the other behind), against the frame's own probe: mean
  // squared RGB error, (0–255)² units, holes (neither layer covers) costing
  // ProbeErrorOptions::holeMse. NaN unless computed (KeyframeProbe::probeError).
  double probeMse = std::numeric_limits<double>::quiet_NaN();
};

// Low-resolution PSNR of a probe MSE, dB: 10·log10(255²/mse), capped at
// kProbePsnrCap (the walk's value for an exact frame) when mse → 0.
constexpr double kProbePsnrCap = 99.0;
double probePsnrDb(double mse);

// HolesDistance: holes and distance together (two regressors). ProbePsnr:
// the probes actually warped and compared (FrameFeatures::probeMse; the
// frame's own probe is rendered too), regressor log10(probeMse + 1e-2), i.e.
// linear in the low-resolution PSNR. ProbePsnrDistance: that and
// log10(relDistance + 1e-3) (two regressors).
enum class Predictor {
  Distance,
  Angle,
  Holes,
  Stretch,
  Disagreement,
  HolesDistance,
  ProbePsnr,
  ProbePsnrDistance,
  // probe-psnr, distance, holes, stretch, disagreement and angle together
  // (six regressors, each as its single predictor's log): the planner's
  // every cheap feature, for a fit to the scene's own calibration walks.
  ProbePsnrFeatures
};
// "distance", "angle", "holes", "stretch", "disagreement", "holes+distance",
// "probe-psnr", "probe-psnr+distance", "probe-psnr+features"
const char* predictorName(Predictor p);
bool parsePredictor(const char* s, Predictor* out);
// The predictors computed from FrameFeatures::features() alone (ProbePsnr
// needs probeError() as well: kProbePredictors).
constexpr Predictor kAllPredictors[] = {Predictor::Distance,     Predictor::Angle,
                                        Predictor::Holes,        Predictor::Stretch,
                                        Predictor::Disagreement, Predictor::HolesDistance};
constexpr Predictor kProbePredictors[] = {Predictor::ProbePsnr, Predictor::ProbePsnrDistance,
                                          Predictor::ProbePsnrFeatures};
inline bool isProbePredictor(Predictor p) {
  return p == Predictor::ProbePsnr || p == Predictor::ProbePsnrDistance ||
         p == Predictor::ProbePsnrFeatures;
}

// The (first) regressor of a predictor: log10(feature + floor), floors keep 0
// finite; HolesDistance's first is the holes one.
double predictorValue(const FrameFeatures& f, Predictor p);
// The second regressor: log10(relDistance + 1e-3) for HolesDistance,
// ProbePsnrDistance and ProbePsnrFeatures, else 0.
double predictorValue2(const FrameFeatures& f, Predictor p);
// ProbePsnrFeatures' regressors after the first two, in order: holes,
// stretch, disagreement, angle (each as predictorValue of its single
// predictor); empty for the others.
std::vector<double> predictorValuesMore(const FrameFeatures& f, Predictor p);
// Regressors of a predictor: 1, 2 or 6.
int predictorRegressors(Predictor p);

// PSNR (dB) ≈ intercept + slope · x + slope2 · x2 + Σ more[i] · xMore[i]
// (x, x2, xMore: the regressors).
struct PsnrFit {
  PsnrFit() = default;
  PsnrFit(double i, double s, double s2 = 0, std::vector<double> m = {})
      : intercept(i), slope(s), slope2(s2), more(std::move(m)) {}
  double intercept = 0;
  double slope = 0;
  double slope2 = 0;
  std::vector<double> more;  // ProbePsnrFeatures: the slopes of its regressors 3..6
  double predict(double x, double x2 = 0) const { return intercept + slope * x + slope2 * x2; }
  bool finite() const;  // every coefficient
};
double predictPsnr(const PsnrFit& fit, const FrameFeatures& f, Predictor p);
// Least-squares fit of a predictor's regressors to measured PSNRs (pairs with
// a non-finite member are skipped); NaN coefficients when underdetermined.
PsnrFit fitPredictor(const std::vector<FrameFeatures>& f, const std::vector<double>& psnr,
                     Predictor p);
// Defaults measured on the built-in indoor scene (100k triangles, 512²,
// τ 2^11, region-local planarity, merged strips) with fixed schedules every
// 4..20 frames: see bench/schedule_study.h. On other scenes the target PSNR
// keeps its ordering but not its exact meaning.
PsnrFit defaultFit(Predictor p);

}  // namespace hw::session
