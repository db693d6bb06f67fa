#pragma once
// Output folders the program owns: a marker file names the command that owns
// the folder and is flock()ed for the whole run, so one writer at a time writes
// into it; folders that are not ours, owned by another command, or reached
// through a symlink are refused unless forced. Format and rules:
// docs/output-folders.md.
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"

namespace hw {

// The marker's file name inside an owned folder.
inline constexpr const char* kOwnerMarkerName = ".hybridwalk-owner.json";

// What a marker says (fields empty/0 where it says nothing readable).
struct OutputDirOwner {
  std::string command;  // "walk", "bake", ...
  std::string version;
  std::string started;  // UTC, ISO 8601
  long pid = 0;
  bool readable = false;  // the marker parsed as a hybridwalk marker
};
// The owner recorded in DIR's marker; readable == false without one.
OutputDirOwner readOutputDirOwner(const std::string& dir);

// An output folder held by this process: the marker names `command` and this
// PID, and its flock is held until destruction. Not copyable.
class OutputDir {
 public:
  // Claims `dir` for `command`. A new or empty folder is created and claimed;
  // a folder whose marker names `command` is claimed again, and the
  // temporaries its previous run left (NAME.tmp-PID with that run's recorded
  // PID, in the folder and its direct subfolders) are removed. Refused with a
  // message naming the folder: a folder another process holds ("DIR is in use
  // by PID P (walk, started T)", --force does not override this); unless
  // `force`: a non-empty folder without a marker, a folder owned by another
  // command, a symlink. Anything else in the folder is never deleted.
  static Result<std::unique_ptr<OutputDir>> open(const std::string& dir, const std::string& command,
                                                 bool force);
  // Releases the lock. When the run wrote nothing (the folder holds only the
  // marker), the marker this run created goes, and the folder if it made it.
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  const std::string& dir() const { return dir_; }
  // The owner this folder had before this run (readable == false if none).
  const OutputDirOwner& previousOwner() const { return previous_; }

  // `name` (relative to the folder) is a summary that describes the other
  // outputs (report.json, sweep.json): an earlier run's copy is removed now,
  // and this run's is removed again at exit, or on SIGINT/SIGTERM, unless
  // commit() was called after everything it describes was written. A run that
  // fails leaves no complete-looking summary.
  void provisional(const std::string& name);
  // Every output is written: provisional summaries stay, and so does the
  // marker naming this run. Without it the marker gets back what it held
  // before this run (a refused or failed run does not change who wrote the
  // folder last).
  void commit();
  // This run changed nothing in the folder (bake --resume on a finished
  // database): the marker gets back its previous bytes at exit even after
  // commit(), so the folder is byte-identical to what it was.
  void leaveAsFound();
  // The folder `dir` this process holds (the path as given to open), or null.
  static OutputDir* held(const std::string& dir);

 private:
  OutputDir() = default;
  std::string dir_;
  int fd_ = -1;
  bool createdDir_ = false;     // made by this run: removed at exit if it holds only the marker
  bool createdMarker_ = false;  // the folder had none: removed at exit if it is all there is
  OutputDirOwner previous_;
  std::string previousMarker_;  // its bytes
  bool leaveAsFound_ = false;
  bool committed_ = false;
  struct Provisional;
  std::vector<std::unique_ptr<Provisional>> provisional_;
};

// Removes, in `dir` and its direct subfolders (not through symlinks), the
// regular files whose name ends exactly in ".tmp-PID" for this `pid`: the
// temporaries a run of that PID left when it was killed. A note on stderr
// names each. Returns how many were removed.
int removeTemporariesOfRun(const std::string& dir, long pid);

// The time now as ISO 8601 UTC, "2026-12-07T10:33:14Z".
std::string utcNow();

}  // namespace hw
