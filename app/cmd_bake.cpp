// The `bake` command.
#include "app/commands.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/viewer.h"
#include "session/bake.h"
#include "session/presets.h"
#include "session/export.h"
#include "core/json_util.h"
#include "core/chunked_runs.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "session/keyframe_planner.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "app/cli_common.h"

namespace hw::app {
namespace {

using nlohmann::json;

int runBake(const Common& c, const keyframe::LodOptions& lod, const std::string& out, int perTask,
            bool quiet, DistributeCli& dist, int argc, char** argv) {
  if (out.empty()) return fail("bake: --out DIR is required (the keyframe database directory)");
  auto in = loadInputs(c);
  if (!in) return fail(in.error().message);
  session::BakeOptions bo;
  bo.lod = lod;
  bo.depthMode = depthModeOf(c.depth);
  bo.maxFrames = c.frames;
  bo.outDir = out;
  bo.progress = !quiet && dist.chunk < 0;
  const int frames = session::bakeFrames(in->path, c.frames);
  const std::vector<int> keys = session::bakeKeyframeList(in->path, frames);
  const auto prov = session::bakeProvenance(c.scene, in->scene.triangleCount(), in->path, frames, lod, bo.depthMode);
  const int chunks = static_cast<int>((keys.size() + perTask - 1) / perTask);
  const std::string work = out + "/.chunks";
  auto range = [&](int i) {
    return std::vector<int>(keys.begin() + i * perTask,
                            keys.begin() + std::min<std::size_t>(keys.size(), (i + 1) * std::size_t(perTask)));
  };
  auto entryJson = [](const keyframe::KeyframeDbEntry& e) {
    return json{{"frame", e.frame}, {"file", e.file}, {"bytes", e.bytes}, {"checksum", keyframe::hex64(e.checksum)}};
  };
  if (dist.chunk >= 0) {
    if (dist.chunk >= chunks)
      return fail("--chunk: " + std::to_string(dist.chunk) + " out of range 0.." + std::to_string(chunks - 1));
    if (auto st = failChunkHook(dist.chunk); !st) return fail(st.error().message);
    auto e = session::bakeKeyframes(in->scene, in->path, range(dist.chunk), bo);
    if (!e) return fail(e.error().message);
    json ej = json::array();
    for (const auto& x : *e) ej.push_back(entryJson(x));
    if (auto st = writeChunkResult(work, dist.chunk, {{"entries", ej}}); !st) return fail(st.error().message);
    return 0;
  }
  if (dist.d.resume && !distributed(dist.d))
    return fail("--resume: only with --slurm or --workers N > 1 (an in-process bake has no chunks to resume)");
  auto start = session::prepareBakeDir(out, prov, in->path, keys, bo.depthMode, dist.d.resume);
  if (!start) return fail(start.error().message);
  if (*start == session::BakeStart::Complete) {
    if (OutputDir* held = OutputDir::held(out)) held->leaveAsFound();
    std::printf("bake: %s is complete (every keyframe of this bake, checked); nothing to do\n",
                out.c_str());
    return 0;
  }
  std::vector<keyframe::KeyframeDbEntry> entries;
  Stopwatch sw;
  if (distributed(dist.d)) {
    ChunkPlan plan{"bake", work, chunks, chunkCommand(argc, argv)};
    dist.d.progress = !quiet;
    if (auto st = runChunks(plan, dist.d); !st) return fail(st.error().message);
    auto results = readChunkResults(plan);
    if (!results) return fail(results.error().message);
    for (const json& r : *results) {
      auto es = keyframe::parseKeyframeEntries(r.contains("entries") ? r["entries"] : json(),
                                               work + " (chunk result)");
      if (!es) return fail(es.error().message);
      entries.insert(entries.end(), es->begin(), es->end());
    }
  } else {
    auto e = session::bakeKeyframes(in->scene, in->path, keys, bo);
    if (!e) return fail(e.error().message);
    entries = std::move(*e);
  }
  if (auto st = session::writeBakeIndex(out, prov, entries); !st) return fail(st.error().message);
  if (distributed(dist.d)) removeChunkDir(work);
  std::uint64_t bytes = 0;
  for (const auto& e : entries) bytes += e.bytes;
  // Every keyframe of the schedule; a walk from the database reads those its
  // warped segments need ("keyframes ... read from the database").
  std::printf("bake: %zu keyframes built and written (every keyframe in the schedule) of %d frames "
              "(%s, %dx%d) in %.1f s, %.1f MB; database %s (index.json)\n",
              entries.size(), frames, c.scene.c_str(), in->path.width, in->path.height, sw.ms() / 1000.0,
              bytes / 1e6, out.c_str());
  return 0;
}

struct BakeCli {
  CLI::App* bakeCmd = nullptr;
  Common bakeC;
  std::string bakeOut;
  // The walk's presets and LOD options: the same defaults, so that `walk
  // --keyframes DB` with the same preset and options finds the database's
  // LOD settings.
  PresetCli pc;
  bool bakeQuiet = false;
  int bakePerTask = 8;
  DistributeCli bakeDist;
};

int run(BakeCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    session::Preset preset = session::Preset::Default;
    session::WalkOptions wo;
    if (const int code = applyPresetCli(o.bakeCmd, o.pc, &preset, &wo); code != 0) return code;
    if (const int code = refusePaperDeparture(preset, wo); code != 0) return code;
    const keyframe::LodOptions& lo = wo.lod;
    return runBake(o.bakeC, lo, o.bakeOut, o.bakePerTask, o.bakeQuiet, o.bakeDist, argc, argv);
}

}  // namespace

void addBakeCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<BakeCli>();
  BakeCli& o = *state;
  // bake
  auto* bakeCmd = o.bakeCmd = app.add_subcommand(
      "bake", "Render and mesh every keyframe of a path ahead of time into a keyframe database "
              "(one checksummed file per keyframe + index.json, docs/keyframe-db.md) for "
              "'walk --keyframes DB'; --slurm runs it as a Slurm job array");
  addCommon(bakeCmd, o.bakeC);
  bakeCmd->add_option("--out", o.bakeOut, "Database directory (created)")->required();
  addWalkOptionSet(bakeCmd, &o.pc, bakeRows(),
                   "LOD settings to start from, as for walk: default or paper");
  bakeCmd->add_option("--keyframes-per-task", o.bakePerTask,
                      "Keyframes per chunk (--slurm array task or --workers process)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  bakeCmd->add_flag("--quiet", o.bakeQuiet, "No progress line");
  addDistribute(bakeCmd, o.bakeDist, "--keyframes-per-task keyframes");

  addForceOption(bakeCmd);
  commands.push_back({bakeCmd, [state](int argc, char** argv) {
    if (state->bakeDist.chunk >= 0) return run(*state, argc, argv);  // in the parent's folder
    return runInOutputDir(state->bakeCmd, state->bakeOut, {},
                          [&] { return run(*state, argc, argv); });
  }});
}

}  // namespace hw::app
