// `apt-get download` + `dpkg-deb -x` into a cache folder, through posix_spawn
// (no shell, so no quoting), each tool's output captured for error messages.
#include "scenes/fetch.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>

#include "core/file_io.h"

extern char** environ;

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;

struct RunResult {
  int exitCode = -1;   // -1: could not start or killed by a signal
  std::string output;  // stderr (and stdout unless passed through)
  std::string startError;
};

// Runs argv[0] (searched in PATH) in `cwd`. stderr, and stdout unless
// `passStdout`, go to `logPath` and are returned; with `passStdout` the
// child's stdout goes to our stderr (progress lines).
RunResult run(const std::vector<std::string>& argv, const std::string& cwd,
              const std::string& logPath, bool passStdout) {
  RunResult r;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  // Actions run in order: with passStdout, stdout becomes our stderr before
  // stderr is redirected to the log; otherwise both go to the log.
  if (passStdout) posix_spawn_file_actions_adddup2(&fa, STDERR_FILENO, STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, logPath.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (!passStdout) posix_spawn_file_actions_adddup2(&fa, STDERR_FILENO, STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) {
    r.startError = std::string("cannot run ") + argv[0] + ": " + std::strerror(rc);
    return r;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) r.exitCode = WEXITSTATUS(status);
  if (auto log = readFile(logPath)) r.output = std::move(*log);
  std::error_code ec;
  fs::remove(logPath, ec);
  if (r.exitCode != 0 && WIFSIGNALED(status))
    r.startError =
        argv[0] + std::string(" was killed by signal ") + std::to_string(WTERMSIG(status));
  return r;
}

std::string trimmed(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

// The .deb of `package` in `dir`, or "" (file names are NAME_VERSION_ARCH.deb).
std::string findDeb(const fs::path& dir, const std::string& package) {
  std::error_code ec;
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(package + "_", 0) == 0 && n.size() > 4 && n.substr(n.size() - 4) == ".deb" &&
        e.is_regular_file(ec))
      found.push_back(e.path().string());
  }
  std::sort(found.begin(), found.end());
  return found.empty() ? "" : found.back();
}

void say(bool progress, const std::string& line) {
  if (!progress) return;
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace

const std::vector<std::string>& scenePackages() {
  static const std::vector<std::string> kPackages = {"openarena-081-maps", "openarena-081-textures",
                                                     "openarena-data"};
  return kPackages;
}

const std::vector<std::string>& outdoorScenePackages() {
  static const std::vector<std::string> kPackages = {"morse-simulator-data", "torcs-data"};
  return kPackages;
}

std::string defaultSceneCacheDir() {
  if (const char* c = std::getenv("HYBRIDWALK_CACHE"); c && *c) return c;
  if (const char* h = std::getenv("HOME"); h && *h)
    return (fs::path(h) / ".cache" / "hybridwalk" / "scenes").string();
  return "hybridwalk-scenes";
}

Status fetchScenePackages(const std::string& cacheDir, bool progress, bool outdoor) {
  std::error_code absEc;
  const fs::path base = fs::absolute(cacheDir, absEc);  // children run in other folders
  if (absEc) return makeError("cache folder '" + cacheDir + "': " + absEc.message());
  const fs::path debs = base / "debs", root = base / "root", stamps = root / ".unpacked";
  for (const fs::path& d : {debs, root, stamps}) HW_TRY(ensureWritableDir(d.string()));
  std::vector<std::string> packages = scenePackages();
  if (outdoor)
    packages.insert(packages.end(), outdoorScenePackages().begin(), outdoorScenePackages().end());
  for (std::size_t i = 0; i < packages.size(); ++i) {
    const std::string& pkg = packages[i];
    char counter[48];
    std::snprintf(counter, sizeof counter, "[%zu/%zu] ", i + 1, packages.size());
    const std::string step = counter + pkg;
    std::string deb = findDeb(debs, pkg);
    if (!deb.empty()) {
      say(progress, step + ": already downloaded (" + fs::path(deb).filename().string() + ")");
    } else {
      say(progress, step + ": apt-get download …");
      // Into a private folder first, so an interrupted download leaves no
      // .deb that a later run would take for complete.
      const fs::path tmp = debs / (".download-" + pkg);
      std::error_code ec;
      fs::remove_all(tmp, ec);
      HW_TRY(ensureWritableDir(tmp.string()));
      const auto t0 = std::chrono::steady_clock::now();
      RunResult r = run({"apt-get", "download", pkg}, tmp.string(),
                        (debs / (".apt-get-" + pkg + ".log")).string(), progress);
      const std::string got = findDeb(tmp, pkg);
      if (r.exitCode != 0 || got.empty()) {
        fs::remove_all(tmp, ec);
        std::string msg = !r.startError.empty() ? r.startError : trimmed(r.output);
        if (msg.empty()) msg = "exit code " + std::to_string(r.exitCode) + ", no .deb written";
        return makeError("cannot download Debian package '" + pkg + "' with `apt-get download " +
                         pkg + "`: " + msg +
                         "\n(the package lists may be out of date or lack this package: run "
                         "`apt-get update` as root, and check that Debian's main archive is in "
                         "the APT sources)");
      }
      deb = (debs / fs::path(got).filename()).string();
      fs::rename(got, deb, ec);
      if (ec) return makeError("cannot move " + got + " to " + deb + ": " + ec.message());
      fs::remove_all(tmp, ec);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      char line[160];
      std::snprintf(line, sizeof line, ": %.1f MB in %.1f s",
                    static_cast<double>(fs::file_size(deb, ec)) / 1e6, s);
      say(progress, step + line);
    }
    const fs::path stamp = stamps / fs::path(deb).filename();
    std::error_code ec;
    if (fs::exists(stamp, ec)) {
      say(progress, step + ": already unpacked");
      continue;
    }
    say(progress, step + ": dpkg-deb -x → " + root.string());
    RunResult r = run({"dpkg-deb", "-x", deb, root.string()}, base.string(),
                      (debs / (".dpkg-deb-" + pkg + ".log")).string(), false);
    if (r.exitCode != 0) {
      std::string msg = !r.startError.empty() ? r.startError : trimmed(r.output);
      return makeError("cannot unpack " + deb + " (package '" + pkg + "') with `dpkg-deb -x`: " +
                       (msg.empty() ? "exit code " + std::to_string(r.exitCode) : msg) +
                       "\n(delete the .deb to download it again)");
    }
    HW_TRY(writeFileAtomic(stamp.string(), pkg + "\n"));
  }
  const auto pk3s = findPk3s(root.string());
  say(progress,
      "scene packages ready in " + cacheDir + ": " + std::to_string(pk3s.size()) + " .pk3 files");
  if (pk3s.empty())
    return makeError("the packages were unpacked into " + root.string() +
                     " but contain no .pk3 files");
  return {};
}

std::vector<std::string> findPk3s(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  fs::recursive_directory_iterator it(dir,
                                      fs::directory_options::follow_directory_symlink |
                                          fs::directory_options::skip_permission_denied,
                                      ec);
  // Directory symlinks are followed (the unpacked packages use them), but a
  // directory already seen (a link pointing back up) is not entered again.
  std::set<std::pair<dev_t, ino_t>> seenDirs;
  std::set<std::pair<dev_t, ino_t>> seenFiles;
  struct stat rootSt {};
  if (::stat(dir.c_str(), &rootSt) == 0) seenDirs.insert({rootSt.st_dev, rootSt.st_ino});
  constexpr int kMaxPk3Depth = 16;
  for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    struct stat st {};
    if (::stat(it->path().c_str(), &st) != 0) continue;
    if (S_ISDIR(st.st_mode)) {
      if (!seenDirs.insert({st.st_dev, st.st_ino}).second || it.depth() >= kMaxPk3Depth)
        it.disable_recursion_pending();
      continue;
    }
    if (!S_ISREG(st.st_mode) || !seenFiles.insert({st.st_dev, st.st_ino}).second) continue;
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".pk3" && it->is_regular_file(ec)) out.push_back(it->path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> defaultPk3Paths(const std::string& cacheDir) {
  std::vector<std::string> out = findPk3s((fs::path(cacheDir) / "root").string());
  if (const char* extra = std::getenv("HYBRIDWALK_PK3_DIR"); extra && *extra) {
    std::string s(extra);
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t end = std::min(s.find(':', start), s.size());
      if (end > start) {
        auto more = findPk3s(s.substr(start, end - start));
        out.insert(out.end(), more.begin(), more.end());
      }
      start = end + 1;
    }
  }
  return out;
}

namespace {
// "" for a folder or a path that does not exist; else what it is.
std::string notAFolder(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return "";
    return S_ISREG(st.st_mode) ? "a file, not a folder" : "not a folder";
  }
  if (errno == ELOOP) return "a symlink loop";
  if (errno == ENOENT) return "";
  return std::string("not readable: ") + std::strerror(errno);
}
}  // namespace

std::string pk3SearchProblems() {
  std::string out;
  auto add = [&](const std::string& var, const std::string& path) {
    const std::string why = notAFolder(path);
    if (!why.empty()) out += (out.empty() ? "" : "; ") + var + " names " + path + ", which is " + why;
  };
  if (const char* c = std::getenv("HYBRIDWALK_CACHE"); c && *c) add("$HYBRIDWALK_CACHE", c);
  if (const char* extra = std::getenv("HYBRIDWALK_PK3_DIR"); extra && *extra) {
    const std::string s(extra);
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t end = std::min(s.find(':', start), s.size());
      if (end > start) add("$HYBRIDWALK_PK3_DIR", s.substr(start, end - start));
      start = end + 1;
    }
  }
  return out;
}

}  // namespace hw::scenes
