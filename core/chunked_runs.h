#pragma once
// Chunked runs of `bake` and `sweep`: the work is split into chunks, each run
// by `hybridwalk` itself in a hidden chunk mode (`--chunk I`) that writes its
// partial result to WORK/chunk-I.json; chunks run in local worker processes
// or as the tasks of one Slurm job array (sbatch), and the caller merges the
// results. Design and options: docs/slurm.md.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"

namespace hw {

struct DistributeOptions {
  bool slurm = false;   // sbatch --array; else local worker processes
  int workers = 1;      // local worker processes (slurm = false); 1 = in-process (no chunks)
  bool resume = false;  // run only chunks without a result; keep the others
  std::string partition, account, timeLimit;  // sbatch --partition/--account/--time when set
  std::vector<std::string> sbatchArgs;        // passed to sbatch as given
  double pollSeconds = 2.0;                   // squeue interval
  bool progress = true;
};

// True when the chunks run out of process (--slurm, or --workers > 1).
inline bool distributed(const DistributeOptions& d) { return d.slurm || d.workers > 1; }

struct ChunkPlan {
  std::string label;    // "bake" / "sweep": job name hw-LABEL, messages
  std::string workDir;  // OUT/.chunks (created; logs in workDir/logs)
  int chunks = 0;
  // argv of one chunk run without "--chunk I" (absolute program path first).
  std::vector<std::string> command;
};

std::string chunkResultFile(const std::string& workDir, int chunk);  // WORK/chunk-000I.json

// Prepares workDir (fresh, or checked against plan.json on resume), runs every
// chunk without a result file, waits, and returns OK when all chunks have
// results. Failed chunks are named by index (with Slurm's state and exit
// code, and their log file). SIGINT/SIGTERM during the wait cancels the job
// (scancel) or stops the workers, and returns an error.
Status runChunks(const ChunkPlan& plan, const DistributeOptions& options);

// Reads every chunk's result (after runChunks succeeded).
Result<std::vector<nlohmann::json>> readChunkResults(const ChunkPlan& plan);

// Writes a chunk's result atomically. Honours the test hook HW_FAIL_CHUNK=I
// (comma-separated indices): those chunks fail with an error instead.
Status writeChunkResult(const std::string& workDir, int chunk, const nlohmann::json& result);
Status failChunkHook(int chunk);

// argv without the options that only the parent uses (--slurm, --resume,
// --workers, --slurm-*, --sbatch-arg), with argv[0] made absolute
// (/proc/self/exe).
std::vector<std::string> chunkCommand(int argc, char** argv);

// Removes workDir after a successful merge.
void removeChunkDir(const std::string& workDir);

}  // namespace hw
