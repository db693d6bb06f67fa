#include "session/spilled_series.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace hw::session {

SpillFile::SpillFile(std::string dir) : dir_(std::move(dir)) {
  if (dir_.empty()) {
    const char* t = std::getenv("TMPDIR");
    dir_ = t && *t ? t : "/tmp";
  }
}

SpillFile::~SpillFile() {
  if (file_) std::fclose(file_);
  registration_.reset();  // removes the named fallback, if any
}

std::int64_t SpillFile::append(const void* data, std::size_t bytes) {
  if (failed_) return -1;
  if (!file_) {
    file_ = openScratchFile(dir_, ".series.tmp-" + std::to_string(::getpid()), &named_);
    if (!named_.empty()) registration_ = std::make_unique<TemporaryFile>(named_);
    if (!file_) {
      failed_ = true;
      return -1;
    }
  }
  const int fd = ::fileno(file_);
  const auto* p = static_cast<const char*>(data);
  std::size_t done = 0;
  while (done < bytes) {
    const ssize_t n = ::pwrite(fd, p + done, bytes - done, static_cast<off_t>(end_ + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      failed_ = true;
      return -1;
    }
    done += static_cast<std::size_t>(n);
  }
  const std::int64_t at = end_;
  end_ += static_cast<std::int64_t>(bytes);
  return at;
}

bool SpillFile::read(std::int64_t offset, void* data, std::size_t bytes) const {
  auto* p = static_cast<char*>(data);
  std::size_t done = 0;
  const int fd = file_ ? ::fileno(file_) : -1;
  while (fd >= 0 && done < bytes) {
    const ssize_t n = ::pread(fd, p + done, bytes - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  if (done == bytes) return true;
  std::memset(p + done, 0, bytes - done);
  readFailed_ = true;
  return false;
}

}  // namespace hw::session
