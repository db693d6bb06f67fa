#pragma once
// The walk's recorder: per-frame entries of the walk report (kept, or
// streamed through a scratch file so that long walks keep flat memory), the
// statistics behind its summary, the strips, and the files it writes
// (docs/walk-report.md). The frame loop (session/walk.cpp) decides; this
// only keeps and writes.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/result.h"
#include "core/safe_io.h"
#include "session/spilled_series.h"
#include "session/walk.h"

namespace hw::session {

// Order statistics of a series as the report writes them: median, p5, p95,
// min, max (null when empty or not finite) and count.
nlohmann::json seriesStats(const std::vector<double>& v);
nlohmann::json seriesStats(const SpilledSeries<double>& v);

// FrameTimes as the walk records them: spilled like the series, turned into a
// FrameTimes for frame_times.png once the walk is done.
struct RecordedFrameTimes {
  SpilledSeries<int> frame;
  SpilledSeries<char> builtKeyframe;
  SpilledSeries<FrameKind> kind;
  SpilledSeries<double> workMs, intervalMs, budgetMs, referenceMs;
  void attach(SpillFile* file);
  void push(int i, FrameKind k, bool built, double work, double interval, double budget,
            double reference);
  FrameTimes take() const;
};

class WalkRecorder {
 public:
  // `scratchPath` empty: entries are only kept in memory (or dropped).
  WalkRecorder(bool keepFrames, std::string scratchPath, int frames);
  ~WalkRecorder();
  WalkRecorder(const WalkRecorder&) = delete;
  WalkRecorder& operator=(const WalkRecorder&) = delete;

  Status open();                        // the scratch file, when streaming
  Status addFrame(nlohmann::json entry);  // one frame's report entry
  // The report document: {"frames": [...], "summary": summary}; written
  // atomically to `path` when it is not empty. The kept entries move into
  // `report` (empty when streamed).
  Status finish(nlohmann::json summary, const std::string& path, nlohmann::json* report);

  // Series for the summary (one value per frame, keyframe or pair, as named);
  // beyond a few thousand values each, spilled to a scratch file (flat memory).
  using Column = SpilledSeries<double>;
  struct Series {
    Column psnr, ssim, holesBefore, holesAfter, inBetweenMs, referenceMs, keyframeMs,
        quadsPerKeyframe, warpMs, composeMs, lodBuildMs, onePixelLeaves, drawnQuads,
        subdividedQuads, pointsPerKeyframe, foregroundUncovered, backgroundCulled,
        psnrLargeQuads, largeQuadPixels, nearMs, stalePixels, maxAges, refreshedPixels,
        refreshMs, frameIntervalMs, inBetweenIntervalMs, frameMs, inBetweenFrameMs, stallMs,
        sliceMs, speedup, refreshPredictedOverMeasured, reprojectedPixels, blendedPixels,
        fallbackMs, psnrDrawn, staleErrorShare, holesRenderedPixels;
  } series;
  struct Counts {
    int backgroundSkips = 0, previousSkips = 0, framesRefreshed = 0, budgetOverruns = 0,
        budgetOverrunsInBetween = 0, budgetOverrunsByRefresh = 0;
    long long refreshRects = 0, glErrors = 0;
  } counts;
  nlohmann::json residentKiB = nlohmann::json::array();  // [frame, KiB] every 500 frames
  RecordedFrameTimes frameTimes;                         // for frame_times.png
  std::vector<Image<Rgba8>> strips;
  std::vector<nlohmann::json> stripInfo;

 private:
  bool keepFrames_;
  std::string scratchPath_;
  std::FILE* scratch_ = nullptr;
  std::unique_ptr<TemporaryFile> registration_;  // removes a named scratch on SIGINT/SIGTERM
  bool firstWritten_ = false;
  nlohmann::json frames_ = nlohmann::json::array();
  std::unique_ptr<SpillFile> spill_;  // the series' older values
};

}  // namespace hw::session
