#include "core/output_dir.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <nlohmann/json.hpp>

#include "core/file_io.h"
#include "core/safe_io.h"

namespace hw {

namespace {

constexpr const char* kProgramVersion = "0.1";
constexpr std::size_t kMaxMarkerBytes = 64 * 1024;

std::string readFd(int fd) {
  std::string text(kMaxMarkerBytes, '\0');
  const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
  text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  return text;
}

OutputDirOwner parseOwner(const std::string& text) {
  OutputDirOwner o;
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("program", "") != "hybridwalk" ||
      !j.contains("command") || !j["command"].is_string())
    return o;
  o.command = j["command"].get<std::string>();
  if (j.contains("version") && j["version"].is_string()) o.version = j["version"];
  if (j.contains("started") && j["started"].is_string()) o.started = j["started"];
  if (j.contains("pid") && j["pid"].is_number_integer()) o.pid = j["pid"].get<long>();
  o.readable = !o.command.empty();
  return o;
}

// "PID 12, started 2026-01-02T03:04:05Z"
std::string describe(const OutputDirOwner& o) {
  std::string s = "PID " + std::to_string(o.pid);
  if (!o.started.empty()) s += ", started " + o.started;
  return s;
}

// True when `dir` holds no entry at all.
bool isEmptyDir(const std::string& dir) {
  DIR* d = ::opendir(dir.c_str());
  if (!d) return false;
  bool empty = true;
  while (const dirent* e = ::readdir(d)) {
    if (std::strcmp(e->d_name, ".") == 0 || std::strcmp(e->d_name, "..") == 0) continue;
    empty = false;
    break;
  }
  ::closedir(d);
  return empty;
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

int removeIn(const std::string& dir, const std::string& suffix, long pid, bool recurse) {
  DIR* d = ::opendir(dir.c_str());
  if (!d) return 0;
  int removed = 0;
  std::vector<std::string> subdirs;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name == "." || name == "..") continue;
    const std::string path = dir + "/" + name;
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) continue;
    if (S_ISDIR(st.st_mode)) {
      if (recurse) subdirs.push_back(path);
      continue;
    }
    if (!S_ISREG(st.st_mode) || st.st_uid != ::getuid() || !endsWith(name, suffix)) continue;
    if (::unlink(path.c_str()) == 0) {
      ++removed;
      std::fprintf(stderr,
                   "hybridwalk: note: removed %s, a temporary left by the interrupted run (PID "
                   "%ld) that wrote this folder before\n",
                   path.c_str(), pid);
    }
  }
  ::closedir(d);
  for (const auto& s : subdirs) removed += removeIn(s, suffix, pid, false);
  return removed;
}

std::vector<OutputDir*>& heldDirs() {
  static std::vector<OutputDir*> dirs;
  return dirs;
}

}  // namespace

std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

struct OutputDir::Provisional {
  explicit Provisional(std::string path) : file(std::move(path)) {}
  TemporaryFile file;  // removed unless released
};

OutputDirOwner readOutputDirOwner(const std::string& dir) {
  const std::string marker = dir + "/" + kOwnerMarkerName;
  const int fd = ::open(marker.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) return {};
  struct stat st {};
  OutputDirOwner o;
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) o = parseOwner(readFd(fd));
  ::close(fd);
  return o;
}

int removeTemporariesOfRun(const std::string& dir, long pid) {
  if (pid <= 0) return 0;
  return removeIn(dir, ".tmp-" + std::to_string(pid), pid, true);
}

Result<std::unique_ptr<OutputDir>> OutputDir::open(const std::string& dir,
                                                   const std::string& command, bool force) {
  if (dir.empty()) return makeError("output directory: expected a path, got an empty string");
  HW_TRY(checkOutputPath(dir, "output directory"));  // a device, FIFO or socket (even via a link)
  struct stat lst {};
  const bool existed = ::lstat(dir.c_str(), &lst) == 0;
  if (existed && S_ISLNK(lst.st_mode) && !force) {
    char target[4096];
    const ssize_t n = ::readlink(dir.c_str(), target, sizeof target - 1);
    const std::string to = n > 0 ? std::string(target, static_cast<std::size_t>(n)) : "?";
    return makeError("output folder " + dir + " is a symbolic link (to " + to +
                     "); refusing to write through it: give the folder itself, or --force to "
                     "write where it points (nothing was written)");
  }
  HW_TRY(ensureWritableDir(dir));
  const std::string marker = dir + "/" + kOwnerMarkerName;
  int fd = -1;
  bool created = false;
  for (int attempt = 0; attempt < 2 && fd < 0; ++attempt) {
    fd = ::open(marker.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd >= 0) break;
    if (errno == ELOOP)
      return makeError(marker +
                       " is a symbolic link: not a hybridwalk marker (remove it, or "
                       "choose another output folder)");
    if (errno != ENOENT) return makeError("cannot open " + marker + ": " + std::strerror(errno));
    if (!force && !isEmptyDir(dir))
      return makeError("output folder " + dir +
                       " is not empty and was not made by hybridwalk (no " + kOwnerMarkerName +
                       "): refusing to write into it, as that could replace files that are not "
                       "ours; choose a new or empty folder, or --force to write there anyway "
                       "(nothing was written)");
    fd = ::open(marker.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd >= 0)
      created = true;
    else if (errno != EEXIST)
      return makeError("cannot create " + marker + ": " + std::strerror(errno));
  }
  if (fd < 0) return makeError("cannot open " + marker + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return makeError(marker + ": not a regular file (expected hybridwalk's marker)");
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    const OutputDirOwner o = parseOwner(readFd(fd));
    ::close(fd);
    if (e == EWOULDBLOCK)
      return makeError(
          dir + " is in use by " +
          (o.readable ? "PID " + std::to_string(o.pid) + " (" + o.command +
                            (o.started.empty() ? "" : ", started " + o.started) + ")"
                      : std::string("another hybridwalk process")) +
          ": one run writes into a folder at a time; wait for it to finish or choose another "
          "output folder");
    return makeError("cannot lock " + marker + ": " + std::strerror(e) +
                     " (the file system does not support flock; choose an output folder on a "
                     "local or lock-capable file system)");
  }
  const std::string old = readFd(fd);
  OutputDirOwner previous = parseOwner(old);
  // An empty marker: a claim that was never completed (or a race with another
  // claim that lost the lock): nothing to honour.
  if (!created && !old.empty() && !previous.readable && !force) {
    ::close(fd);
    return makeError(marker + ": not a hybridwalk marker (unreadable); refusing to write into " +
                     dir + ": choose another output folder, or --force to take it over");
  }
  if (previous.readable && previous.command != command && !force) {
    ::close(fd);
    return makeError("output folder " + dir + " belongs to 'hybridwalk " + previous.command +
                     "' (" + describe(previous) + "); refusing to write " + command +
                     " outputs into it: choose another output folder, or --force to take it over");
  }
  const nlohmann::json j = {{"program", "hybridwalk"},
                            {"version", kProgramVersion},
                            {"command", command},
                            {"pid", static_cast<long>(::getpid())},
                            {"started", utcNow()}};
  const std::string text = j.dump(1) + "\n";
  if (::ftruncate(fd, 0) != 0 ||
      ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
    const int e = errno;
    ::close(fd);
    return makeError("cannot write " + marker + ": " + std::strerror(e));
  }
  std::unique_ptr<OutputDir> out(new OutputDir());
  out->dir_ = dir;
  out->fd_ = fd;
  out->previous_ = previous;
  out->previousMarker_ = old;
  out->createdDir_ = !existed;
  out->createdMarker_ = created;
  if (previous.readable && previous.pid != static_cast<long>(::getpid()))
    removeTemporariesOfRun(dir, previous.pid);
  heldDirs().push_back(out.get());
  return out;
}

OutputDir* OutputDir::held(const std::string& dir) {
  for (OutputDir* d : heldDirs())
    if (d->dir_ == dir) return d;
  return nullptr;
}

void OutputDir::leaveAsFound() { leaveAsFound_ = true; }

OutputDir::~OutputDir() {
  auto& dirs = heldDirs();
  dirs.erase(std::remove(dirs.begin(), dirs.end(), this), dirs.end());
  provisional_.clear();  // uncommitted summaries go
  if ((leaveAsFound_ || !committed_) && fd_ >= 0 && !previousMarker_.empty()) {
    if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, previousMarker_.data(), previousMarker_.size(),
                                             0) != static_cast<ssize_t>(previousMarker_.size()))
      std::fprintf(stderr, "hybridwalk: warning: cannot restore %s/%s\n", dir_.c_str(),
                   kOwnerMarkerName);
  }
  if (createdMarker_) {
    bool onlyMarker = true;
    if (DIR* d = ::opendir(dir_.c_str())) {
      while (const dirent* e = ::readdir(d))
        if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0 &&
            std::strcmp(e->d_name, kOwnerMarkerName) != 0)
          onlyMarker = false;
      ::closedir(d);
    }
    if (onlyMarker) {
      ::unlink((dir_ + "/" + kOwnerMarkerName).c_str());
      if (createdDir_) ::rmdir(dir_.c_str());
    }
  }
  if (fd_ >= 0) ::close(fd_);
}

void OutputDir::provisional(const std::string& name) {
  const std::string path = dir_ + "/" + name;
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)))
    ::unlink(path.c_str());
  provisional_.push_back(std::make_unique<Provisional>(path));
}

void OutputDir::commit() {
  committed_ = true;
  for (auto& p : provisional_) p->file.release();
  provisional_.clear();
}

}  // namespace hw
