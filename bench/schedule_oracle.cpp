#include "bench/schedule_oracle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "bench/plot.h"
#include "core/check.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/timer.h"

namespace hw::bench {

using nlohmann::json;

SegmentTable::SegmentTable(int frames, int maxGap) : frames_(frames), maxGap_(maxGap) {
  HW_CHECK_GE(frames, 1);
  HW_CHECK_GE(maxGap, 1);
  psnr_.assign(static_cast<std::size_t>(frames) * static_cast<std::size_t>(maxGap) *
                   static_cast<std::size_t>(maxGap),
               std::nan(""));
}

std::size_t SegmentTable::index(int k0, int k1, int f) const {
  HW_CHECK(k0 >= 0 && k0 < k1 && k1 < frames_ && k1 - k0 <= maxGap_ && k0 < f && f < k1);
  const auto g = static_cast<std::size_t>(maxGap_);
  return (static_cast<std::size_t>(k0) * g + static_cast<std::size_t>(k1 - k0 - 1)) * g +
         static_cast<std::size_t>(f - k0 - 1);
}

void SegmentTable::set(int k0, int k1, int f, double psnrDb) { psnr_[index(k0, k1, f)] = psnrDb; }

double SegmentTable::at(int k0, int k1, int f) const { return psnr_[index(k0, k1, f)]; }

bool SegmentTable::complete() const {
  for (int k0 = 0; k0 < frames_; ++k0)
    for (int k1 = k0 + 2; k1 < frames_ && k1 - k0 <= maxGap_; ++k1)
      for (int f = k0 + 1; f < k1; ++f)
        if (std::isnan(at(k0, k1, f))) return false;
  return true;
}

Result<SchedulePsnr> schedulePsnr(const SegmentTable& table, const std::vector<int>& keyframes) {
  const int n = table.frames();
  if (keyframes.empty() || keyframes.front() != 0 || keyframes.back() != n - 1)
    return makeError("schedule: expected keyframes from 0 to " + std::to_string(n - 1));
  std::vector<double> v;
  for (std::size_t i = 1; i < keyframes.size(); ++i) {
    const int k0 = keyframes[i - 1], k1 = keyframes[i];
    if (k1 <= k0 || k1 - k0 > table.maxGap())
      return makeError("schedule: keyframes " + std::to_string(k0) + ", " + std::to_string(k1) +
                       ": expected increasing, at most " + std::to_string(table.maxGap()) +
                       " apart");
    for (int f = k0 + 1; f < k1; ++f) {
      const double p = table.at(k0, k1, f);
      if (std::isnan(p))
        return makeError("schedule: no PSNR for frame " + std::to_string(f) + " between " +
                         std::to_string(k0) + " and " + std::to_string(k1));
      v.push_back(p);
    }
  }
  SchedulePsnr s;
  s.inBetween = static_cast<int>(v.size());
  s.median = median(v);
  s.p5 = percentile(v, 5);
  std::sort(v.begin(), v.end());
  s.lowerMedian = v.empty() ? std::nan("") : v[(v.size() + 1) / 2 - 1];
  return s;
}

OracleSchedule fewestKeyframesForMedian(const SegmentTable& table, double targetDb) {
  const int n = table.frames(), gmax = table.maxGap();
  OracleSchedule best;
  if (n < 3) return best;
  // good[k0][g-1]: frames of segment (k0, k0+g) at or above the target.
  std::vector<int> good(static_cast<std::size_t>(n) * static_cast<std::size_t>(gmax), 0);
  auto goodAt = [&](int k0, int g) -> int& {
    return good[static_cast<std::size_t>(k0) * static_cast<std::size_t>(gmax) +
                static_cast<std::size_t>(g - 1)];
  };
  for (int k0 = 0; k0 < n; ++k0)
    for (int g = 2; g <= gmax && k0 + g < n; ++g)
      for (int f = k0 + 1; f < k0 + g; ++f) goodAt(k0, g) += table.at(k0, k0 + g, f) >= targetDb;
  // dp[c][k]: most good in-between frames in [0, k] with c keyframes, the
  // last at k; -1 = impossible.
  const auto un = static_cast<std::size_t>(n);
  std::vector<int> parent(un * un, -1);
  std::vector<int> prev(un, -1), cur(un, -1);
  prev[0] = 0;  // one keyframe: frame 0
  for (int c = 2; c <= n; ++c) {
    std::fill(cur.begin(), cur.end(), -1);
    for (int k1 = 1; k1 < n; ++k1) {
      int bestV = -1, bestK = -1;
      for (int g = 1; g <= gmax && g <= k1; ++g) {
        const int k0 = k1 - g;
        if (prev[static_cast<std::size_t>(k0)] < 0) continue;
        const int v = prev[static_cast<std::size_t>(k0)] + (g >= 2 ? goodAt(k0, g) : 0);
        if (v > bestV) bestV = v, bestK = k0;
      }
      cur[static_cast<std::size_t>(k1)] = bestV;
      parent[static_cast<std::size_t>(c - 1) * un + static_cast<std::size_t>(k1)] = bestK;
    }
    const int inBetween = n - c;
    const int g = cur[un - 1];
    if (inBetween >= 1 && g >= inBetween / 2 + 1) {
      best.good = g;
      best.keyframes.assign(static_cast<std::size_t>(c), 0);
      int k = n - 1;
      for (int i = c; i >= 1; --i) {
        best.keyframes[static_cast<std::size_t>(i - 1)] = k;
        if (i > 1) k = parent[static_cast<std::size_t>(i - 1) * un + static_cast<std::size_t>(k)];
      }
      HW_CHECK_EQ(best.keyframes.front(), 0);
      return best;
    }
    std::swap(prev, cur);
  }
  return best;
}

namespace {

std::vector<int> fixedSchedule(int frames, int every) {
  std::vector<int> k;
  for (int i = 0; i < frames; i += every) k.push_back(i);
  if (k.back() != frames - 1) k.push_back(frames - 1);
  return k;
}

json finiteOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string fmt(double v, int digits = 3) {
  if (!std::isfinite(v)) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

}  // namespace

Result<json> runScheduleOracle(const scenes::Scene& scene, const std::string& sceneLabel,
                               const scenes::CameraPath& path, const ScheduleOracleOptions& opt) {
  if (opt.maxGap < 2) return makeError("schedule oracle: --max-gap must be >= 2, got " + std::to_string(opt.maxGap));
  for (int s : opt.fixedSpacings)
    if (s < 1 || s > opt.maxGap)
      return makeError("schedule oracle: fixed spacing " + std::to_string(s) +
                       " outside 1.." + std::to_string(opt.maxGap) + " (--max-gap)");
  if (std::find(opt.fixedSpacings.begin(), opt.fixedSpacings.end(), opt.referenceSpacing) ==
      opt.fixedSpacings.end())
    return makeError("schedule oracle: reference spacing " + std::to_string(opt.referenceSpacing) +
                     " is not one of the fixed spacings");
  HW_TRY(ensureWritableDir(opt.outDir));
  Stopwatch all;
  const int frames =
      opt.walk.maxFrames > 0 ? std::min(opt.walk.maxFrames, path.frames) : path.frames;
  if (frames < 3) return makeError("schedule oracle: the path has " + std::to_string(frames) + " frames, expected >= 3");
  SegmentTable table(frames, opt.maxGap);
  const int walks = opt.maxGap * (opt.maxGap + 1) / 2 - 1;
  int walkNo = 0;
  double referenceWalkMedian = std::nan("");
  for (int g = 2; g <= opt.maxGap; ++g)
    for (int o = 0; o < g; ++o) {
      ++walkNo;
      if (opt.progress)
        std::fprintf(stderr, "\rschedule-oracle %s: walk %d/%d (gap %d, offset %d), %.0f s   ",
                     sceneLabel.c_str(), walkNo, walks, g, o, all.ms() / 1000.0);
      std::vector<int> keys{0};
      for (int k = o; k < frames; k += g)
        if (k > 0) keys.push_back(k);
      if (keys.back() != frames - 1) keys.push_back(frames - 1);
      WalkOptions w = opt.walk;
      w.outDir.clear();
      w.keepFrames = true;
      w.progress = false;
      w.strips = 0;
      w.reference = true;
      w.maxFrames = frames;
      w.keyframeFrames = keys;
      auto res = runWalk(scene, sceneLabel, path, w);
      if (!res) return res.error();
      for (const json& f : res->report["frames"]) {
        if (f["is_keyframe"].get<bool>()) continue;
        const int k0 = f["keyframes"][0].get<int>(), k1 = f["keyframes"][1].get<int>();
        const double p = f["psnr"].is_number() ? f["psnr"].get<double>() : 99.0;  // as the walk
        if (k1 - k0 <= opt.maxGap) table.set(k0, k1, f["index"].get<int>(), p);
      }
      if (g == opt.referenceSpacing && o == 0 && res->report["summary"]["psnr"]["median"].is_number())
        referenceWalkMedian = res->report["summary"]["psnr"]["median"].get<double>();
    }
  if (opt.progress) std::fprintf(stderr, "\n");
  if (!table.complete()) return makeError("schedule oracle: the walks left segments unmeasured");
  const double tableMs = all.ms();

  json fixedRows = json::array();
  double refMedian = std::nan(""), refKf = std::nan("");
  std::vector<double> fx, fmed, ox, omed;
  for (int s : opt.fixedSpacings) {
    const std::vector<int> keys = fixedSchedule(frames, s);
    auto fp = schedulePsnr(table, keys);
    if (!fp) return fp.error();
    // More than half of the fixed schedule's frames reach its lower median;
    // the oracle must do as well (its interpolated median then also >= it).
    const OracleSchedule o = fewestKeyframesForMedian(table, fp->lowerMedian);
    json row = {{"spacing", s},
                {"fixed_keyframes", keys.size()},
                {"fixed_keyframes_per_100", 100.0 * static_cast<double>(keys.size()) / frames},
                {"fixed_psnr_median", fp->median},
                {"fixed_psnr_lower_median", fp->lowerMedian},
                {"fixed_psnr_p5", fp->p5}};
    if (!o.keyframes.empty()) {
      auto op = schedulePsnr(table, o.keyframes);
      if (!op) return op.error();
      row["oracle_keyframes"] = o.keyframes.size();
      row["oracle_keyframes_per_100"] = 100.0 * static_cast<double>(o.keyframes.size()) / frames;
      row["oracle_psnr_median"] = op->median;
      row["oracle_psnr_p5"] = op->p5;
      row["keyframe_reduction"] =
          1.0 - static_cast<double>(o.keyframes.size()) / static_cast<double>(keys.size());
      row["oracle_schedule"] = o.keyframes;
    } else {
      row["oracle_keyframes"] = nullptr;
      row["keyframe_reduction"] = nullptr;
    }
    if (s == opt.referenceSpacing) {
      refMedian = fp->median;
      refKf = row["fixed_keyframes_per_100"].get<double>();
    }
    fixedRows.push_back(row);
  }
  // The oracle's curve: fewest keyframes for targets across the fixed range.
  json oracleRows = json::array();
  {
    double lo = 1e9, hi = -1e9;
    for (const json& r : fixedRows) {
      lo = std::min(lo, r["fixed_psnr_median"].get<double>());
      hi = std::max(hi, r["fixed_psnr_median"].get<double>());
    }
    int lastK = -1;
    for (double t = std::floor((lo - 2.0) * 4) / 4; t <= hi + 2.0; t += 0.25) {
      const OracleSchedule o = fewestKeyframesForMedian(table, t);
      if (o.keyframes.empty()) break;
      const int k = static_cast<int>(o.keyframes.size());
      if (k == lastK) continue;
      lastK = k;
      auto op = schedulePsnr(table, o.keyframes);
      if (!op) return op.error();
      oracleRows.push_back({{"target", t},
                            {"keyframes", k},
                            {"keyframes_per_100", 100.0 * k / frames},
                            {"psnr_median", op->median},
                            {"psnr_p5", op->p5}});
      ox.push_back(100.0 * k / frames);
      omed.push_back(op->median);
    }
  }
  for (const json& r : fixedRows) {
    fx.push_back(r["fixed_keyframes_per_100"].get<double>());
    fmed.push_back(r["fixed_psnr_median"].get<double>());
  }
  json headline = {{"reference_spacing", opt.referenceSpacing},
                   {"reference_keyframes_per_100", refKf},
                   {"reference_psnr_median", refMedian},
                   {"reference_walk_psnr_median", finiteOrNull(referenceWalkMedian)},
                   {"goal_reduction", 0.30}};
  for (const json& r : fixedRows)
    if (r["spacing"].get<int>() == opt.referenceSpacing) {
      headline["oracle_keyframes_per_100"] = r.value("oracle_keyframes_per_100", json(nullptr));
      headline["best_possible_reduction"] = r["keyframe_reduction"];
      headline["goal_reachable"] =
          r["keyframe_reduction"].is_number() && r["keyframe_reduction"].get<double>() >= 0.30;
    }
  json doc = {{"scene", sceneLabel},
              {"frames", frames},
              {"max_gap", opt.maxGap},
              {"walks", walks},
              {"table_ms", tableMs},
              {"width", path.width},
              {"height", path.height},
              {"tau", opt.walk.lod.tau},
              {"machine", machineInfo(opt.walk.glRenderer, opt.walk.glVersion)},
              {"headline", headline},
              {"fixed", fixedRows},
              {"oracle", oracleRows}};
  std::string csv =
      "spacing,fixed_keyframes,fixed_keyframes_per_100,fixed_psnr_median,fixed_psnr_p5,"
      "oracle_keyframes,oracle_keyframes_per_100,oracle_psnr_median,oracle_psnr_p5,keyframe_reduction\n";
  auto num = [](const json& j, const char* k) {
    return j.contains(k) && j[k].is_number() ? j[k].get<double>() : std::nan("");
  };
  for (const json& r : fixedRows)
    csv += std::to_string(r["spacing"].get<int>()) + "," + fmt(num(r, "fixed_keyframes"), 0) + "," +
           fmt(num(r, "fixed_keyframes_per_100"), 2) + "," + fmt(num(r, "fixed_psnr_median")) + "," +
           fmt(num(r, "fixed_psnr_p5")) + "," + fmt(num(r, "oracle_keyframes"), 0) + "," +
           fmt(num(r, "oracle_keyframes_per_100"), 2) + "," + fmt(num(r, "oracle_psnr_median")) +
           "," + fmt(num(r, "oracle_psnr_p5")) + "," + fmt(num(r, "keyframe_reduction")) + "\n";
  {
    Series fs, os;
    fs.label = "fixed schedule (every N frames)";
    fs.x = fx, fs.y = fmed;
    os.label = "best possible schedule (oracle)";
    os.x = ox, os.y = omed;
    const auto& pal = plotPalette();
    fs.colour = pal[0];
    os.colour = pal[2];
    PlotOptions po;
    po.title = "Median in-between PSNR vs keyframes: " + sceneLabel + " (" + std::to_string(frames) +
               " frames, " + std::to_string(path.width) + "x" + std::to_string(path.height) + ")";
    po.xLabel = "keyframes per 100 frames";
    po.yLabel = "median in-between PSNR (dB)";
    po.width = 900;
    po.height = 560;
    HW_TRY(writePlot(opt.outDir + "/oracle.png", {fs, os}, po));
  }
  HW_TRY(writeFileAtomic(opt.outDir + "/oracle.csv", csv));
  {
    // The whole table, so any other schedule can be scored without walking.
    std::string seg = "k0,k1,frame,psnr\n";
    for (int k0 = 0; k0 < frames; ++k0)
      for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= opt.maxGap; ++k1)
        for (int f = k0 + 1; f < k1; ++f)
          seg += std::to_string(k0) + "," + std::to_string(k1) + "," + std::to_string(f) + "," +
                 fmt(table.at(k0, k1, f), 4) + "\n";
    HW_TRY(writeFileAtomic(opt.outDir + "/segments.csv", seg));
  }
  HW_TRY(writeFileAtomic(opt.outDir + "/oracle.json", doc.dump(1)));
  return doc;
}

}  // namespace hw::bench
