#include "core/safe_io.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace hw {

std::string fileKindName(unsigned mode) {
  switch (mode & S_IFMT) {
    case S_IFREG: return "a regular file";
    case S_IFDIR: return "a directory";
    case S_IFIFO: return "a FIFO (named pipe)";
    case S_IFCHR: return "a character device";
    case S_IFBLK: return "a block device";
    case S_IFSOCK: return "a socket";
    case S_IFLNK: return "a symbolic link";
    default: return "a special file";
  }
}

std::string formatBytes(std::uint64_t bytes) {
  char buf[64];
  if (bytes < 1024)
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
  else if (bytes < (1ull << 20))
    std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(bytes) / 1024.0);
  else if (bytes < (1ull << 30))
    std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  else
    std::snprintf(buf, sizeof buf, "%.1f GiB", static_cast<double>(bytes) / (1 << 30));
  return buf;
}

Status checkOutputPath(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return {};  // new path (or unreachable: the write says why)
  if (S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) return {};
  return makeError("refusing to write " + what + " " + path + ": it exists and is " +
                   fileKindName(st.st_mode) +
                   " (expected a regular file, a directory or a new path; nothing was written)");
}

namespace {

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

Result<int> openRegular(const std::string& path, struct stat* st) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int e = errno;
    if (e == EISDIR) return makeError(path + ": is a directory, expected a file");
    return makeError("cannot open " + path + ": " + std::strerror(e));
  }
  if (::fstat(fd, st) != 0) {
    const int e = errno;
    ::close(fd);
    return makeError("cannot read " + path + ": " + std::strerror(e));
  }
  if (S_ISDIR(st->st_mode)) {
    ::close(fd);
    return makeError(path + ": is a directory, expected a file");
  }
  if (!S_ISREG(st->st_mode)) {
    ::close(fd);
    return makeError(path + ": is " + fileKindName(st->st_mode) +
                     ", expected a regular file (devices, FIFOs and sockets are not read)");
  }
  return fd;
}

}  // namespace

Result<std::uint64_t> regularFileSize(const std::string& path) {
  struct stat st {};
  auto fd = openRegular(path, &st);
  if (!fd) return fd.error();
  ::close(*fd);
  return static_cast<std::uint64_t>(st.st_size);
}

Result<std::string> readRegularFile(const std::string& path, std::uint64_t maxBytes) {
  struct stat st {};
  auto opened = openRegular(path, &st);
  if (!opened) return opened.error();
  Fd fd{*opened};
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > maxBytes)
    return makeError(path + ": " + formatBytes(size) + ", larger than the " +
                     formatBytes(maxBytes) + " this input may have (not read)");
  std::string bytes;
  try {
    bytes.resize(static_cast<std::size_t>(size));
  } catch (const std::bad_alloc&) {
    return makeError(path + ": out of memory reading " + formatBytes(size));
  }
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd.fd, bytes.data() + got, bytes.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      return makeError("cannot read " + path + ": " + std::strerror(errno));
    }
    if (n == 0) break;  // shrank while reading
    got += static_cast<std::size_t>(n);
  }
  bytes.resize(got);
  return bytes;
}

// ---- temporaries -----------------------------------------------------------

namespace {

constexpr int kMaxTemporaries = 64;
constexpr std::size_t kMaxTempPath = 1024;
// 0 free, 1 being written, 2 registered. The signal handler reads only slots
// in state 2, whose path is complete.
struct Slot {
  std::atomic<int> state{0};
  char path[kMaxTempPath];
};
Slot gSlots[kMaxTemporaries];

int registerTemporary(const std::string& path) {
  if (path.size() >= kMaxTempPath) return -1;
  for (int i = 0; i < kMaxTemporaries; ++i) {
    int expected = 0;
    if (gSlots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(gSlots[i].path, path.c_str(), path.size() + 1);
      gSlots[i].state.store(2);
      return i;
    }
  }
  return -1;  // table full: the file is still removed by its owner's destructor
}

void appendText(char* buf, std::size_t cap, std::size_t* len, const char* s) {
  while (*s && *len + 1 < cap) buf[(*len)++] = *s++;
}

void appendInt(char* buf, std::size_t cap, std::size_t* len, int v) {
  char digits[16];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v > 0 && n < 15);
  while (n > 0 && *len + 1 < cap) buf[(*len)++] = digits[--n];
}

void onTerminatingSignal(int sig) {
  const int removed = removeRegisteredTemporaries();
  char line[160];
  std::size_t len = 0;
  appendText(line, sizeof line, &len, "hybridwalk: interrupted by ");
  appendText(line, sizeof line, &len, sig == SIGINT ? "SIGINT" : "SIGTERM");
  appendText(line, sizeof line, &len, "; removed ");
  appendInt(line, sizeof line, &len, removed);
  appendText(line, sizeof line, &len, removed == 1 ? " temporary file\n" : " temporary files\n");
  ssize_t ignored = ::write(STDERR_FILENO, line, len);
  (void)ignored;
  ::_exit(128 + sig);
}

}  // namespace

TemporaryFile::TemporaryFile(std::string path) : path_(std::move(path)) {
  if (!path_.empty()) slot_ = registerTemporary(path_);
}

TemporaryFile::~TemporaryFile() {
  if (slot_ >= 0 || !path_.empty()) {
    if (slot_ >= 0) gSlots[slot_].state.store(0);
    if (!path_.empty()) ::unlink(path_.c_str());
  }
}

void TemporaryFile::release() {
  if (slot_ >= 0) gSlots[slot_].state.store(0);
  slot_ = -1;
  path_.clear();
}

int removeRegisteredTemporaries() {
  int removed = 0;
  for (Slot& s : gSlots)
    if (s.state.load() == 2 && ::unlink(s.path) == 0) ++removed;
  return removed;
}

void installSignalCleanup() {
  struct sigaction sa {};
  sa.sa_handler = onTerminatingSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void dieWithParentIfWorker() {
  const char* parent = std::getenv("HW_WORKER_PARENT_PID");
  if (!parent || !*parent) return;
  char* end = nullptr;
  const long pid = std::strtol(parent, &end, 10);
  if (*end != '\0' || pid <= 0) return;
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  // The parent may have died before prctl: then we were re-parented already.
  if (::getppid() != static_cast<pid_t>(pid)) ::_exit(1);
}

void markChildrenAsWorkers() {
  ::setenv("HW_WORKER_PARENT_PID", std::to_string(::getpid()).c_str(), 1);
}

std::FILE* openScratchFile(const std::string& dir, const std::string& name,
                           std::string* fallbackPath) {
  fallbackPath->clear();
#ifdef O_TMPFILE
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) {
    std::FILE* f = ::fdopen(fd, "w+b");
    if (f) return f;
    ::close(fd);
  }
#endif
  *fallbackPath = dir + "/" + name;
  return std::fopen(fallbackPath->c_str(), "w+b");
}

}  // namespace hw
