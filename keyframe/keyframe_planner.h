#pragma once
// Error-driven keyframe schedule: instead of a keyframe every N
// frames, walk the known camera path forward and start a new keyframe when a
// cheap predictor says an in-between frame would fall below a target PSNR.
// Backward warping (Zheng et al. 1999 §2) needs the keyframe *after* a frame
// too, so the planner looks ahead along the path, as the Rail-Track viewer
// does. The predictor works on low-resolution probes of the candidate
// keyframes (a few ms each), never on the frame's own reference image.
// A viewer without a known path would run the same test on predicted motion:
// extrapolate the eye and view direction from the last frames' velocity,
// place the candidate next keyframe at the extrapolated pose a look-ahead
// time away, and render it (asynchronously) as soon as the predictor says a
// frame between the current keyframe and that candidate drops below target;
// a wrong guess costs holes, filled from the previous frame as usual.
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/result.h"
#include "keyframe/geometry_renderer.h"

namespace hw::keyframe {

// ---- the schedule, pure logic ----------------------------------------------

// Predicted PSNR (dB) of in-between frame `frame` warped from keyframes k0 and
// k1, k0 < frame < k1.
using FramePredictor = std::function<double(int k0, int k1, int frame)>;

// What must reach the target in a segment between two keyframes.
enum class PlanCriterion {
  WorstFrame,   // every in-between frame (the predicted minimum)
  SegmentMean,  // the mean predicted PSNR of the segment's in-between frames
  // The median of the segment's in-between frames: then at least half of all
  // in-between frames are predicted ≥ target, i.e. the walk's median is.
  SegmentMedian,
  // More than half of all in-between frames of the walk predicted ≥ target,
  // with the fewest keyframes: not greedy but exact for the predictor, by
  // dynamic programming over the whole path (fewestKeyframesForMedian). A
  // segment may then be long and poor where others are short and good.
  // Costs every (k0, k1, frame) with k1 − k0 ≤ maxGap in predictor calls.
  WalkMedian,
};
const char* planCriterionName(PlanCriterion c);  // "worst", "mean", "median", "walk-median"
bool parsePlanCriterion(const char* s, PlanCriterion* out);

// Greedy forward plan: from keyframe k, the next keyframe is the farthest
// k1 ∈ [k + minGap, k + maxGap] such that every frame between k and k1 — and
// every shorter candidate before it — is predicted ≥ targetPsnrDb (the scan
// stops at the first candidate that fails). Frames 0 and frames−1 are always
// keyframes; only the last gap may be shorter than minGap. When the predictor
// is nested (a sub-segment is never predicted worse than the segment holding
// it), this is the fewest keyframes meeting the target, and a stricter target
// never gives fewer. Preconditions (checked): frames ≥ 1, 1 ≤ minGap ≤ maxGap.
// `evaluations` (optional) counts predictor calls.
// With SegmentMean/SegmentMedian the segment's mean/median must reach the
// target instead (the nesting argument then holds only approximately).
std::vector<int> planKeyframes(int frames, double targetPsnrDb, int minGap, int maxGap,
                               const FramePredictor& predict, long* evaluations = nullptr,
                               PlanCriterion criterion = PlanCriterion::WorstFrame);

// The fewest keyframes (frame 0 and frames−1 included; gaps from minGap to
// maxGap, only the last may be shorter) such that more than half of the
// in-between frames are predicted ≥ targetPsnrDb; exact, by dynamic
// programming over (keyframes so far, last keyframe) of the most frames
// predicted ≥ target. Empty when no schedule reaches it (at least one
// in-between frame is required). `good` (optional): frames ≥ target.
// Preconditions (checked): frames ≥ 1, 1 ≤ minGap ≤ maxGap.
// `error`: how far measured PSNRs fall from predicted ones. Unless none(),
// each frame counts as its probability of reaching the target
// (PredictionError::probabilityAtLeast), and the expected number must exceed
// half (`good`: that expectation, rounded down). The plain count rewards
// schedules whose median frame is predicted just above the target, which the
// predictor's errors then put below it about half the time; the expected
// count does not.
struct PredictionError;
std::vector<int> fewestKeyframesForMedian(int frames, double targetPsnrDb, int minGap, int maxGap,
                                          const FramePredictor& predict,
                                          long* evaluations = nullptr, int* good = nullptr,
                                          const PredictionError* error = nullptr);

// The same dynamic programme on any count: segmentGood(k0, k1) is the
// (expected) number of segment (k0, k1)'s in-between frames reaching the
// target, in [0, k1 − k0 − 1]; called once for every segment with
// 2 ≤ k1 − k0 ≤ maxGap. `good` (optional): the chosen schedule's sum.
// minKeyframes: the fewest keyframes *at least* this many (the schedule of
// that many with the most good frames, when fewer already reach the target).
using SegmentGood = std::function<double(int k0, int k1)>;
std::vector<int> fewestKeyframesForMedian(int frames, int minGap, int maxGap,
                                          const SegmentGood& segmentGood, double* good = nullptr,
                                          int minKeyframes = 0);

// The predictor's error model for the walk-median plan: measured = predicted
// + e, with e either normal with standard deviation sigmaDb, or distributed
// as the calibration frames' residuals (measured − predicted), when given:
// their empirical distribution keeps the skew and heavy tails a normal
// misses. Neither: the plain count (predicted ≥ target).
struct PredictionError {
  double sigmaDb = 0;                // ≥ 0; used when residualsDb is empty
  std::vector<double> residualsDb;   // sorted ascending (setResiduals sorts)
  bool none() const { return residualsDb.empty() && !(sigmaDb > 0); }
  void setResiduals(std::vector<double> r);  // non-finite values dropped
  // P(predicted + e ≥ target): Φ((predicted − target) / σ), or the fraction
  // of residuals ≥ target − predicted; with neither 1 or 0. NaN → 0.
  double probabilityAtLeast(double predictedDb, double targetPsnrDb) const;
};

// The same with the search made cheaper: candidates for the next keyframe
// every candidateStride frames (from k + minGap; k + maxGap and the last frame
// are always tried), and at most framesPerSegment evenly spaced in-between
// frames tested per candidate (0 = all). Fewer probes and predictor calls,
// at the risk of missing a bad frame between the tested ones.
struct PlanSearch {
  int minGap = 2;
  int maxGap = 30;
  PlanCriterion criterion = PlanCriterion::WorstFrame;
  int candidateStride = 1;   // ≥ 1
  int framesPerSegment = 0;  // ≥ 0
  PredictionError error;  // WalkMedian only: see fewestKeyframesForMedian
};
std::vector<int> planKeyframes(int frames, double targetPsnrDb, const PlanSearch& search,
                               const FramePredictor& predict, long* evaluations = nullptr);

// ---- the predictor ----------------------------------------------------------

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

// How KeyframeProbe::probeError measures a composed probe warp.
// Defaults: the best measured on the schedule-oracle tables (indoor and
// q3:oa_dm5, 256², docs/results/2026-12-01/schedule/README.md).
struct ProbeErrorOptions {
  // Squared error charged per hole pixel, (0–255)² units: the walk fills holes
  // from the previous frame, usually close but not exact.
  double holeMse = 1000;
  // Compare box-blurred images (radius in probe pixels, 0 = none): textures
  // alias at 64 px, and a sub-pixel shift of an aliased texture is not an error
  // the full-resolution warp makes.
  int blurRadius = 1;
  // Without blur: each composed pixel is compared with the closest-matching
  // reference pixel within this many probe pixels (0 = the same pixel): a
  // splat rounds positions to whole probe pixels, the warp does not.
  int shiftTolerance = 0;
  // Holes take the previous frame's composed probe, as the walk fills them
  // (the segment's chain from keyframe k0 on), instead of costing holeMse.
  bool previousFill = true;
  // Render probes at supersample× the probe size and box-filter colour down
  // (depth: the nearest sample): anti-aliased probes. 1 = off.
  int supersample = 2;
};

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

// Least-squares line through (x, y) pairs (pairs with a non-finite member are
// skipped); {nan, nan} with fewer than two distinct x.
PsnrFit fitLine(const std::vector<double>& x, const std::vector<double>& y);
// Pearson and Spearman (rank) correlation; NaN when undefined.
double pearson(const std::vector<double>& x, const std::vector<double>& y);
double spearman(const std::vector<double>& x, const std::vector<double>& y);

// Low-resolution probes (colour + eye depth) of path frames, rendered on
// demand and kept, and the features of a frame between two of them. The
// probe camera is the path camera with the longer side scaled to probeSize
// pixels (same field of view).
class KeyframeProbe {
 public:
  // `renderer` must outlive the probe; it is used at probe resolution (times
  // error.supersample).
  KeyframeProbe(GeometryRenderer& renderer, std::function<Camera(int)> cameraOf, int probeSize,
                ProbeErrorOptions error = {});
  ~KeyframeProbe();
  KeyframeProbe(const KeyframeProbe&) = delete;
  KeyframeProbe& operator=(const KeyframeProbe&) = delete;

  // Features are memoised per (k0, k1, frame): repeated plans on one probe
  // (e.g. a search for the target giving N keyframes) cost little.
  Result<FrameFeatures> features(int k0, int k1, int frame);
  // FrameFeatures::probeMse of (k0, k1, frame), memoised; renders the frame's
  // probe too (with previousFill, those of the frames before it in the
  // segment as well). A frame equal to a keyframe's camera gives 0. Keyframe probes
  // warped into a frame are cached (least recently used, ~64 MB).
  Result<double> probeError(int k0, int k1, int frame);
  // FrameFeatures::relDistance alone (no splats), for ProbePsnrDistance.
  Result<double> relDistance(int k0, int k1, int frame);
  int probesRendered() const { return probesRendered_; }
  double renderMs() const { return renderMs_; }  // probe draws + readbacks
  double splatMs() const { return splatMs_; }    // CPU forward splats
  int probeSize() const { return probeSize_; }
  const ProbeErrorOptions& errorOptions() const { return error_; }

  struct Probe;  // one rendered low-resolution keyframe (keyframe_planner.cpp)
 private:
  Result<const Probe*> probe(int frame);
  Camera probeCamera(int frame) const;
  struct Warped;
  Result<const Warped*> warped(int key, int frame);
  // One frame's composed probe (left in scratch) and its error; holes from
  // `previous` when given (same size), else charged holeMse.
  Result<double> composeAndCompare(int k0, int k1, int frame, const std::vector<Rgba8>* previous);
  struct Chain {
    int frame = -1;             // the last frame composed
    std::vector<Rgba8> image;   // its composed probe
  };
  std::map<std::pair<int, int>, Chain> chains_;

  GeometryRenderer& renderer_;
  std::function<Camera(int)> cameraOf_;
  int probeSize_;
  ProbeErrorOptions error_;
  std::map<int, std::unique_ptr<Probe>> probes_;
  std::map<std::tuple<int, int, int>, FrameFeatures> memo_;
  std::map<std::tuple<int, int, int>, double> errorMemo_, distanceMemo_;
  std::map<std::pair<int, int>, std::unique_ptr<Warped>> warpCache_;
  long warpTick_ = 0;
  int probesRendered_ = 0;
  double renderMs_ = 0, splatMs_ = 0;
  struct Scratch;
  std::unique_ptr<Scratch> scratch_;
};

struct PlannerOptions {
  double targetPsnrDb = 24.0;  // in-between frames should not fall below this, dB (predicted)
  int minGap = 2;              // frames between consecutive keyframes (≥ 1)
  int maxGap = 30;             // frames (≥ minGap)
  // holes+distance: on indoor a 1 dB higher median than holes alone at equal
  // keyframe count (p5 both well above fixed); the best fit on q3:oa_dm5.
  Predictor predictor = Predictor::HolesDistance;
  PlanCriterion criterion = PlanCriterion::WorstFrame;
  bool useDefaultFit = true;  // fit = defaultFit(predictor)
  PsnrFit fit;                // used when !useDefaultFit
  int probeSize = 64;         // pixels, longer side of the probes
  ProbeErrorOptions probeError;  // probe-psnr only
  int candidateStride = 1;    // see PlanSearch
  int framesPerSegment = 0;   // see PlanSearch (0 = every in-between frame)
  PredictionError error;      // walk-median: the predictor's error (see PlanSearch)
  std::vector<double> frameOffsetDb;  // added to frame i's prediction (PathOffsets; empty = none)
};

struct PlanResult {
  std::vector<int> keyframes;  // sorted, first 0, last frames−1
  double planMs = 0;           // whole plan: probes, splats, search (wall clock)
  double probeRenderMs = 0;    // of which probe renders
  int probes = 0;              // probe keyframes rendered
  long evaluations = 0;        // predictor calls
  PsnrFit fit;                 // the fit used
};

// The features predictor `p` reads for (k0, k1, frame): probeMse (and
// relDistance) alone for probe-psnr (+distance), KeyframeProbe::features()
// and probeMse for probe-psnr+features, features() for the others.
Result<FrameFeatures> predictorFeatures(KeyframeProbe& probe, Predictor p, int k0, int k1,
                                        int frame);

// ---- calibration on the scene itself ----------------------------------------

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

// ---- verified plans: measure the segments a plan picks ----------------------

// A predictor's error is shared by a segment's frames, and a plan picks the
// segments predicted best, i.e. those it overrates (on forza at 512² the
// calibrated planner's segment-level error is 0.8 dB rms, and the fewest
// keyframes reaching fixed-10's median need it well under 0.5 dB: docs/
// results/2026-12-02/calibration_window). So measure them: walk the planned
// segments not measured yet at the walk's own resolution, count their frames
// exactly, correct the predictions near them along the path by their
// residuals, and plan again, aiming one keyframe below the guaranteed
// schedule (below); until a plan is made of measured segments only, or needs
// no fewer keyframes than the guaranteed schedule.
// The schedule returned is the fewest keyframes whose median measured frames
// alone guarantee: more than half of its in-between frames are measured ≥
// the target, a segment not measured counting as below it.

// Measured PSNRs (dB) of whole segments: (k0, k1) → in-between frames k0+1 ..
// k1−1 in order; a frame identical to its reference counts kProbePsnrCap, as
// the walk's statistics count it.
using MeasuredSegments = std::map<std::pair<int, int>, std::vector<double>>;
// Measures every segment of `segments` into `out` (every frame).
using SegmentMeasurer =
    std::function<Status(const std::vector<std::pair<int, int>>& segments, MeasuredSegments& out)>;

struct VerifyOptions {
  int maxRounds = 8;  // rounds that measure (≥ 0); 0 = plan once, measure nothing
  // Path offsets (smoothResidualsAlongPath) from the residuals of every
  // measured frame, frames; 0 = none.
  double windowFrames = 0;
  double prior = 2.0;  // samples, as smoothResidualsAlongPath
  // The error model of unmeasured frames: the measured frames' residuals left
  // by the offsets (held out by segment) instead of search.error.
  bool empiricalError = true;
  // Added to every unmeasured frame's prediction while searching, dB (≥ 0):
  // segments that might do better than predicted get measured too. The
  // schedule returned stays a guaranteed one, so optimism costs
  // measurements, never the target; converged with it means no schedule
  // with fewer keyframes is predicted to reach the target even that much
  // above its predictions.
  double optimismDb = 0;
};

struct VerifyRound {
  int keyframes = 0;       // this round's plan
  int unmeasured = 0;      // of its segments, not measured before the round
  int framesMeasured = 0;  // in-between frames this round measured
  // The fewest keyframes whose median measured frames alone guarantee,
  // before the round's measurements (0: none yet).
  int guaranteedKeyframes = 0;
  double heldOutRmsDb = 0;  // what the offsets leave of the measured frames' residuals
};

struct VerifiedPlan {
  std::vector<int> keyframes;
  // The last plan was all measured segments, or needed no fewer keyframes
  // than the guaranteed schedule (the search found nothing better to measure).
  bool converged = false;
  // keyframes: measured frames alone reach the target for more than half of
  // its in-between frames (segments not measured count as missing it), so
  // its median is at least the target; false: none does, the last plan.
  bool guaranteed = false;
  int good = 0;  // guaranteed: its in-between frames measured ≥ target (a lower bound)
  std::vector<VerifyRound> rounds;
  std::vector<double> offsetDb;  // the last round's path offsets (empty: window 0)
};

// `predict`: the calibrated predictor without path offsets. `measured`
// starts with what is known (the calibration walks' segments) and gains what
// the rounds measure. search.criterion is ignored (walk-median).
Result<VerifiedPlan> planVerified(int frames, double targetPsnrDb, const PlanSearch& search,
                                  const FramePredictor& predict, MeasuredSegments& measured,
                                  const SegmentMeasurer& measure, const VerifyOptions& options);

// Plans an error-driven schedule for `frames` frames of a path. A GL context
// must be current; `renderer` draws the probes (its scene is the walk's).
Result<PlanResult> planAdaptiveSchedule(GeometryRenderer& renderer,
                                        const std::function<Camera(int)>& cameraOf, int frames,
                                        const PlannerOptions& options);
// The same on an existing probe (its probes and memoised features are
// reused; planMs then excludes what earlier plans already paid for).
Result<PlanResult> planAdaptiveSchedule(KeyframeProbe& probe, int frames,
                                        const PlannerOptions& options);

}  // namespace hw::keyframe
