#include "core/chunked_runs.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "core/file_io.h"
#include "core/json_guard.h"
#include "core/safe_io.h"
#include "core/timer.h"

extern char** environ;

namespace hw {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

volatile sig_atomic_t gInterrupted = 0;
void onSignal(int sig) { gInterrupted = sig; }

// Installs SIGINT/SIGTERM handlers for the lifetime of the object.
class SignalGuard {
 public:
  SignalGuard() {
    gInterrupted = 0;
    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &oldInt_);
    sigaction(SIGTERM, &sa, &oldTerm_);
  }
  ~SignalGuard() {
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
  }

 private:
  struct sigaction oldInt_ {
  }, oldTerm_{};
};

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  }
  return out + "'";
}

struct Captured {
  int status = -1;  // exit status, or -1 when the program could not run
  std::string out;
};

// Runs argv (PATH lookup) and captures stdout+stderr.
Captured capture(const std::vector<std::string>& argv) {
  std::string cmd;
  for (const auto& a : argv) {
    if (!cmd.empty()) cmd += ' ';
    cmd += shellQuote(a);
  }
  cmd += " 2>&1";
  Captured c;
  std::FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return c;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) c.out.append(buf, n);
  const int st = ::pclose(p);
  c.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  if (c.status == 127) c.status = -1;  // shell: command not found
  return c;
}

std::string lastLine(const std::string& text) {
  std::string t = text;
  while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
  const auto nl = t.find_last_of("\n\r");
  return nl == std::string::npos ? t : t.substr(nl + 1);
}

std::string logFile(const std::string& workDir, int chunk) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "/logs/chunk-%04d.log", chunk);
  return workDir + buf;
}

std::string tailOfLog(const std::string& file) {
  auto t = readFile(file);
  if (!t) return "";
  return lastLine(*t);
}

bool haveResult(const std::string& workDir, int chunk) {
  std::error_code ec;
  return fs::is_regular_file(chunkResultFile(workDir, chunk), ec);
}

std::string indexList(const std::vector<int>& idx) {
  std::string s;
  for (int i : idx) {
    if (!s.empty()) s += ',';
    s += std::to_string(i);
  }
  return s;
}

Status prepareWorkDir(const ChunkPlan& plan, bool resume) {
  const json planJson = {{"label", plan.label}, {"chunks", plan.chunks}, {"command", plan.command}};
  const std::string planFile = plan.workDir + "/plan.json";
  std::error_code ec;
  if (resume) {
    if (!fs::exists(planFile, ec))
      return makeError("--resume: " + planFile + " not found: there is no interrupted " +
                       plan.label + " run in this output directory (run without --resume)");
    auto text = readFile(planFile);
    if (!text) return text.error();
    json old;
    try {
      old = json::parse(*text);
    } catch (const json::exception& e) {
      return makeError(planFile + ": not valid JSON: " + e.what());
    }
    // argv[0] may differ (a rebuilt binary elsewhere) and --quiet does not
    // change the results; every other option must be the same.
    auto comparable = [](json j) {
      if (!j.contains("command") || !j["command"].is_array() || j["command"].empty()) return j;
      json c = json::array();
      for (std::size_t i = 1; i < j["command"].size(); ++i)
        if (j["command"][i] != "--quiet") c.push_back(j["command"][i]);
      j["command"] = c;
      return j;
    };
    const json a = comparable(old), b = comparable(planJson);
    if (a != b)
      return makeError("--resume: " + planFile + " was made by a different command: " + old.dump() +
                       ", this run is " + planJson.dump() +
                       " (run without --resume to start over)");
  } else {
    fs::remove_all(plan.workDir, ec);
    if (ec) return makeError("cannot remove " + plan.workDir + ": " + ec.message());
  }
  HW_TRY(ensureWritableDir(plan.workDir + "/logs"));
  HW_TRY(writeFileAtomic(planFile, planJson.dump(1)));
  return {};
}

std::vector<int> missingChunks(const ChunkPlan& plan) {
  std::vector<int> m;
  for (int i = 0; i < plan.chunks; ++i)
    if (!haveResult(plan.workDir, i)) m.push_back(i);
  return m;
}

void progressLine(const DistributeOptions& o, const std::string& text) {
  if (!o.progress) return;
  std::fprintf(stderr, "\r%s        ", text.c_str());
  std::fflush(stderr);
}

// ---- local workers --------------------------------------------------------
Status runLocal(const ChunkPlan& plan, const DistributeOptions& o, const std::vector<int>& todo) {
  struct Running {
    pid_t pid;
    int chunk;
  };
  std::vector<Running> running;
  std::map<int, int> exitOf;  // chunk → exit status (−signal when killed)
  std::size_t next = 0;
  Stopwatch sw;
  markChildrenAsWorkers();  // each worker dies with this process (PR_SET_PDEATHSIG)
  auto spawn = [&](int chunk) -> Status {
    std::vector<std::string> args = plan.command;
    args.push_back("--chunk");
    args.push_back(std::to_string(chunk));
    std::vector<char*> cargv;
    for (auto& a : args) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    const std::string log = logFile(plan.workDir, chunk);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, cargv[0], &fa, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return makeError("cannot start " + args[0] + ": " + std::strerror(rc));
    running.push_back({pid, chunk});
    return {};
  };
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < o.workers && !gInterrupted)
      HW_TRY(spawn(todo[next++]));
    if (gInterrupted) {
      for (const auto& r : running) ::kill(r.pid, SIGTERM);
      for (const auto& r : running) ::waitpid(r.pid, nullptr, 0);
      if (o.progress) std::fprintf(stderr, "\n");
      return makeError(
          plan.label + ": interrupted (signal " + std::to_string(gInterrupted) +
          "); stopped the workers; run again with --resume to finish the missing chunks");
    }
    for (std::size_t i = 0; i < running.size();) {
      int st = 0;
      const pid_t p = ::waitpid(running[i].pid, &st, WNOHANG);
      if (p == running[i].pid) {
        exitOf[running[i].chunk] = WIFEXITED(st) ? WEXITSTATUS(st) : -WTERMSIG(st);
        running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
      } else {
        ++i;
      }
    }
    progressLine(o, plan.label + ": workers: " + std::to_string(exitOf.size()) + "/" +
                        std::to_string(todo.size()) + " chunks finished, " +
                        std::to_string(running.size()) + " running, elapsed " +
                        std::to_string(static_cast<int>(sw.ms() / 1000)) + " s");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (o.progress) std::fprintf(stderr, "\n");
  std::vector<int> failed;
  std::string detail;
  for (int c : todo) {
    if (haveResult(plan.workDir, c)) continue;
    failed.push_back(c);
    const int e = exitOf.count(c) ? exitOf[c] : 0;
    detail += "\n  chunk " + std::to_string(c) + ": " +
              (e < 0 ? "killed by signal " + std::to_string(-e) : "exit " + std::to_string(e)) +
              "; log " + logFile(plan.workDir, c) + ": " + tailOfLog(logFile(plan.workDir, c));
  }
  if (!failed.empty())
    return makeError(plan.label + ": " + std::to_string(failed.size()) + " of " +
                     std::to_string(todo.size()) + " worker chunks failed (indices " +
                     indexList(failed) + "):" + detail +
                     "\nrun the same command with --resume to rerun only these");
  return {};
}

// ---- Slurm ----------------------------------------------------------------
struct TaskInfo {
  std::string state = "UNKNOWN", exitCode = "?", reason;
};

// Per-task states from `scontrol show job JOBID` (no accounting needed).
std::map<int, TaskInfo> scontrolTasks(const std::string& jobId) {
  std::map<int, TaskInfo> out;
  const Captured c = capture({"scontrol", "show", "job", jobId});
  if (c.status != 0) return out;
  std::istringstream in(c.out);
  std::string record, line;
  auto flush = [&] {
    std::smatch m;
    static const std::regex task(R"(ArrayTaskId=(\d+))"), state(R"(JobState=(\S+))"),
        exitc(R"((?:^|\s)ExitCode=(\S+))"), reason(R"(Reason=(\S+))");
    if (std::regex_search(record, m, task)) {
      TaskInfo t;
      const int idx = std::stoi(m[1]);
      if (std::regex_search(record, m, state)) t.state = m[1];
      if (std::regex_search(record, m, exitc)) t.exitCode = m[1];
      if (std::regex_search(record, m, reason)) t.reason = m[1];
      out[idx] = t;
    }
    record.clear();
  };
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t") == std::string::npos)
      flush();
    else
      record += line + "\n";
  }
  flush();
  return out;
}

Status runSlurm(const ChunkPlan& plan, const DistributeOptions& o, const std::vector<int>& todo) {
  // The task script: the program on one chunk, the array index as chunk.
  std::string script =
      "#!/bin/sh\n# hybridwalk " + plan.label + ": one chunk per array task (docs/slurm.md)\nexec";
  for (const auto& a : plan.command) {
    script += ' ';
    script += shellQuote(a);
  }
  script += " --chunk \"$SLURM_ARRAY_TASK_ID\"\n";
  const std::string scriptFile = plan.workDir + "/task.sh";
  HW_TRY(writeFileAtomic(scriptFile, script));
  fs::permissions(scriptFile,
                  fs::perms::owner_all | fs::perms::group_read | fs::perms::others_read);
  std::error_code ec;
  const std::string cwd = fs::current_path(ec).string();
  std::vector<std::string> args = {"sbatch",
                                   "--parsable",
                                   "--array=" + indexList(todo),
                                   "--job-name=hw-" + plan.label,
                                   "--output=" + plan.workDir + "/logs/chunk-%4a.log",
                                   "--chdir=" + cwd};
  if (!o.partition.empty()) args.push_back("--partition=" + o.partition);
  if (!o.account.empty()) args.push_back("--account=" + o.account);
  if (!o.timeLimit.empty()) args.push_back("--time=" + o.timeLimit);
  for (const auto& a : o.sbatchArgs) args.push_back(a);
  args.push_back(scriptFile);
  const Captured sub = capture(args);
  std::string cmdText;
  for (const auto& a : args) {
    if (!cmdText.empty()) cmdText += ' ';
    cmdText += a;
  }
  if (sub.status != 0)
    return makeError(
        plan.label + ": sbatch failed (" +
        (sub.status < 0 ? std::string("not found or not runnable; is Slurm installed and on PATH?")
                        : "exit " + std::to_string(sub.status)) +
        "): " + lastLine(sub.out) + "\n  command: " + cmdText +
        (std::getenv("SLURM_CONF") ? "" : "\n  (SLURM_CONF is not set)"));
  std::string jobId = lastLine(sub.out);
  if (const auto semi = jobId.find(';'); semi != std::string::npos) jobId = jobId.substr(0, semi);
  if (jobId.empty() || jobId.find_first_not_of("0123456789") != std::string::npos)
    return makeError(plan.label + ": sbatch printed '" + sub.out + "', expected a job id");
  HW_TRY(writeFileAtomic(plan.workDir + "/job-id", jobId + "\n"));
  if (o.progress)
    std::fprintf(stderr, "%s: submitted Slurm job %s: %zu array tasks (indices %s)\n",
                 plan.label.c_str(), jobId.c_str(), todo.size(), indexList(todo).c_str());

  Stopwatch sw;
  int squeueFailures = 0;
  for (;;) {
    const Captured q = capture({"squeue", "-h", "-r", "-j", jobId, "-o", "%T"});
    squeueFailures = q.status == 0 ? 0 : squeueFailures + 1;
    int pending = 0, runningN = 0, other = 0;
    if (q.status == 0) {
      std::istringstream in(q.out);
      std::string st;
      while (in >> st) {
        if (st == "PENDING")
          ++pending;
        else if (st == "RUNNING" || st == "COMPLETING" || st == "CONFIGURING")
          ++runningN;
        else
          ++other;
      }
    }
    int done = 0;
    for (int c : todo) done += haveResult(plan.workDir, c);
    progressLine(o, plan.label + ": Slurm job " + jobId + ": " + std::to_string(done) + "/" +
                        std::to_string(todo.size()) + " tasks done, " + std::to_string(runningN) +
                        " running, " + std::to_string(pending) + " pending, elapsed " +
                        std::to_string(static_cast<int>(sw.ms() / 1000)) + " s");
    // An empty list means the job has ended; squeue also fails once the job
    // is purged (MinJobAge), so five failures in a row count as ended too
    // (one failure may be a busy controller).
    if ((q.status == 0 && pending + runningN + other == 0) || squeueFailures >= 5) break;
    for (int t = 0; !gInterrupted && t < static_cast<int>(o.pollSeconds * 10); ++t)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (gInterrupted) {
      const Captured c = capture({"scancel", jobId});
      if (o.progress) std::fprintf(stderr, "\n");
      return makeError(
          plan.label + ": interrupted (signal " + std::to_string(gInterrupted) +
          "); cancelled Slurm job " + jobId +
          (c.status == 0 ? std::string() : " (scancel failed: " + lastLine(c.out) + ")") +
          "; run the same command with --resume to finish the missing chunks");
    }
  }
  if (o.progress) std::fprintf(stderr, "\n");
  const std::vector<int> missing = [&] {
    std::vector<int> m;
    for (int c : todo)
      if (!haveResult(plan.workDir, c)) m.push_back(c);
    return m;
  }();
  if (missing.empty()) return {};
  const auto tasks = scontrolTasks(jobId);
  std::string detail;
  for (int c : missing) {
    const auto it = tasks.find(c);
    detail += "\n  array index " + std::to_string(c) + ": " +
              (it == tasks.end() ? std::string("state unknown (job no longer in scontrol)")
                                 : it->second.state + ", exit code " + it->second.exitCode +
                                       (it->second.reason.empty() || it->second.reason == "None"
                                            ? ""
                                            : ", reason " + it->second.reason)) +
              "; log " + logFile(plan.workDir, c) + ": " + tailOfLog(logFile(plan.workDir, c));
  }
  return makeError(plan.label + ": " + std::to_string(missing.size()) + " of " +
                   std::to_string(todo.size()) + " tasks of Slurm job " + jobId +
                   " failed (array indices " + indexList(missing) + "):" + detail +
                   "\nrun the same command with --resume to resubmit only these");
}

}  // namespace

std::string chunkResultFile(const std::string& workDir, int chunk) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "/chunk-%04d.json", chunk);
  return workDir + buf;
}

Status runChunks(const ChunkPlan& plan, const DistributeOptions& o) {
  HW_CHECK_GE(plan.chunks, 1);
  HW_CHECK(!plan.command.empty());
  HW_TRY(prepareWorkDir(plan, o.resume));
  const std::vector<int> todo = missingChunks(plan);
  if (todo.empty()) return {};
  if (o.resume && o.progress)
    std::fprintf(stderr, "%s: resuming: %zu of %d chunks to run (indices %s)\n", plan.label.c_str(),
                 todo.size(), plan.chunks, indexList(todo).c_str());
  SignalGuard guard;  // from before sbatch / the first worker until the end
  return o.slurm ? runSlurm(plan, o, todo) : runLocal(plan, o, todo);
}

Result<std::vector<json>> readChunkResults(const ChunkPlan& plan) {
  std::vector<json> out;
  for (int i = 0; i < plan.chunks; ++i) {
    const std::string f = chunkResultFile(plan.workDir, i);
    auto text = readFile(f);
    if (!text) return text.error();
    auto parsed = parseJsonStrict(*text, f);
    if (!parsed) return parsed.error();
    out.push_back(std::move(*parsed));
  }
  return out;
}

Status failChunkHook(int chunk) {
  const char* env = std::getenv("HW_FAIL_CHUNK");
  if (!env) return {};
  std::stringstream in(env);
  std::string item;
  while (std::getline(in, item, ','))
    if (item == std::to_string(chunk))
      return makeError("chunk " + std::to_string(chunk) +
                       " failed on purpose (HW_FAIL_CHUNK=" + env + ", a test hook)");
  return {};
}

Status writeChunkResult(const std::string& workDir, int chunk, const json& result) {
  return writeFileAtomic(chunkResultFile(workDir, chunk), result.dump());
}

std::vector<std::string> chunkCommand(int argc, char** argv) {
  static const std::set<std::string> flags = {"--slurm", "--resume"};
  static const std::set<std::string> withValue = {"--workers",       "--slurm-partition",
                                                  "--slurm-account", "--slurm-time",
                                                  "--sbatch-arg",    "--slurm-poll"};
  std::vector<std::string> out;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  out.push_back(ec ? fs::absolute(argv[0]).string() : self.string());
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const std::string name = a.substr(0, a.find('='));
    if (flags.count(a)) continue;
    if (withValue.count(name)) {
      if (a.find('=') == std::string::npos) ++i;  // skip the value too
      continue;
    }
    out.push_back(a);
  }
  return out;
}

void removeChunkDir(const std::string& workDir) {
  std::error_code ec;
  fs::remove_all(workDir, ec);
}

}  // namespace hw
