#pragma once
// Guards at the file-system boundary: outputs never replace a device, FIFO or
// socket; inputs are read only from regular files whose size is checked
// before reading; temporaries are removed when the process is interrupted;
// worker processes die with their parent. docs/bad-input.md lists the limits.
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/result.h"

namespace hw {

// Largest file readFile() reads unless the caller passes its own limit. The
// biggest inputs we read whole are keyframe files (17 bytes per pixel: 1.1 GiB
// at 8192²); anything larger is not ours.
inline constexpr std::uint64_t kDefaultMaxReadBytes = 2ull << 30;

// "a FIFO (named pipe)", "a character device", ... for a stat mode.
std::string fileKindName(unsigned mode);

// Error when `path` exists and is not a regular file or a directory (device,
// FIFO, socket; symlinks are followed, so a link to /dev/null counts as the
// device). Nothing is written: outputs are written to a temporary name and
// renamed, and a rename would replace the device node itself.
Status checkOutputPath(const std::string& path, const std::string& what = "output");

// Reads a whole regular file of at most `maxBytes` bytes. Refuses directories,
// FIFOs, devices and sockets without blocking (opened O_NONBLOCK, checked with
// fstat), and files over the limit before reading a byte.
Result<std::string> readRegularFile(const std::string& path,
                                    std::uint64_t maxBytes = kDefaultMaxReadBytes);
// Size of a regular file (same refusals as readRegularFile).
Result<std::uint64_t> regularFileSize(const std::string& path);

// "12.5 MiB" style.
std::string formatBytes(std::uint64_t bytes);

// Temporary files removed by the SIGINT/SIGTERM handler (installSignalCleanup)
// and by removeRegisteredTemporaries(). RAII: registers on construction,
// unregisters (and removes the file, if it still exists) on destruction
// unless release() was called after the file was renamed into place.
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string path);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return path_; }
  // The file is gone (renamed into place): forget it without removing.
  void release();

 private:
  std::string path_;
  int slot_ = -1;
};

// Temporaries of a process killed by SIGKILL (or a power cut) stay behind as
// `NAME.tmp-PID` (writeFileAtomic), `.report-frames.tmp-PID` and
// `.series.tmp-PID` (where O_TMPFILE is missing); the next run that claims the
// folder removes those of the PID its marker recorded (core/output_dir.h).

// Removes every registered temporary file; returns how many were removed.
int removeRegisteredTemporaries();

// SIGINT and SIGTERM: remove the registered temporaries, print one line
// ("hybridwalk: interrupted by SIGTERM; removed 1 temporary file") and exit
// 128 + signal (130, 143). Handlers installed later (e.g. the chunk runner's)
// take precedence while they are installed.
void installSignalCleanup();

// A worker started by a parent hybridwalk (environment HW_WORKER_PARENT_PID,
// set by markChildrenAsWorkers) asks the kernel for SIGTERM when its parent
// dies (PR_SET_PDEATHSIG), and exits at once if the parent is already gone.
void dieWithParentIfWorker();
// Sets HW_WORKER_PARENT_PID for the children this process spawns from now on.
void markChildrenAsWorkers();

// A scratch file in `dir` that disappears when closed or when the process dies
// (O_TMPFILE), even by SIGKILL. Where the file system lacks O_TMPFILE, a named
// file `dir/name` is created instead and *fallbackPath is set to it (the
// caller removes it); otherwise *fallbackPath is cleared.
std::FILE* openScratchFile(const std::string& dir, const std::string& name,
                           std::string* fallbackPath);

}  // namespace hw
