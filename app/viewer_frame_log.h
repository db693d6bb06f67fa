#pragma once
// A viewer session's per-frame records: the `view --frame-stats` CSV
// (docs/viewer.md) and the summary lines printed at exit. Plain data, no GL.
#include <string>
#include <vector>

#include "session/frame_mode.h"

namespace hw::app {

// One displayed frame.
struct FrameRecord {
  long frame = 0;
  int playFrame = -1;     // frame of the played path shown; -1: not playing it
  double ms = 0;          // from the end of the previous frame to the end of this one
  double workMs = 0;      // from the start of this frame until it was shown (pacing wait excluded)
  double budgetMs = 0;    // this frame's budget (--frame-budget-ms; 0 = none)
  double keyframeMs = 0;  // keyframe render, read or worker hand-over in this frame
  // Keyframe events: rendered in the frame, read from a database, taken from
  // the worker, requested from it, wanted while it was not ready, and lost
  // while waiting for it.
  bool built = false, read = false, worker = false, requested = false, waited = false,
       stalled = false;
  int layers = 0;  // warped layers (0: a keyframe shown as is; -1: geometry)
  session::FrameKind kind = session::FrameKind::Warp;
  int holeRects = 0, holeRectsOverBudget = 0;  // the hole pass's rectangles
  double holesMs = 0;
};

// The --frame-stats file: a header line, then one row per record (ms to 3
// decimals, booleans as 0/1, mode as session::frameKindName).
std::string frameStatsCsv(const std::vector<FrameRecord>& records);

// "hybridwalk view: mode M: G frames drawn as geometry, W warped, K with a
// keyframe built, read or taken", and with mode Auto when it first chose
// geometry (firstGeometryChoice < 0: never). One line with its newline.
std::string modeSummary(const std::vector<FrameRecord>& records, session::FrameMode mode,
                        long firstGeometryChoice, long autoSwitches);

// Frame ms median / p95 / max over the frames after the first (which renders
// or waits for the first keyframe, a load), and with a frame budget
// (`budget` "fixed" or "auto"; nullptr: none) the budgets and the work.
// Empty when there is no frame after the first.
std::string frameTimeSummary(const std::vector<FrameRecord>& records, const char* budget);

}  // namespace hw::app
