#include "session/planner_verify.h"

#include <cmath>
#include <string>

#include "session/planner_calibration.h"
#include "session/planner_predictors.h"

namespace hw::session {

namespace {

// In-between frames of (k0, k1) measured ≥ target (NaN counts below).
double measuredGood(const std::vector<double>& psnr, double targetPsnrDb) {
  double n = 0;
  for (double v : psnr) n += v >= targetPsnrDb ? 1 : 0;
  return n;
}

}  // namespace

Result<VerifiedPlan> planVerified(int frames, double targetPsnrDb, const PlanSearch& search,
                                  const FramePredictor& predict, MeasuredSegments& measured,
                                  const SegmentMeasurer& measure, const VerifyOptions& opt) {
  if (frames < 3)
    return makeError("verified plan: expected at least 3 frames, got " + std::to_string(frames));
  if (search.minGap < 1 || search.maxGap < search.minGap)
    return makeError("verified plan: gaps must satisfy 1 <= min-gap <= max-gap, got min " +
                     std::to_string(search.minGap) + ", max " + std::to_string(search.maxGap));
  if (opt.maxRounds < 0 || !(opt.windowFrames >= 0) || !std::isfinite(opt.windowFrames) ||
      !(opt.prior >= 0) || !std::isfinite(targetPsnrDb) || !(opt.optimismDb >= 0) ||
      !std::isfinite(opt.optimismDb))
    return makeError(
        "verified plan: expected rounds >= 0, a finite window >= 0 frames, a prior >= 0, "
        "a finite target and a finite optimism >= 0 dB, got " +
        std::to_string(opt.maxRounds) + ", " + std::to_string(opt.windowFrames) + ", " +
        std::to_string(opt.prior) + ", " + std::to_string(targetPsnrDb) + ", " +
        std::to_string(opt.optimismDb));
  auto checkSegment = [&](const std::pair<int, int>& s, const std::vector<double>& v) -> Status {
    if (s.first < 0 || s.second >= frames || s.second - s.first < 1 ||
        v.size() != static_cast<std::size_t>(s.second - s.first - 1))
      return makeError("verified plan: a measured segment (" + std::to_string(s.first) + ", " +
                       std::to_string(s.second) + ") is outside the path or has " +
                       std::to_string(v.size()) + " frames, expected " +
                       std::to_string(std::max(s.second - s.first - 1, 0)));
    return {};
  };
  for (const auto& [s, v] : measured) HW_TRY(checkSegment(s, v));
  auto guaranteedPlan = [&](double* good) {
    return fewestKeyframesForMedian(
        frames, search.minGap, search.maxGap,
        [&](int k0, int k1) {
          const auto it = measured.find({k0, k1});
          return it == measured.end() ? 0.0 : measuredGood(it->second, targetPsnrDb);
        },
        good);
  };
  VerifiedPlan out;
  std::vector<int> plan;
  std::vector<int> sampleFrames, groups;
  std::vector<double> residuals;
  for (int round = 0;; ++round) {
    // Residuals of every measured frame, one group per segment; frames
    // identical to their reference are skipped, as the calibration skips
    // them (no error to fit).
    sampleFrames.clear(), groups.clear(), residuals.clear();
    int group = 0;
    for (const auto& [s, v] : measured) {
      for (std::size_t i = 0; i < v.size(); ++i) {
        if (!std::isfinite(v[i]) || v[i] >= kProbePsnrCap) continue;
        const int f = s.first + 1 + static_cast<int>(i);
        sampleFrames.push_back(f);
        residuals.push_back(v[i] - predict(s.first, s.second, f));
        groups.push_back(group);
      }
      ++group;
    }
    PathOffsets offsets = smoothResidualsAlongPath(frames, sampleFrames, residuals,
                                                   opt.windowFrames, opt.prior, groups);
    PredictionError err = search.error;
    if (opt.empiricalError) {
      err.setResiduals(offsets.heldOutResidualsDb);
      if (err.residualsDb.empty()) err = search.error;
    }
    VerifyRound vr;
    vr.heldOutRmsDb = offsets.heldOutRmsDb;
    std::vector<int> safe = guaranteedPlan(nullptr);
    vr.guaranteedKeyframes = static_cast<int>(safe.size());
    // The search aims one keyframe below the guaranteed schedule (when there
    // is one): the plan of that many most likely to reach the target, not the
    // fewest the optimism allows, which is rarely real and costs rounds
    // (docs/results/2026-12-02/verified_plan: table_verify.py).
    const int aim = safe.empty() ? 0 : static_cast<int>(safe.size()) - 1;
    plan = fewestKeyframesForMedian(
        frames, search.minGap, search.maxGap,
        [&](int k0, int k1) {
          const auto it = measured.find({k0, k1});
          if (it != measured.end()) return measuredGood(it->second, targetPsnrDb);
          double n = 0;
          for (int f = k0 + 1; f < k1; ++f)
            n += err.probabilityAtLeast(
                predict(k0, k1, f) + pathOffsetAt(offsets.offsetDb, f) + opt.optimismDb,
                targetPsnrDb);
          return n;
        },
        nullptr, aim);
    if (plan.empty()) plan = densestSchedule(frames, search.minGap);  // unreachable: measured next
    std::vector<std::pair<int, int>> fresh;
    for (std::size_t i = 1; i < plan.size(); ++i)
      if (plan[i] - plan[i - 1] >= 2 && !measured.count({plan[i - 1], plan[i]}))
        fresh.emplace_back(plan[i - 1], plan[i]);
    vr.keyframes = static_cast<int>(plan.size());
    vr.unmeasured = static_cast<int>(fresh.size());
    out.offsetDb = opt.windowFrames > 0 ? offsets.offsetDb : std::vector<double>{};
    // Done when the plan is measured, or when it needs no fewer keyframes
    // than the guaranteed schedule: nothing fewer is predicted to reach the
    // target.
    out.converged = fresh.empty() || (!safe.empty() && plan.size() >= safe.size());
    if (out.converged || round >= opt.maxRounds) {
      out.rounds.push_back(vr);
      break;
    }
    HW_TRY(measure(fresh, measured));
    for (const auto& s : fresh) {
      const auto it = measured.find(s);
      if (it == measured.end())
        return makeError("verified plan: segment (" + std::to_string(s.first) + ", " +
                         std::to_string(s.second) + ") was to be measured but was not");
      HW_TRY(checkSegment(s, it->second));
      vr.framesMeasured += s.second - s.first - 1;
    }
    out.rounds.push_back(vr);
  }
  double good = 0;
  std::vector<int> safe = guaranteedPlan(&good);
  if (!safe.empty()) {
    out.keyframes = std::move(safe);
    out.guaranteed = true;
    out.good = static_cast<int>(std::lround(good));
  } else {
    out.keyframes = std::move(plan);
  }
  return out;
}

}  // namespace hw::session
