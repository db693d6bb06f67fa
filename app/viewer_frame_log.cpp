// The viewer's frame records as CSV and summary lines (app/viewer_frame_log.h).
#include "app/viewer_frame_log.h"

#include <algorithm>
#include <array>
#include <cstdio>

#include "core/timer.h"

namespace hw::app {

std::string frameStatsCsv(const std::vector<FrameRecord>& records) {
  std::string csv =
      "frame,play_frame,ms,keyframe_ms,keyframe_rendered,keyframe_read,worker_keyframe,"
      "worker_requested,worker_waited,worker_stall,layers,work_ms,budget_ms,mode,hole_rects,"
      "hole_rects_over_budget,holes_ms\n";
  char line[260];
  for (const FrameRecord& r : records) {
    std::snprintf(
        line, sizeof line, "%ld,%d,%.3f,%.3f,%d,%d,%d,%d,%d,%d,%d,%.3f,%.3f,%s,%d,%d,%.3f\n",
        r.frame, r.playFrame, r.ms, r.keyframeMs, r.built ? 1 : 0, r.read ? 1 : 0, r.worker ? 1 : 0,
        r.requested ? 1 : 0, r.waited ? 1 : 0, r.stalled ? 1 : 0, r.layers, r.workMs, r.budgetMs,
        session::frameKindName(r.kind), r.holeRects, r.holeRectsOverBudget, r.holesMs);
    csv += line;
  }
  return csv;
}

std::string modeSummary(const std::vector<FrameRecord>& records, session::FrameMode mode,
                        long firstGeometryChoice, long autoSwitches) {
  std::array<long, 3> count{};
  for (const FrameRecord& r : records) ++count[static_cast<std::size_t>(r.kind)];
  using K = session::FrameKind;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "hybridwalk view: mode %s: %ld frames drawn as geometry, %ld warped, %ld with a "
                "keyframe built, read or taken",
                session::frameModeName(mode), count[static_cast<std::size_t>(K::Geometry)],
                count[static_cast<std::size_t>(K::Warp)],
                count[static_cast<std::size_t>(K::Keyframe)]);
  std::string out = buf;
  if (mode == session::FrameMode::Auto) {
    if (firstGeometryChoice >= 0) {
      std::snprintf(buf, sizeof buf, "; auto chose geometry from frame %ld (%ld switches)",
                    firstGeometryChoice, autoSwitches);
      out += buf;
    } else {
      out += "; auto never chose geometry";
    }
  }
  return out + "\n";
}

std::string frameTimeSummary(const std::vector<FrameRecord>& records, const char* budget) {
  std::vector<double> ms;
  for (std::size_t i = 1; i < records.size(); ++i) ms.push_back(records[i].ms);
  if (ms.empty()) return {};
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "hybridwalk view: frame ms over frames 1..%zu: median %.2f, p95 %.2f, max %.2f\n",
                records.size() - 1, median(ms), percentile(ms, 95.0),
                *std::max_element(ms.begin(), ms.end()));
  std::string out = buf;
  if (budget) {
    std::vector<double> work, budgets;
    for (std::size_t i = 1; i < records.size(); ++i) {
      work.push_back(records[i].workMs);
      if (records[i].budgetMs > 0) budgets.push_back(records[i].budgetMs);
    }
    std::snprintf(buf, sizeof buf,
                  "hybridwalk view: frame budget %s: median %.2f ms (%zu frames had one); work "
                  "median %.2f, p95 %.2f; frame ms p95/median %.2f\n",
                  budget, budgets.empty() ? 0.0 : median(budgets), budgets.size(), median(work),
                  percentile(work, 95.0), percentile(ms, 95.0) / median(ms));
    out += buf;
  }
  return out;
}

}  // namespace hw::app
