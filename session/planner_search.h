#pragma once
// The keyframe planner's search: which frames become keyframes, given a
// predictor of each in-between frame's PSNR (greedy forward plans and the
// exact walk-median dynamic programme). Pure logic, no probes.
#include <functional>
#include <vector>

namespace hw::session {

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

// The densest schedule allowed: keyframes every minGap frames and frames − 1.
std::vector<int> densestSchedule(int frames, int minGap);

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

}  // namespace hw::session
