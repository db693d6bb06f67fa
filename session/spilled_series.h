#pragma once
// Per-frame series whose memory stays flat however long the walk: the newest
// kBlock values are kept in memory, older ones are written in blocks to one
// unnamed scratch file shared by a recorder's series, and read back once, at
// the end, for the summary's exact order statistics and frame_times.png.
// A 100,000-frame walk kept ~40 growing series in memory: ~0.2 KiB per frame,
// the soak's RSS creep (docs/notes/memory.md).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/safe_io.h"

namespace hw::session {

// Append-only scratch file of raw blocks. Opened on the first append: short
// walks create nothing. Unnamed (O_TMPFILE) where the file system allows, so
// nothing is left even after SIGKILL; otherwise a named file registered for
// removal on SIGINT/SIGTERM and removed by the destructor.
class SpillFile {
 public:
  // `dir`: where the scratch file goes; "" = $TMPDIR, else /tmp.
  explicit SpillFile(std::string dir);
  ~SpillFile();
  SpillFile(const SpillFile&) = delete;
  SpillFile& operator=(const SpillFile&) = delete;

  // Offset of the written block, or -1 when the file cannot be opened or
  // written (the caller keeps its values in memory instead).
  std::int64_t append(const void* data, std::size_t bytes);
  // False when the bytes cannot be read back (`data` is then zero-filled).
  bool read(std::int64_t offset, void* data, std::size_t bytes) const;
  // Bytes written so far.
  std::int64_t size() const { return end_; }
  // A read back failed: the values read are wrong (WalkRecorder::finish reports it).
  bool readFailed() const { return readFailed_; }

 private:
  std::string dir_;
  std::FILE* file_ = nullptr;
  bool failed_ = false;
  mutable bool readFailed_ = false;
  std::int64_t end_ = 0;
  std::string named_;                            // fallback path, when not O_TMPFILE
  std::unique_ptr<TemporaryFile> registration_;  // removes the fallback on SIGINT/SIGTERM
};

// A growing series of T (trivially copyable) with bounded memory once a
// SpillFile is attached; without one (or after a failed write) it is a plain
// vector. push_back/size/empty as std::vector; values() materialises it.
template <typename T>
class SpilledSeries {
 public:
  static constexpr std::size_t kBlock = 4096;

  void attach(SpillFile* file) { file_ = file; }
  void push_back(T v) {
    if (file_ && !stopSpilling_ && tail_.size() >= kBlock) spill();
    tail_.push_back(v);
  }
  std::size_t size() const { return blocks_.size() * kBlock + tail_.size(); }
  bool empty() const { return size() == 0; }
  // Every value in order (reads the spilled blocks back).
  std::vector<T> values() const {
    std::vector<T> out(size());
    for (std::size_t b = 0; b < blocks_.size(); ++b)
      file_->read(blocks_[b], out.data() + b * kBlock, kBlock * sizeof(T));
    std::copy(tail_.begin(), tail_.end(),
              out.begin() + static_cast<std::ptrdiff_t>(blocks_.size() * kBlock));
    return out;
  }

 private:
  void spill() {
    const std::int64_t at = file_->append(tail_.data(), tail_.size() * sizeof(T));
    if (at < 0) {  // disk full or no scratch dir: grow in memory from here on
      stopSpilling_ = true;
      return;
    }
    blocks_.push_back(at);
    tail_.clear();  // keeps its capacity: kBlock values, the series' whole footprint
  }

  SpillFile* file_ = nullptr;
  bool stopSpilling_ = false;
  std::vector<std::int64_t> blocks_;  // offsets of full blocks of kBlock values
  std::vector<T> tail_;
};

}  // namespace hw::session
