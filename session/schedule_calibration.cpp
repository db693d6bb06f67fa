#include "session/schedule_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/file_io.h"
#include "core/json_util.h"
#include "core/timer.h"
#include "keyframe/keyframe_cache.h"

namespace hw::session {

using nlohmann::json;

namespace {

// A walk that only measures: no output, the reference on, nothing that
// depends on timing (a budget's refreshes) or on a baked database.
WalkOptions measuringWalk(const WalkOptions& base, int frames, bool progress) {
  WalkOptions o = base;
  o.outDir.clear();
  o.saveFrames = false;
  o.strips = 0;
  o.keepFrames = true;
  o.reference = true;
  o.progress = progress;
  o.maxFrames = frames;
  o.keyframeSource = {};
  o.asyncKeyframes = false;
  o.frameBudgetMs = 0;
  o.frameBudgetAuto = false;
  o.onlySegments.clear();
  return o;
}

// The walk report's in-between frames into `out` by segment (a null PSNR:
// identical to the reference, counted kProbePsnrCap as the walk counts it).
void addMeasured(const json& frames, session::MeasuredSegments& out) {
  for (const json& f : frames) {
    if (f["is_keyframe"].get<bool>()) continue;
    const int k0 = f["keyframes"][0].get<int>(), k1 = f["keyframes"][1].get<int>();
    const int i = f["index"].get<int>();
    auto& v = out[{k0, k1}];
    v.resize(static_cast<std::size_t>(std::max(k1 - k0 - 1, 0)), std::nan(""));
    if (i > k0 && i < k1)
      v[static_cast<std::size_t>(i - k0 - 1)] =
          f["psnr"].is_number() ? f["psnr"].get<double>() : session::kProbePsnrCap;
  }
}

}  // namespace

Status measureSegments(const scenes::Scene& scene, const std::string& sceneLabel,
                       const scenes::CameraPath& path, int frames,
                       const std::vector<std::pair<int, int>>& segments, const WalkOptions& base,
                       session::MeasuredSegments& out) {
  if (segments.empty()) return {};
  WalkOptions o = measuringWalk(base, frames, false);
  o.onlySegments = segments;
  o.keyframeFrames.clear();
  for (const auto& [a, b] : segments) o.keyframeFrames.push_back(a), o.keyframeFrames.push_back(b);
  o.keyframeFrames.push_back(0);
  o.keyframeFrames.push_back(frames - 1);
  std::sort(o.keyframeFrames.begin(), o.keyframeFrames.end());
  o.keyframeFrames.erase(std::unique(o.keyframeFrames.begin(), o.keyframeFrames.end()),
                         o.keyframeFrames.end());
  auto res = runWalk(scene, sceneLabel, path, o);
  if (!res) return res.error();
  session::MeasuredSegments got;
  addMeasured(res->report["frames"], got);
  for (const auto& s : segments) {
    if (s.second - s.first < 2) continue;  // no in-between frame
    const auto it = got.find(s);
    if (it == got.end())
      return makeError("measuring segments: the walk did not reach segment (" +
                       std::to_string(s.first) + ", " + std::to_string(s.second) + ")");
    out[s] = it->second;
  }
  return {};
}

Result<ScheduleCalibration> runCalibrationWalks(const scenes::Scene& scene,
                                                const std::string& sceneLabel,
                                                const scenes::CameraPath& path, int frames,
                                                const std::vector<int>& spacings,
                                                const WalkOptions& base, bool progress) {
  if (frames < 3 || frames > path.frames)
    return makeError("calibration walks: expected 3.." + std::to_string(path.frames) +
                     " frames, got " + std::to_string(frames));
  ScheduleCalibration cal;
  for (std::size_t w = 0; w < spacings.size(); ++w) {
    const int g = spacings[w];
    if (g < 2 || g > frames - 1)
      return makeError("calibration walks: a spacing leaves no in-between frame or exceeds the path: "
                       "expected 2.." + std::to_string(frames - 1) + " frames, got " + std::to_string(g));
    WalkOptions o = measuringWalk(base, frames, progress);
    o.keyframeFrames = keyframe::KeyframeSchedule{frames, g, {}}.keyframes();
    if (progress)
      std::fprintf(stderr, "calibration walk %zu/%zu: keyframes every %d frames\n", w + 1,
                   spacings.size(), g);
    Stopwatch sw;
    auto res = runWalk(scene, sceneLabel, path, o);
    if (!res) return res.error();
    CalibrationWalk cw;
    cw.spacing = g;
    cw.keyframes = static_cast<int>(o.keyframeFrames.size());
    cw.walkMs = sw.ms();
    addMeasured(res->report["frames"], cal.measured);
    for (const json& f : res->report["frames"]) {
      if (f["is_keyframe"].get<bool>()) continue;
      ++cw.inBetween;
      // Identical to the reference (PSNR +inf, null in the report): no error
      // to fit; a stand-in like the walk's 99 dB would pull the line.
      if (!f["psnr"].is_number()) continue;
      session::CalibrationSample s;
      s.k0 = f["keyframes"][0].get<int>();
      s.k1 = f["keyframes"][1].get<int>();
      s.frame = f["index"].get<int>();
      s.psnrDb = f["psnr"].get<double>();
      cal.samples.push_back(s);
      cal.spacing.push_back(g);
    }
    const json& med = res->report["summary"]["psnr"]["median"];
    cw.psnrMedian = med.is_number() ? med.get<double>() : std::nan("");
    cal.walks.push_back(cw);
  }
  return cal;
}

Result<std::vector<PlannedFrame>> predictSchedule(session::KeyframeProbe& probe,
                                                  session::Predictor predictor,
                                                  const session::PsnrFit& fit,
                                                  const std::vector<int>& keyframes,
                                                  const std::vector<double>& frameOffsetDb) {
  std::vector<PlannedFrame> out;
  for (std::size_t j = 1; j < keyframes.size(); ++j)
    for (int f = keyframes[j - 1] + 1; f < keyframes[j]; ++f) {
      auto ff = session::predictorFeatures(probe, predictor, keyframes[j - 1], keyframes[j], f);
      if (!ff) return ff.error();
      out.push_back({f, keyframes[j - 1], keyframes[j],
                     session::predictPsnr(fit, *ff, predictor) + session::pathOffsetAt(frameOffsetDb, f)});
    }
  return out;
}

json fitJson(const session::PsnrFit& f) {
  json j = {{"intercept", finiteOrNull(f.intercept)},
            {"slope", finiteOrNull(f.slope)},
            {"slope2", finiteOrNull(f.slope2)}};
  if (!f.more.empty()) {
    json m = json::array();
    for (double v : f.more) m.push_back(finiteOrNull(v));
    j["more"] = m;
  }
  return j;
}

json calibrationJson(const ScheduleCalibration& cal, const session::PredictorCalibration& fit) {
  json walks = json::array();
  for (const CalibrationWalk& w : cal.walks)
    walks.push_back({{"spacing", w.spacing},
                     {"keyframes", w.keyframes},
                     {"in_between", w.inBetween},
                     {"psnr_median", std::isfinite(w.psnrMedian) ? json(w.psnrMedian) : json(nullptr)},
                     {"walk_ms", w.walkMs}});
  return {{"walks", walks},
          {"samples", fit.samples},
          {"residual_std_db", fit.residualStdDb},
          {"spearman", std::isfinite(fit.spearman) ? json(fit.spearman) : json(nullptr)}};
}

}  // namespace hw::session
