#include "session/walk_recorder.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include "core/file_io.h"
#include "core/json_util.h"
#include "core/safe_io.h"
#include "core/timer.h"

namespace hw::session {

using nlohmann::json;

json seriesStats(const std::vector<double>& v) {
  return {{"median", finiteOrNull(median(v))},
          {"p5", finiteOrNull(percentile(v, 5))},
          {"p95", finiteOrNull(percentile(v, 95))},
          {"min", finiteOrNull(percentile(v, 0))},
          {"max", finiteOrNull(percentile(v, 100))},
          {"count", v.size()}};
}

json seriesStats(const SpilledSeries<double>& v) { return seriesStats(v.values()); }

void RecordedFrameTimes::attach(SpillFile* file) {
  frame.attach(file);
  builtKeyframe.attach(file);
  kind.attach(file);
  workMs.attach(file);
  intervalMs.attach(file);
  budgetMs.attach(file);
  referenceMs.attach(file);
}

void RecordedFrameTimes::push(int i, FrameKind k, bool built, double work, double interval,
                              double budget, double reference) {
  frame.push_back(i);
  kind.push_back(k);
  builtKeyframe.push_back(built ? 1 : 0);
  workMs.push_back(work);
  intervalMs.push_back(interval);
  budgetMs.push_back(budget);
  referenceMs.push_back(reference);
}

FrameTimes RecordedFrameTimes::take() const {
  FrameTimes t;
  t.frame = frame.values();
  t.builtKeyframe = builtKeyframe.values();
  t.kind = kind.values();
  t.workMs = workMs.values();
  t.intervalMs = intervalMs.values();
  t.budgetMs = budgetMs.values();
  t.referenceMs = referenceMs.values();
  return t;
}

WalkRecorder::WalkRecorder(bool keepFrames, std::string scratchPath, int /*frames*/)
    : keepFrames_(keepFrames),
      scratchPath_(std::move(scratchPath)),
      // Beside the streamed report frames when writing, else in $TMPDIR.
      spill_(std::make_unique<SpillFile>(
          scratchPath_.empty() ? std::string()
                               : std::filesystem::path(scratchPath_).parent_path().string())) {
  Series& s = series;
  for (Column* c :
       {&s.psnr, &s.ssim, &s.holesBefore, &s.holesAfter, &s.inBetweenMs, &s.referenceMs,
        &s.keyframeMs, &s.quadsPerKeyframe, &s.warpMs, &s.composeMs, &s.lodBuildMs,
        &s.onePixelLeaves, &s.drawnQuads, &s.subdividedQuads, &s.pointsPerKeyframe,
        &s.foregroundUncovered, &s.backgroundCulled, &s.psnrLargeQuads, &s.largeQuadPixels,
        &s.nearMs, &s.stalePixels, &s.maxAges, &s.refreshedPixels, &s.refreshMs,
        &s.frameIntervalMs, &s.inBetweenIntervalMs, &s.frameMs, &s.inBetweenFrameMs, &s.stallMs,
        &s.sliceMs, &s.speedup, &s.refreshPredictedOverMeasured, &s.reprojectedPixels,
        &s.blendedPixels, &s.fallbackMs, &s.psnrDrawn, &s.staleErrorShare,
        &s.holesRenderedPixels})
    c->attach(spill_.get());
  static_assert(sizeof(Series) == 38 * sizeof(Column), "attach every series above");
  frameTimes.attach(spill_.get());
}

WalkRecorder::~WalkRecorder() {
  if (scratch_) std::fclose(scratch_);
  if (!scratchPath_.empty()) std::remove(scratchPath_.c_str());
}

Status WalkRecorder::open() {
  if (scratchPath_.empty()) return {};
  // Unnamed (O_TMPFILE) where the file system allows: nothing is left even
  // after SIGKILL; a named one is removed on SIGINT/SIGTERM.
  const std::filesystem::path p(scratchPath_);
  std::string named;
  scratch_ = openScratchFile(p.parent_path().string(), p.filename().string(), &named);
  if (!named.empty()) registration_ = std::make_unique<TemporaryFile>(named);
  if (!scratch_) return makeError("cannot write " + scratchPath_ + ": " + std::strerror(errno));
  return {};
}

// Entries are kept as JSON for callers that read them, otherwise streamed to
// the scratch file, so a 10,000-frame walk's memory stays flat (about 3 KiB
// per frame as JSON objects).
Status WalkRecorder::addFrame(json entry) {
  if (keepFrames_) {
    frames_.push_back(std::move(entry));
    return {};
  }
  if (!scratch_) return {};
  const std::string text = (firstWritten_ ? ",\n" : "\n") + entry.dump();
  firstWritten_ = true;
  if (std::fwrite(text.data(), 1, text.size(), scratch_) != text.size())
    return makeError("cannot write " + scratchPath_ + ": " + std::strerror(errno));
  return {};
}

Status WalkRecorder::finish(json summary, const std::string& path, json* report) {
  if (spill_->readFailed())
    return makeError("cannot read back the walk's series scratch file (in " +
                     (scratchPath_.empty() ? std::string("$TMPDIR") : scratchPath_) +
                     "): the summary would be wrong");
  *report = {{"frames", std::move(frames_)}, {"summary", std::move(summary)}};
  frames_ = json::array();
  if (path.empty()) return {};
  if (keepFrames_ || !scratch_) return writeFileAtomic(path, report->dump(1));
  // Same document: the streamed frames, then the summary.
  std::string text = "{\n\"frames\": [";
  std::fflush(scratch_);
  const long size = std::ftell(scratch_);
  std::rewind(scratch_);
  const std::size_t start = text.size();
  text.resize(start + static_cast<std::size_t>(size > 0 ? size : 0));
  if (size > 0 && std::fread(text.data() + start, 1, static_cast<std::size_t>(size), scratch_) !=
                      static_cast<std::size_t>(size))
    return makeError("cannot read back " + scratchPath_);
  text += "\n],\n\"summary\": " + (*report)["summary"].dump(1) + "\n}\n";
  return writeFileAtomic(path, text);
}

}  // namespace hw::session
