#pragma once
// The best any keyframe schedule can do on a path (the goal "the
// error-driven schedule reaches the same median PSNR as the fixed schedule
// with >= 30 % fewer keyframes"). An in-between frame f between keyframes
// k0 < f < k1 depends only on (k0, k1, f): the walk shows keyframe k0 at
// frame k0, and every frame up to k1 takes its holes from the one before it.
// So the measured PSNR of every (k0, k1, f) with k1 − k0 <= maxGap is a table
// from which the in-between PSNRs of *any* schedule with gaps <= maxGap
// follow exactly, and the fewest keyframes whose median reaches a target is
// found exactly by dynamic programming. The table is filled by walks with
// keyframes every g frames from offset o, for every 2 <= g <= maxGap and
// 0 <= o < g (maxGap·(maxGap+1)/2 − 1 walks). No predictor can beat this
// schedule: it is the bound the planner is judged against.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "session/walk.h"
#include "core/result.h"
#include "session/keyframe_planner.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::bench {

using session::WalkOptions;


// PSNR (dB) of in-between frame f warped from keyframes k0 < f < k1,
// 0 <= k0, k1 < frames, k1 − k0 <= maxGap. Unset entries are NaN.
class SegmentTable {
 public:
  SegmentTable(int frames, int maxGap);  // frames >= 1, maxGap >= 1 (checked)
  int frames() const { return frames_; }
  int maxGap() const { return maxGap_; }
  // Out-of-range (k0, k1, f) is a programming error (checked).
  void set(int k0, int k1, int f, double psnrDb);
  double at(int k0, int k1, int f) const;
  // Every in-between frame of every segment with gap <= maxGap is set.
  bool complete() const;

 private:
  std::size_t index(int k0, int k1, int f) const;
  int frames_, maxGap_;
  std::vector<double> psnr_;
};

// In-between PSNRs of a schedule (sorted keyframes, first 0, last frames−1,
// gaps <= maxGap) read from the table: median and 5th percentile as the walk
// report computes them. Error when the schedule is not of that form or
// reads an unset entry.
// lowerMedian: the ceil(n/2)-th smallest of the n values, the largest target
// that more than half of them reach (the median itself for odd n).
struct SchedulePsnr {
  double median = 0, p5 = 0, lowerMedian = 0;
  int inBetween = 0;
};
Result<SchedulePsnr> schedulePsnr(const SegmentTable& table, const std::vector<int>& keyframes);

// The fewest keyframes (0 and frames−1 included, gaps <= maxGap) such that
// more than half of the in-between frames reach targetDb (lowerMedian >=
// targetDb, hence also the interpolated median); exact, by dynamic
// programming over (number of keyframes, last keyframe) of the most frames
// >= targetDb. At least one in-between frame is required (a keyframe at
// every frame has no median). Empty keyframes when no schedule reaches it.
struct OracleSchedule {
  std::vector<int> keyframes;  // empty: unreachable
  int good = 0;                // in-between frames >= target
};
OracleSchedule fewestKeyframesForMedian(const SegmentTable& table, double targetDb);

struct ScheduleOracleOptions {
  std::string outDir = "out/schedule-oracle";
  int maxGap = 20;
  std::vector<int> fixedSpacings{4, 6, 8, 10, 15, 20};  // compared, each <= maxGap
  int referenceSpacing = 10;  // the headline compares with this fixed spacing
  WalkOptions walk;           // τ, planarity, depth, size, … (schedule, output set here)
  // The table from an earlier run's segments.csv instead of walking (same
  // scene, path, size and LOD options: not checkable from the file, the
  // caller's promise); frames and max gap must match.
  std::string tableCsv;
  // The error-driven planner (keyframe/keyframe_planner.h) scored on the same
  // table: one plan per target from plannerTargetMin to plannerTargetMax
  // (dB, predicted) in plannerTargetStep steps, for the worst-frame,
  // segment-median and walk-median criteria; its max gap is capped at maxGap.
  bool planner = true;
  session::PlannerOptions plannerOptions;
  double plannerTargetMin = 18, plannerTargetMax = 40, plannerTargetStep = 0.5;
  // The probe predictors (probe-psnr, probe-psnr+distance) scored the same
  // way on their own probes of this size (pixels, longer side; 0 = not
  // scored): worst, median, walk-median with the default fit, walk-median
  // fitted on the table, one plan's cost, targets every probeTargetStep dB;
  // oracle.json "headline.probe_predictors", probe_error.csv (the regressors
  // of every entry).
  int probePsnrSize = 64;
  double probeTargetStep = 0.25;
  session::ProbeErrorOptions probeError;
  bool probePsnrOnly = false;  // skip the planner's own predictor (its sweeps, features.csv)
  bool progress = true;
};

// Reads a segments.csv written by runScheduleOracle into a table of the
// given size; errors name the line. Every entry must be present.
Result<SegmentTable> readSegmentTable(const std::string& csvText, const std::string& source,
                                      int frames, int maxGap);

// A GL context must be current. Fills the table with walks, then writes
// oracle.json (headline, fixed and oracle curves, schedules), oracle.csv,
// oracle.png, segments.csv (the table: k0,k1,frame,psnr) and, with the planner,
// features.csv (its probe features of every entry) and probe_error.csv into outDir. Returns the oracle.json document.
Result<nlohmann::json> runScheduleOracle(const scenes::Scene& scene, const std::string& sceneLabel,
                                         const scenes::CameraPath& path,
                                         const ScheduleOracleOptions& options);

}  // namespace hw::bench
