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

WalkRecorder::WalkRecorder(bool keepFrames, std::string scratchPath, int frames)
    : keepFrames_(keepFrames), scratchPath_(std::move(scratchPath)) {
  frameTimes.reserve(static_cast<std::size_t>(frames > 0 ? frames : 0));
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
