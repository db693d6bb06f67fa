// hybridwalk: the command-line program. Subcommands render (geometry frames),
// lod (a keyframe's quad mesh overlay, paper Plate I-A) and walk (the hybrid
// walkthrough with its report, the main job). Errors from outside (files,
// options, GL) are printed as "hybridwalk: error: ..." with a non-zero exit.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/option_checks.h"
#include "app/viewer.h"
#include "bench/bake.h"
#include "bench/bench_suite.h"
#include "bench/export.h"
#include "bench/json_util.h"
#include "bench/slurm.h"
#include "bench/schedule_calibration.h"
#include "bench/schedule_oracle.h"
#include "bench/schedule_study.h"
#include "bench/stress.h"
#include "bench/sweep.h"
#include "bench/walk.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/safe_io.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/keyframe_planner.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"

namespace {

using namespace hw;  // NOLINT
using nlohmann::json;

constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

int fail(const std::string& msg) {
  std::fprintf(stderr, "hybridwalk: error: %s\n", msg.c_str());
  return kExitRuntime;
}

// "2048", "2^11", "1e3" → value; error text otherwise.
bool parseTau(const std::string& s, double* out) {
  try {
    std::size_t pos = 0;
    const auto caret = s.find('^');
    double v;
    if (caret != std::string::npos) {
      const double base = std::stod(s.substr(0, caret), &pos);
      if (pos != caret) return false;
      const std::string e = s.substr(caret + 1);
      const double ex = std::stod(e, &pos);
      if (pos != e.size()) return false;
      v = std::pow(base, ex);
    } else {
      v = std::stod(s, &pos);
      if (pos != s.size()) return false;
    }
    if (!std::isfinite(v) || v < 0) return false;
    *out = v;
    return true;
  } catch (...) {
    return false;
  }
}

// A whole string that is one finite number (strtod syntax).
bool parseFiniteDouble(const std::string& s, double* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

// "4,6,2^3" → values (each as parseTau); false on a bad element.
bool parseList(const std::string& s, std::vector<double>* out) {
  out->clear();
  std::size_t start = 0;
  while (start < s.size()) {
    std::size_t end = s.find(',', start);
    if (end == std::string::npos) end = s.size();
    double v = 0;
    if (!parseTau(s.substr(start, end - start), &v)) return false;
    out->push_back(v);
    start = end + 1;
  }
  return true;
}

// --tau-gradient (LodOptions::tauGradient): the option and its parse.
std::string suggestedTauGradient() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", keyframe::suggestedTauGradient());
  return buf;
}
std::string tauGradientHelp() {
  return "Gradient-following LOD tolerance A: a pixel is non-planar when |Δ²z'| > tau + A·g, "
         "g its depth gradient in z' units per pixel (per axis the smaller one-sided "
         "difference, so a depth step does not raise its own tolerance). Dimensionless: extra "
         "z' tolerance per z' unit/pixel of gradient; absorbs rasteriser noise on steep planes "
         "at small tau. 0 = off (the fixed tau); suggested " +
         suggestedTauGradient();
}
bool parseTauGradient(const std::string& s, double* out, std::string* err) {
  if (parseTau(s, out)) return true;
  *err = "--tau-gradient: expected a finite non-negative number like " +
         suggestedTauGradient() + ", got '" + s + "'";
  return false;
}

// LOD options shared by the schedule commands (schedule-study, schedule-oracle).
struct StudyLod {
  std::string tau = "2^11", planarity = "region-local";
  bool noMerge = false;
};

void addStudyLodOptions(CLI::App* c, StudyLod& o) {
  c->add_option("--tau", o.tau, "LOD threshold in z' units ('2^11' or '2048')")->capture_default_str();
  c->add_option("--planarity", o.planarity, "stencil (paper) or region-local")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  c->add_flag("--no-merge-strips", o.noMerge, "Do not merge coplanar leaves");
}

// Empty on success, else the message for the user.
std::string applyStudyLod(const StudyLod& o, keyframe::LodOptions* lod) {
  if (!parseTau(o.tau, &lod->tau))
    return "--tau: expected a non-negative number like 2048 or 2^11, got '" + o.tau + "'";
  keyframe::parsePlanarity(o.planarity.c_str(), &lod->planarity);
  lod->mergeStrips = !o.noMerge;
  return {};
}

// --spacings: comma-separated whole frame counts from 1 to maxSpacing (0 = no
// bound, named by maxName in the message). Empty on success, else the message.
std::string parseSpacings(const std::string& text, int maxSpacing, const std::string& maxName,
                          std::vector<int>* out, const std::string& option = "--spacings") {
  std::vector<double> v;
  if (!parseList(text, &v) || v.empty())
    return option + ": expected comma-separated frame counts like 4,10,20, got '" + text + "'";
  out->clear();
  for (double d : v) {
    if (d < 1 || d != std::floor(d) || (maxSpacing > 0 && d > maxSpacing))
      return maxSpacing > 0 ? option + ": expected whole numbers from 1 to " + maxName + " " +
                                  std::to_string(maxSpacing) + ", got '" + text + "'"
                            : option + ": expected whole numbers >= 1, got '" + text + "'";
    out->push_back(static_cast<int>(d));
  }
  return {};
}

// Keyframe schedule options of walk and schedule-study (issue #8).
void addPlannerOptions(CLI::App* c, keyframe::PlannerOptions& p, std::string& predictor,
                       std::string& planBy, bool withAuto) {
  c->add_option("--plan-by", planBy,
                "Adaptive schedule: worst (every in-between frame predicted >= the target), "
                "mean (each segment's mean predicted PSNR >= the target) or median (each "
                "segment's median: at least half of all in-between frames) or walk-median "
                "(the fewest keyframes with more than half of all in-between frames predicted "
                ">= the target, placed by dynamic programming over the whole path)")
      ->check(CLI::IsMember({"worst", "mean", "median", "walk-median"}))
      ->capture_default_str();
  c->add_option("--min-gap", p.minGap, "Adaptive schedule: fewest frames between keyframes")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  c->add_option("--max-gap", p.maxGap, "Adaptive schedule: most frames between keyframes")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  c->add_option("--probe-size", p.probeSize,
                "Adaptive schedule: the predictor's low-resolution keyframe probes, pixels on "
                "the longer side")
      ->check(CLI::Range(8, 1024))
      ->capture_default_str();
  c->add_option("--candidate-stride", p.candidateStride,
                "Adaptive schedule: try the next keyframe only every this many frames (fewer "
                "probes to render)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  c->add_option("--frames-per-segment", p.framesPerSegment,
                "Adaptive schedule: in-between frames tested per candidate segment, evenly "
                "spaced (0 = all; fewer = cheaper, may miss a bad frame)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
  std::vector<std::string> names;
  if (withAuto) names.push_back("auto");
  for (auto pr : keyframe::kAllPredictors) names.push_back(keyframe::predictorName(pr));
  for (auto pr : keyframe::kProbePredictors) names.push_back(keyframe::predictorName(pr));
  c->add_option("--predictor", predictor,
                std::string("Adaptive schedule's predictor of in-between quality: holes (fraction "
                            "of a low-res frame neither keyframe's forward splat covers), distance "
                            "(eye offset / keyframe median depth), angle (view direction, deg), "
                            "stretch (mean |log2| area change of warped pixels), disagreement "
                            "(colour MSE between the two warped probes), holes+distance (both, two-term fit), "
                            "probe-psnr (both keyframe probes warped into the frame's own probe and "
                            "composed like the walk; its low-res PSNR, holes charged, calibrated "
                            "to full-res dB; renders every frame's probe), probe-psnr+distance "
                            "(that and distance, two-term fit), probe-psnr+features (probe-psnr, "
                            "distance, holes, stretch, disagreement and angle: six regressors, "
                            "meant to be refitted on the scene with --calibrate-spacing)") +
                    (withAuto ? "; auto = the one, probe predictors included, whose fit ranks the fixed walks' PSNR best (Spearman; fits where PSNR rises with the regressor are skipped)" : ""))
      ->check(CLI::IsMember(names))
      ->capture_default_str();
}

struct Common {
  std::string scene = "indoor";
  std::string path;  // empty: the scene's default path
  std::string depth = depthModeName(kDefaultDepthMode);
  int frames = 0;
};

// A whole number of frames in [lo, hi]: "expected a whole number of frames from
// lo to hi, got 'V'".
CLI::Validator wholeFrames(long lo, long hi, const std::string& name) {
  return CLI::Validator(
      [lo, hi](std::string& v) -> std::string {
        char* end = nullptr;
        const long x = std::strtol(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || x < lo || x > hi)
          return "expected a whole number of frames from " + std::to_string(lo) + " to " +
                 std::to_string(hi) + ", got '" + v + "'";
        return {};
      },
      "FRAMES", name);
}

// --frame-budget-ms MS|auto with --frame-budget-quantile and --frame-budget-window
// (walk and view; bench/frame_budget.h).
struct FrameBudgetCli {
  std::string arg = "0";
  double quantile = 0.9;
  int window = 30;
  bool isAuto() const { return arg == "auto"; }
  double ms() const { return isAuto() ? 0.0 : std::strtod(arg.c_str(), nullptr); }
};

void addFrameBudgetOptions(CLI::App* c, FrameBudgetCli& o, const std::string& what) {
  c->add_option("--frame-budget-ms", o.arg,
                "Per-frame time budget in milliseconds of frame work (0 = off), or 'auto': " +
                    what +
                    ". 'auto' sets each frame's budget to the --frame-budget-quantile of the "
                    "work of the last --frame-budget-window frames, so the frame rate stays "
                    "steady on any scene and machine")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            if (v == "auto") return {};
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (v.empty() || *end != '\0' || !std::isfinite(x) || x < 0 || x > 60000)
              return "expected milliseconds from 0 (off) to 60000, or 'auto', got '" + v + "'";
            return {};
          },
          "MS|auto", "frame budget"))
      ->capture_default_str();
  c->add_option("--frame-budget-quantile", o.quantile,
                "With --frame-budget-ms auto: the budget is this quantile of the recent "
                "frames' work (walk: in-between frames, without their refresh; above 0, at most 1; 0.9 = 90th percentile: about one frame in "
                "ten is late, the others present at the budget)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (v.empty() || *end != '\0' || !std::isfinite(x) || x <= 0 || x > 1)
              return "expected a quantile above 0 and at most 1, got '" + v + "'";
            return {};
          },
          "Q", "budget quantile"))
      ->capture_default_str();
  c->add_option("--frame-budget-window", o.window,
                "With --frame-budget-ms auto: how many of the last frames the quantile is taken "
                "over (frames, 1 to 100000)")
      ->check(wholeFrames(1, 100000, "budget window"))
      ->capture_default_str();
}

void addCommon(CLI::App* c, Common& o) {
  c->add_option("--scene", o.scene,
                "Scene: 'indoor' or 'outdoor' (built-in; append ':N' for ~N triangles, e.g. "
                "indoor:1M; default 100k), or a model file read by Assimp (OBJ, glTF, PLY, "
                "COLLADA, AC3D, .blend, ...)")
      ->capture_default_str();
  c->add_option("--path", o.path,
                "Camera path JSON (DESIGN.md format: width, height, fov_y_deg, near, far, up, "
                "keys[{eye, look_at}], frames, keyframe_every; scene units). Default: the "
                "scene's built-in path");
  c->add_option("--depth", o.depth,
                "Keyframe depth buffer: float32-reversed (default: keeps corner accuracy at "
                "far/near 1e5..1e6), fixed24 (the paper's 24-bit z-buffer), float32; all mapped "
                "to the same z' scale")
      ->check(CLI::IsMember({"fixed24", "float32", "float32-reversed"}))
      ->capture_default_str();
  c->add_option("--frames", o.frames, "Stop after this many frames of the path (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  c->add_flag_callback("--allow-external-refs", [] { scenes::setExternalRefsAllowed(true); },
                       "Let a model file name files outside its own folder tree (glTF buffers "
                       "and images, OBJ mtllib, textures); refused by default");
  c->add_option_function<int>(
       "--max-texture-size", [](const int& px) { setMaxTextureSize(px); },
       "Scene textures with a side above this are downscaled (with a warning); images over "
       "max(8192, this)^2 pixels are not decoded (default 8192)")
      ->check(CLI::Range(16, 65536));
}

struct Loaded {
  scenes::Scene scene;
  scenes::CameraPath path;
  std::unique_ptr<gl::Context> context;
};

Result<Loaded> loadInputs(const Common& o) {
  Loaded l;
  // Validate the cheap inputs first, so a bad path file fails before a
  // large scene is generated or loaded.
  if (!o.path.empty()) {
    auto p = scenes::loadCameraPath(o.path);
    if (!p) return p.error();
    l.path = std::move(*p);
  }
  Stopwatch sw;
  auto s = scenes::loadScene(o.scene);
  if (!s) return s.error();
  l.scene = std::move(*s);
  for (const auto& w : l.scene.warnings) std::fprintf(stderr, "hybridwalk: warning: %s\n", w.c_str());
  std::fprintf(stderr, "scene %s: %zu triangles, %zu meshes, loaded in %.0f ms\n",
               l.scene.name.c_str(), l.scene.triangleCount(), l.scene.meshes.size(), sw.ms());
  if (o.path.empty()) {
    auto p = scenes::defaultPathFor(o.scene);
    if (!p) return p.error();
    l.path = std::move(*p);
  }
  auto ctx = gl::createHeadlessContext();
  if (!ctx) return ctx.error();
  l.context = std::move(*ctx);
  return l;
}

DepthMode depthModeOf(const std::string& s) {
  DepthMode m = kDefaultDepthMode;
  parseDepthMode(s.c_str(), &m);
  return m;
}

// ---- render ---------------------------------------------------------------
int runRender(const Common& o, const std::string& outDir) {
  auto in = loadInputs(o);
  if (!in) return fail(in.error().message);
  if (auto st = ensureWritableDir(outDir); !st) return fail(st.error().message);
  keyframe::RenderOptions ropt;
  ropt.depthMode = depthModeOf(o.depth);
  auto r = keyframe::GeometryRenderer::create(in->scene, ropt);
  if (!r) return fail(r.error().message);
  const int frames = o.frames > 0 ? std::min(o.frames, in->path.frames) : in->path.frames;
  Image<Rgba8> img;
  json fr = json::array();
  std::vector<double> ms;
  Stopwatch progress, all;
  for (int i = 0; i < frames; ++i) {
    keyframe::RenderStats st;
    if (auto s = (*r)->renderColour(in->path.cameraAt(i), img, &st); !s) return fail(s.error().message);
    char name[32];
    std::snprintf(name, sizeof name, "%04d.png", i);
    if (auto s = writePng(outDir + "/" + name, img); !s) return fail(s.error().message);
    fr.push_back({{"index", i}, {"ms", st.drawMs + st.readbackMs}, {"draw_ms", st.drawMs},
                  {"readback_ms", st.readbackMs}, {"meshes_drawn", st.meshesDrawn},
                  {"triangles_drawn", st.trianglesDrawn}});
    ms.push_back(st.drawMs + st.readbackMs);
    if (progress.ms() > 1000 || i + 1 == frames) {
      progress.restart();
      std::fprintf(stderr, "\rrender: frame %d/%d, ETA %.0f s   %s", i + 1, frames,
                   all.ms() / 1000.0 / (i + 1) * (frames - i - 1), i + 1 == frames ? "\n" : "");
    }
  }
  json report = {{"frames", fr},
                 {"summary",
                  {{"scene", {{"name", in->scene.name}, {"triangles", in->scene.triangleCount()}}},
                   {"resolution", {in->path.width, in->path.height}},
                   {"depth_mode", o.depth},
                   {"ms", {{"median", median(ms)}, {"p95", percentile(ms, 95)}}},
                   {"machine", machineInfo(in->context->renderer(), in->context->version())}}}};
  if (auto s = writeFileAtomic(outDir + "/render.json", report.dump(1)); !s) return fail(s.error().message);
  std::printf("rendered %d frames of %s (%zu triangles) at %dx%d: median %.2f ms, p95 %.2f ms\n"
              "frames and render.json in %s\n",
              frames, in->scene.name.c_str(), in->scene.triangleCount(), in->path.width,
              in->path.height, median(ms), percentile(ms, 95), outDir.c_str());
  return 0;
}


// ---- chunked runs (bake, sweep): --slurm / --workers, docs/slurm.md ----------
struct DistributeCli {
  bench::DistributeOptions d;
  int chunk = -1;  // hidden: run one chunk (what a worker or array task runs)
};

void addDistribute(CLI::App* c, DistributeCli& o, const char* unit) {
  c->add_flag("--slurm", o.d.slurm,
              std::string("Run the chunks as one Slurm job array (sbatch --array; one task per chunk of ") +
                  unit + "), poll squeue, merge; SIGINT/SIGTERM cancels the job (docs/slurm.md)");
  c->add_option("--workers", o.d.workers,
                "Without --slurm: run the chunks in this many local worker processes (1 = in-process)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  c->add_flag("--resume", o.d.resume,
              "Rerun only the chunks without a result from an earlier failed or interrupted run of the "
              "same command (same --out)");
  c->add_option("--slurm-partition", o.d.partition, "sbatch --partition");
  c->add_option("--slurm-account", o.d.account, "sbatch --account");
  c->add_option("--slurm-time", o.d.timeLimit, "sbatch --time: time limit per array task (minutes, or [D-]H:MM:SS), e.g. 30 or 1:00:00");
  c->add_option("--sbatch-arg", o.d.sbatchArgs,
                "Extra sbatch argument, passed as given (repeatable); write it with = since it starts "
                "with a dash: --sbatch-arg=--qos=short")
      ->allow_extra_args(false);
  c->add_option("--slurm-poll", o.d.pollSeconds, "Seconds between squeue polls")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  c->add_option("--chunk", o.chunk, "internal: run one chunk")->group("");
}

int runBake(const Common& c, const keyframe::LodOptions& lod, const std::string& out, int perTask,
            bool quiet, DistributeCli& dist, int argc, char** argv) {
  namespace fs = std::filesystem;
  if (out.empty()) return fail("bake: --out DIR is required (the keyframe database directory)");
  auto in = loadInputs(c);
  if (!in) return fail(in.error().message);
  bench::BakeOptions bo;
  bo.lod = lod;
  bo.depthMode = depthModeOf(c.depth);
  bo.maxFrames = c.frames;
  bo.outDir = out;
  bo.progress = !quiet && dist.chunk < 0;
  const int frames = bench::bakeFrames(in->path, c.frames);
  const std::vector<int> keys = bench::bakeKeyframeList(in->path, frames);
  const auto prov = bench::bakeProvenance(c.scene, in->scene.triangleCount(), in->path, frames, lod, bo.depthMode);
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
    if (auto st = bench::failChunkHook(dist.chunk); !st) return fail(st.error().message);
    auto e = bench::bakeKeyframes(in->scene, in->path, range(dist.chunk), bo);
    if (!e) return fail(e.error().message);
    json ej = json::array();
    for (const auto& x : *e) ej.push_back(entryJson(x));
    if (auto st = bench::writeChunkResult(work, dist.chunk, {{"entries", ej}}); !st) return fail(st.error().message);
    return 0;
  }
  if (dist.d.resume && !bench::distributed(dist.d))
    return fail("--resume: only with --slurm or --workers N > 1 (an in-process bake has no chunks to resume)");
  if (auto st = ensureWritableDir(out); !st) return fail(st.error().message);
  // A fresh bake replaces an earlier database: its index first (a directory
  // without index.json is an incomplete database), then its keyframe files.
  std::error_code ec;
  fs::remove(out + "/index.json", ec);
  if (!dist.d.resume)
    for (const auto& f : fs::directory_iterator(out, ec))
      if (f.path().extension() == ".hwkf") fs::remove(f.path(), ec);
  std::vector<keyframe::KeyframeDbEntry> entries;
  Stopwatch sw;
  if (bench::distributed(dist.d)) {
    bench::ChunkPlan plan{"bake", work, chunks, bench::chunkCommand(argc, argv)};
    dist.d.progress = !quiet;
    if (auto st = bench::runChunks(plan, dist.d); !st) return fail(st.error().message);
    auto results = bench::readChunkResults(plan);
    if (!results) return fail(results.error().message);
    for (const json& r : *results) {
      auto es = keyframe::parseKeyframeEntries(r.contains("entries") ? r["entries"] : json(),
                                               work + " (chunk result)");
      if (!es) return fail(es.error().message);
      entries.insert(entries.end(), es->begin(), es->end());
    }
  } else {
    auto e = bench::bakeKeyframes(in->scene, in->path, keys, bo);
    if (!e) return fail(e.error().message);
    entries = std::move(*e);
  }
  if (auto st = bench::writeBakeIndex(out, prov, entries); !st) return fail(st.error().message);
  if (bench::distributed(dist.d)) bench::removeChunkDir(work);
  std::uint64_t bytes = 0;
  for (const auto& e : entries) bytes += e.bytes;
  std::printf("bake: %zu keyframes of %d frames (%s, %dx%d) in %.1f s, %.1f MB; database %s (index.json)\n",
              entries.size(), frames, c.scene.c_str(), in->path.width, in->path.height, sw.ms() / 1000.0,
              bytes / 1e6, out.c_str());
  return 0;
}

}  // namespace

int runMain(int argc, char** argv) {
  CLI::App app{
      "hybridwalk: real-time walkthroughs that mix geometry and images (Zheng, Bao, Peng & Sun "
      "1999).\nKeyframes are drawn with OpenGL (headless OSMesa); every frame between two "
      "keyframes is backward-warped from their level-of-detail quad meshes.\nUnits: distances "
      "are the scene's; tau is in z' units of the 24-bit depth buffer (2^24 scale, eq. 2; the "
      "paper uses 2^11 and 2^15); times in ms."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "hybridwalk 0.1");

  // walk
  Common walkC;
  std::string walkOut = "out/walk", tauS = "2^11", criterion = "five-point", compose = "overlay",
              texcoords = "projective", planarity = "stencil";
  bool mergeStrips = false;
  double tauPx = 0;
  bool noRef = false, saveFrames = false, quiet = false, noSky = false;
  std::string layers = "fused";
  bool noSkipBg = false, noSkipPrev = false;
  double nearDistance = 0;
  std::string subdivide = "none";
  std::string primitives = "indexed";
  bool cullBg = false;
  int subdivideCell = 16;
  int strips = 4;
  auto* walk = app.add_subcommand(
      "walk", "The main job: a hybrid walkthrough along a camera path, measured against the "
              "geometry renderer; writes report.json, strips and (optionally) frames");
  addCommon(walk, walkC);
  walk->add_option("--tau", tauS,
                   "LOD threshold on |Δ²z'| in z' units (2^24 scale); '2^11' or '2048' form")
      ->capture_default_str();
  walk->add_option("--tau-px", tauPx,
                   "Physical threshold instead of --tau: parallax error in pixels per scene unit "
                   "of camera motion (same meaning indoors and out); 0 = use --tau")
      ->check(CLI::NonNegativeNumber)
      ->excludes("--tau");
  walk->add_option("--criterion", criterion,
                   "Planarity test: five-point (paper's eq. 3) or per-axis-max (max(|Δ²x|,|Δ²y|))")
      ->check(CLI::IsMember({"five-point", "per-axis-max"}))
      ->capture_default_str();
  walk->add_option("--planarity", planarity,
                   "Planarity test: stencil (paper: Δ² stencils reach across region borders) or "
                   "region-local (second differences only inside the region; no one-pixel strips "
                   "along edges)")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  walk->add_flag("--merge-strips", mergeStrips,
                 "Merge adjacent coplanar leaves (within max(tau/4, 4) z' units) into larger quads");
  std::string tauGradS = "0";
  walk->add_option("--tau-gradient", tauGradS, tauGradientHelp())->capture_default_str();
  walk->add_option("--compose", compose,
                   "Composition: overlay (paper: nearer keyframe in front) or depth-merge "
                   "(per-pixel nearer of the two layers)")
      ->check(CLI::IsMember({"overlay", "depth-merge"}))
      ->capture_default_str();
  walk->add_option("--texcoords", texcoords,
                   "Warp texture mapping: projective (exact for planar quads) or affine "
                   "(plain perspective-correct s,t; for comparison)")
      ->check(CLI::IsMember({"projective", "affine"}))
      ->capture_default_str();
  walk->add_flag("--no-sky-backdrop", noSky,
                 "Do not draw empty keyframe pixels (sky) as a backdrop at infinity; they then "
                 "count as holes, as in the paper");
  walk->add_option("--layers", layers,
                   "How the two warped layers are composed (overlay rule): fused (one render "
                   "target, background drawn only where the foreground left pixels empty, one "
                   "readback) or separate (the paper's two layers read back and composed on the "
                   "CPU). Depth-merge always uses separate")
      ->check(CLI::IsMember({"fused", "separate"}))
      ->capture_default_str();
  walk->add_flag("--no-skip-background", noSkipBg,
                 "Draw the background layer even when the foreground covers every pixel "
                 "(default: a coverage test skips it; the frame is identical)");
  walk->add_flag("--no-skip-previous", noSkipPrev,
                 "Run the previous-frame fill even when the layers leave no holes");
  walk->add_option("--near", nearDistance,
                   "Draw objects near the viewpoint directly (paper §3): meshes whose bounds come "
                   "within this distance (scene units, e.g. metres) of a keyframe's eye are left "
                   "out of that keyframe and rendered as geometry into the frames that use it; "
                   "0 = off")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  walk->add_option("--subdivide", subdivide,
                   "Cut large quads into cells at upload (paper §2.1): none, uniform (every quad, "
                   "the paper's), adaptive (only quads whose corner depths differ by 1.5x or whose "
                   "pixels leave their plane by > 0.2 %); interior cell corners follow the "
                   "keyframe depth")
      ->check(CLI::IsMember({"none", "uniform", "adaptive"}))
      ->capture_default_str();
  walk->add_option("--primitives", primitives,
                   "How quads are drawn (same pixels, different vertex work): independent (6 "
                   "vertices per quad), indexed (4 vertices + 6 indices), shared (indexed, corners "
                   "identical between neighbouring quads stored once), points (indexed, 1x1 "
                   "leaves as one GL point each, sized to their footprint; not pixel-identical)")
      ->check(CLI::IsMember({"independent", "indexed", "shared", "points"}))
      ->capture_default_str();
  walk->add_flag("--cull-background", cullBg,
                 "Leave out background quads whose surfaces the foreground keyframe sees (they "
                 "mostly land under foreground pixels; lossy: cracks along edges then come from "
                 "the previous frame). Needs --primitives indexed or shared");
  walk->add_option("--subdivide-cell", subdivideCell, "Cell size for --subdivide, keyframe pixels")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  walk->add_flag("--no-reference", noRef,
                 "Skip the geometry reference render (no PSNR/SSIM; faster)");
  walk->add_flag("--save-frames", saveFrames, "Write every frame and hole mask as PNG");
  walk->add_option("--strips", strips,
                   "Number of reference|hybrid|diff×4|holes strips to write")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  walk->add_option("--out", walkOut, "Output directory")->capture_default_str();
  walk->add_flag("--quiet", quiet, "No progress line");
  std::string walkKeyframes;
  walk->add_option("--keyframes", walkKeyframes,
                   "Read keyframes and quad meshes from this database (written by 'hybridwalk bake' "
                   "with the same scene, path, --frames, --depth and LOD options) instead of rendering "
                   "them; the next keyframe is read ahead on a background thread");
  std::string schedule = "fixed", walkPredictor = "holes+distance", walkPlanBy = "worst";
  keyframe::PlannerOptions walkPlan;
  walk->add_option("--schedule", schedule,
                   "Keyframes: fixed (every keyframe_every frames of the path) or adaptive "
                   "(error-driven: planned ahead along the path, a new keyframe where the "
                   "predictor says an in-between frame would fall below --target-psnr)")
      ->check(CLI::IsMember({"fixed", "adaptive"}))
      ->capture_default_str();
  std::string walkTarget = "24", walkCalibrate, walkUncertainty = "auto";
  walk->add_option("--target-psnr", walkTarget,
                   "Adaptive schedule: the in-between PSNR to reach, dB, as --plan-by says (predicted; "
                   "the predictor's default fit comes from the built-in indoor scene at 512x512, so "
                   "on other scenes the dB are only ordered, unless --calibrate-spacing refits it "
                   "here), or fixed:G = the measured median of the calibration walk with keyframes "
                   "every G frames (G is added to --calibrate-spacing)")
      ->capture_default_str();
  walk->add_option("--calibrate-spacing", walkCalibrate,
                   "Adaptive schedule: first walk the path with keyframes every G frames (a "
                   "comma-separated list, e.g. 20 or 10,20; each a full walk with reference "
                   "frames, no output), refit the predictor to their measured in-between PSNRs, "
                   "and plan with that fit: the target is then in measured dB of this scene, "
                   "path and resolution. Writes calibration.csv and calibration.png. Empty = the "
                   "default fit")
      ->capture_default_str();
  walk->add_option("--plan-uncertainty", walkUncertainty,
                   "Adaptive schedule, --plan-by walk-median: the predictor's error model; each "
                   "in-between frame counts as its probability of reaching the target instead of "
                   "0 or 1. empirical = the calibration frames' residuals (measured - predicted) "
                   "as the error distribution; normal = a normal error with their standard "
                   "deviation; a number = a normal error of that standard deviation, dB (0 = the "
                   "plain count); auto = empirical with --calibrate-spacing, else 0")
      ->capture_default_str();
  double walkCalWindow = 0;
  walk->add_option("--calibration-window", walkCalWindow,
                   "Adaptive schedule with --calibrate-spacing: also correct each frame's "
                   "prediction by the calibration residuals near it along the path (a Gaussian "
                   "of this many frames standard deviation, shrunk toward 0 by 2 samples' "
                   "weight; the error model then takes the residuals left, each calibration "
                   "segment's computed without its own samples), frames; 0 = off")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  int walkVerifyRounds = 0;
  walk->add_option("--verify-rounds", walkVerifyRounds,
                   "Adaptive schedule, --plan-by walk-median, with a calibration: measure what the "
                   "plan picks. Each round walks the planned segments not measured yet (at this "
                   "resolution, with reference frames, no output), counts their frames exactly, "
                   "corrects the predictions near them (--calibration-window) and plans again, "
                   "aiming one keyframe below the best schedule whose median measured frames "
                   "alone guarantee; it stops when the plan is all measured, needs no fewer "
                   "keyframes, or the rounds run out. The walk runs that guaranteed schedule "
                   "(its median is at least the target); verify.png shows the rounds. Rounds, "
                   "0 = off")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  double walkVerifyOptimism = 1.0;
  walk->add_option("--verify-optimism", walkVerifyOptimism,
                   "With --verify-rounds: added to the unmeasured frames' predictions while "
                   "searching, dB, so segments that may beat their prediction get measured too; "
                   "costs measuring rounds, never the target (the schedule walked is guaranteed by "
                   "measured frames). 1 dB reached the fewest keyframes on all four 512x512 paths "
                   "measured, 0.5 dB on two (docs/results/2026-12-02/verified_plan)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  addPlannerOptions(walk, walkPlan, walkPredictor, walkPlanBy, false);
  bool asyncKeyframes = false;
  double keyframeCacheMb = 256;
  int keyframePrefetch = 2;
  walk->add_flag("--async-keyframes", asyncKeyframes,
                 "Render and mesh keyframes ahead of need on a worker thread with a second "
                 "OSMesa context (frames are identical; only their timing changes)");
  walk->add_option("--keyframe-cache-mb", keyframeCacheMb,
                   "Memory bound of the keyframe cache in MiB (colour + depth + quad mesh; the "
                   "two keyframes of the current bracket are always kept)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  walk->add_option("--keyframe-prefetch", keyframePrefetch,
                   "With --async-keyframes: keyframes past the current pair built ahead")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  std::size_t keyframeFlushTriangles = 8192;
  int keyframeWorkerNice = 0;
  walk->add_option("--keyframe-flush-triangles", keyframeFlushTriangles,
                   "With --async-keyframes: the worker flushes its keyframe render after about "
                   "this many triangles, so frames on the main context wait behind one piece of "
                   "it on llvmpipe's shared rasteriser threads (0 = one flush)")
      ->capture_default_str();
  int keyframeStepsPerFrame = 2;
  std::string keyframePacing = "time";
  double keyframeBudgetScale = 2.0;
  walk->add_option("--keyframe-pacing", keyframePacing,
                   "With --async-keyframes: how the worker spreads a keyframe over the frames "
                   "before its need: time (each frame allows budget-scale x last build ms / frames "
                   "per keyframe of worker time, alongside the frame), slices (the same budget, "
                   "run at the end of each frame while the frame waits: the two never share the "
                   "CPUs; counted in the frame's time), steps (--keyframe-steps-per-frame steps "
                   "per frame) or none (as fast as it can); lifted while a frame waits")
      ->check(CLI::IsMember({"time", "slices", "steps", "none"}))
      ->capture_default_str();
  walk->add_option("--keyframe-budget-scale", keyframeBudgetScale,
                   "With --keyframe-pacing time or slices: the worker's time per frame as a multiple of its "
                   "even share (> 1 lets it get ahead)")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  walk->add_option("--keyframe-steps-per-frame", keyframeStepsPerFrame,
                   "With --keyframe-pacing steps: worker steps (a flushed piece of the render, the "
                   "readback, a mesh-build step) per frame")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  walk->add_option("--keyframe-worker-nice", keyframeWorkerNice,
                   "With --async-keyframes: nice increment of the worker thread (0-19)")
      ->check(CLI::Range(0, 19))
      ->capture_default_str();
  FrameBudgetCli fb;
  int staleAfter = 2;
  bool noFramePacing = false, pixelAge = false;
  addFrameBudgetOptions(walk, fb,
                        "with time left after an in-between frame is composed, the region of "
                        "pixels carried over from earlier frames longest is re-rendered by the "
                        "geometry renderer if its estimated cost fits, and frames are presented "
                        "every this many ms");
  walk->add_option("--stale-after", staleAfter,
                   "With --frame-budget-ms: frames a pixel must have been carried over from the "
                   "previous frame before it counts for a refresh (at least 1)")
      ->check(wholeFrames(1, 255, "stale after"))
      ->capture_default_str();
  walk->add_flag("--no-frame-pacing", noFramePacing,
                 "With --frame-budget-ms: refresh within the budget but do not wait for it to "
                 "pass before the next frame");
  walk->add_flag("--pixel-age", pixelAge,
                 "Track and report per-pixel age (frames carried over from the previous frame) "
                 "without a budget (always on with --frame-budget-ms); frames are identical");

  // render
  Common renderC;
  std::string renderOut = "out/render";
  auto* render = app.add_subcommand(
      "render", "Geometry renderer only: each frame of the path as PNG, plus render.json "
                "with per-frame times and the scene's triangle count");
  addCommon(render, renderC);
  render->add_option("--out", renderOut, "Output directory")->capture_default_str();

  // lod
  Common lodC;
  std::string lodOut = "overlay.png", lodTau = "2^11", lodCriterion = "five-point";
  int lodFrame = 0;
  auto* lod = app.add_subcommand(
      "lod", "Build one keyframe's quad mesh and draw its leaves over it (paper Plate I-A); "
             "writes OUT (PNG) and OUT with .json (stats)");
  addCommon(lod, lodC);
  lod->add_option("--frame", lodFrame, "Frame index on the path to use as the keyframe")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  lod->add_option("--tau", lodTau, "LOD threshold in z' units ('2^11' or '2048')")
      ->capture_default_str();
  lod->add_option("--criterion", lodCriterion, "five-point or per-axis-max")
      ->check(CLI::IsMember({"five-point", "per-axis-max"}))
      ->capture_default_str();
  std::string lodPlanarity = "stencil";
  bool lodMerge = false;
  lod->add_option("--planarity", lodPlanarity, "stencil (paper) or region-local")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  lod->add_flag("--merge-strips", lodMerge, "Merge adjacent coplanar leaves");
  std::string lodTauGradS = "0";
  lod->add_option("--tau-gradient", lodTauGradS, tauGradientHelp())->capture_default_str();
  lod->add_option("--out", lodOut, "Overlay PNG path")->capture_default_str();

  // sweep
  Common sweepC;
  std::string sweepOut = "out/sweep", sweepTaus;
  bool sweepOneCriterion = false, sweepNoBaselines = false, sweepQuiet = false;
  int sweepOverlayFrame = -1;
  auto* sweep = app.add_subcommand(
      "sweep", "Run time against error: the walk for tau = 2^6 .. 2^16 (or --tau), both "
               "criteria, and baselines at matched quad count (uniform tiles, one quad per "
               "pixel); writes sweep.json, sweep.csv, plots, overlays and index.html");
  addCommon(sweep, sweepC);
  sweep->add_option("--tau", sweepTaus,
                    "Comma-separated thresholds in z' units, e.g. '2^8,2^11,2^15' (default "
                    "2^6..2^16)");
  sweep->add_flag("--five-point-only", sweepOneCriterion, "Skip the per-axis-max criterion");
  sweep->add_flag("--no-baselines", sweepNoBaselines, "Skip uniform tiles and per-pixel meshes");
  bool sweepNoVariants = false;
  sweep->add_flag("--no-variants", sweepNoVariants,
                  "Skip the edge-strip variants (region-local planarity, strip merging)");
  std::string sweepTauGradS = "0";
  sweep->add_option("--tau-gradient", sweepTauGradS,
                    "Adds the gradient-tolerance variant (five-point, region-local+merge, "
                    "--tau-gradient A) per tau; 0 = not run. " + tauGradientHelp())
      ->capture_default_str();
  sweep->add_option("--overlay-frame", sweepOverlayFrame,
                    "Frame whose quad mesh is drawn per tau (default -1: the middle keyframe)")
      ->check(CLI::Range(-1, 1 << 30));
  sweep->add_option("--out", sweepOut, "Output directory")->capture_default_str();
  sweep->add_flag("--quiet", sweepQuiet, "No progress line");
  int sweepPerTask = 4;
  DistributeCli sweepDist;
  sweep->add_option("--cells-per-task", sweepPerTask,
                    "Sweep cells (walks) per chunk (--slurm array task or --workers process)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  addDistribute(sweep, sweepDist, "--cells-per-task cells");

  // bake
  Common bakeC;
  std::string bakeOut, bakeTau = "2^11", bakeCriterion = "five-point", bakePlanarity = "stencil";
  double bakeTauPx = 0;
  bool bakeMerge = false, bakeQuiet = false;
  int bakePerTask = 8;
  DistributeCli bakeDist;
  auto* bakeCmd = app.add_subcommand(
      "bake", "Render and mesh every keyframe of a path ahead of time into a keyframe database "
              "(one checksummed file per keyframe + index.json, docs/keyframe-db.md) for "
              "'walk --keyframes DB'; --slurm runs it as a Slurm job array");
  addCommon(bakeCmd, bakeC);
  bakeCmd->add_option("--out", bakeOut, "Database directory (created)")->required();
  bakeCmd->add_option("--tau", bakeTau, "LOD threshold in z' units, as for walk")->capture_default_str();
  bakeCmd->add_option("--tau-px", bakeTauPx, "Parallax threshold in pixels per scene unit, as for walk")
      ->check(CLI::NonNegativeNumber)
      ->excludes("--tau");
  bakeCmd->add_option("--criterion", bakeCriterion, "five-point or per-axis-max, as for walk")
      ->check(CLI::IsMember({"five-point", "per-axis-max"}))
      ->capture_default_str();
  bakeCmd->add_option("--planarity", bakePlanarity, "stencil or region-local, as for walk")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  bakeCmd->add_flag("--merge-strips", bakeMerge, "Merge adjacent coplanar leaves, as for walk");
  std::string bakeTauGradS = "0";
  bakeCmd->add_option("--tau-gradient", bakeTauGradS, tauGradientHelp() + "; as for walk")
      ->capture_default_str();
  bakeCmd->add_option("--keyframes-per-task", bakePerTask,
                      "Keyframes per chunk (--slurm array task or --workers process)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  bakeCmd->add_flag("--quiet", bakeQuiet, "No progress line");
  addDistribute(bakeCmd, bakeDist, "--keyframes-per-task keyframes");

  // bench
  std::string benchOut = "out/bench", benchSizes;
  bool benchQuick = false, benchQuiet = false;
  std::vector<std::string> benchOnly;
  auto* benchCmd = app.add_subcommand(
      "bench", "Frame-timing benchmark: geometry vs in-between ms over scene sizes 100k..4M "
               "triangles (tau 2^11, 2^15), a walkthrough trace with per-stage ms, PSNR vs "
               "keyframe spacing, and each skip on and off; writes bench.json, CSVs, plots and "
               "index.html");
  benchCmd->add_option("--out", benchOut, "Output directory")->capture_default_str();
  benchCmd->add_option("--sizes", benchSizes,
                       "Comma-separated triangle counts for the complexity part (k/M suffixes), "
                       "default 100k,300k,1M,2M,4M");
  benchCmd->add_flag("--quick", benchQuick,
                     "Small version: sizes 100k,300k, fewer frames, trace at 100k, 3 spacings, skips on indoor only (11 frames)");
  benchCmd->add_flag("--quiet", benchQuiet, "No progress lines");
  benchCmd->add_option("--only", benchOnly,
                       "Run only these parts (comma-separated): complexity, trace, spacing, skips "
                       "(skips = issue #8's table: each skip on and off, and --subdivide none, "
                       "uniform, adaptive with PSNR also over the pixels of leaves larger than a "
                       "cell, on indoor, outdoor, q3:oa_dm5 and torcs:forza; real scenes need "
                       "'scenes fetch --outdoor')")
      ->delimiter(',')
      ->check(CLI::IsMember({"complexity", "trace", "spacing", "skips"}));

  // export-keyframes
  Common exportC;
  std::string exportOut = "out/keyframes";
  bool exportNoInBetween = false, exportQuiet = false;
  auto* exportCmd = app.add_subcommand(
      "export-keyframes",
      "Write the path's keyframes for other view-synthesis tools: NAME.png (RGB), "
      "NAME.depth.pfm (float32 eye-space depth along the view direction, 0 = nothing drawn) and "
      "cameras.json (fx, fy, cx, cy in pixels with pixel centres at +0.5, near, far, "
      "world_from_camera 4x4 row-major in OpenCV axes: x right, y down, z forward); also the "
      "in-between cameras and their reference images");
  addCommon(exportCmd, exportC);
  exportCmd->add_flag("--no-in-between", exportNoInBetween, "Keyframes only");
  exportCmd->add_option("--out", exportOut, "Output directory")->capture_default_str();
  exportCmd->add_flag("--quiet", exportQuiet, "No progress line");

  // view
  Common viewC;
  app::ViewerOptions vo;
  std::string viewTau = "2^11";
  std::string viewKeyframes;
  bool viewGeometry = false, viewNoHud = false;
  auto* viewCmd = app.add_subcommand(
      "view", "Interactive viewer (GLFW window; needs a display, e.g. xvfb-run): fly with the "
              "right mouse button held + W/A/S/D/Q/E (Shift x4, +/- speed), g hybrid/geometry, "
              "w wireframe/quad outlines, s statistics, o overlay, m hole mask, p PSNR, c "
              "screenshot, z/Z record/play path, space home, h help, Esc quit");
  viewCmd->add_option("--scene", viewC.scene, "Scene, as for walk")->capture_default_str();
  viewCmd->add_option("--path", viewC.path, "Camera path JSON to play (default: the scene's own)");
  viewCmd->add_option("--tau", viewTau, "LOD threshold in z' units ('2^11' or '2048')")
      ->capture_default_str();
  std::string viewTauGradS = "0";
  viewCmd->add_option("--tau-gradient", viewTauGradS, tauGradientHelp())->capture_default_str();
  viewCmd->add_option("--width", vo.width, "Window width, pixels")->check(CLI::Range(16, 8192))
      ->capture_default_str();
  viewCmd->add_option("--height", vo.height, "Window height, pixels")->check(CLI::Range(16, 8192))
      ->capture_default_str();
  viewCmd->add_flag("--play", vo.play, "Replay the camera path (--path, or the scene's default)");
  viewCmd->add_option("--exit-after", vo.exitAfterFrames,
                      "Quit after this many frames (scripted runs; 0 = when closed)")
      ->check(CLI::NonNegativeNumber);
  viewCmd->add_option("--screenshot", vo.screenshotPath, "Write the last frame to this PNG on exit");
  viewCmd->add_option("--record", vo.recordPath, "Camera path file for z (record) / Z (play)");
  viewCmd->add_option("--keys", vo.keys, "Keys typed before the first frame, e.g. 'so'");
  viewCmd->add_flag("--geometry", viewGeometry, "Start in geometry mode instead of hybrid");
  viewCmd->add_flag("--no-hud", viewNoHud, "No on-screen text");
  viewCmd->add_option("--keyframes", viewKeyframes,
                      "Warp keyframes baked by 'hybridwalk bake' from this scene and path instead of "
                      "rendering them while near the baked path (with --play, exactly the walk's "
                      "keyframe pairs); the window takes the database's size");
  std::string viewPacing = "time";
  viewCmd->add_flag("--async-keyframes", vo.asyncKeyframes,
                    "Render and mesh keyframes ahead on a worker thread with a second OpenGL "
                    "context (a hidden window): the viewer requests the next keyframe and warps "
                    "the ones it has until it is ready instead of rendering it in the frame "
                    "(keyframes are identical; when one arrives changes). Lost (no keyframe "
                    "within reach) it waits for the one in flight if that is within reach, else "
                    "renders one in the frame; baked --keyframes are read as without it. "
                    "With s s, the statistics show keyframe stalls and waits");
  viewCmd->add_option("--keyframe-pacing", viewPacing,
                      "With --async-keyframes, as for walk: time (per frame the worker may take "
                      "budget-scale x last build ms / F of wall time, F = the frames the "
                      "viewer takes per keyframe: measured from its requests, at most the frames "
                      "until it would be lost, starting from keyframe_every / 2 of the path), "
                      "slices (the same budget, run after each frame is shown, counted in its "
                      "time), steps (--keyframe-steps-per-frame steps per frame) or none (as fast "
                      "as it can)")
      ->check(CLI::IsMember({"time", "slices", "steps", "none"}))
      ->capture_default_str();
  viewCmd->add_option("--keyframe-budget-scale", vo.keyframeBudgetScale,
                      "With --keyframe-pacing time or slices: the worker's time per frame as a "
                      "multiple of its even share (> 1 lets it get ahead)")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  viewCmd->add_option("--keyframe-steps-per-frame", vo.keyframeStepsPerFrame,
                      "With --keyframe-pacing steps: worker steps (a flushed piece of the render, "
                      "the readback, a mesh-build step) per frame")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  viewCmd->add_option("--keyframe-flush-triangles", vo.keyframeFlushTriangles,
                      "With --async-keyframes: the worker flushes its keyframe render after about "
                      "this many triangles (0 = one flush)")
      ->capture_default_str();
  FrameBudgetCli viewFb;
  addFrameBudgetOptions(viewCmd, viewFb,
                        "after a frame is shown the viewer waits until this many ms have passed "
                        "since it started, so frames are presented at a steady cadence (pacing "
                        "only: the viewer does not refresh stale pixels)");
  viewCmd->add_option("--frame-stats", vo.frameStatsPath,
                      "Write one CSV row per frame at exit: ms (time since the previous frame "
                      "ended), keyframe ms and events (rendered in the frame = a stall, read, "
                      "taken from the worker, requested, waited for); the exit also prints the "
                      "frame ms median / p95 / max");

  // compare
  std::string cmpA, cmpB, cmpDiff;
  auto* cmpCmd = app.add_subcommand(
      "compare", "Compare two PNG images of the same size (e.g. a viewer screenshot and a walk "
                 "frame): PSNR (dB, RGB), SSIM, pixels that differ, largest channel difference");
  cmpCmd->add_option("a", cmpA, "First PNG")->required();
  cmpCmd->add_option("b", cmpB, "Second PNG")->required();
  cmpCmd->add_option("--diff", cmpDiff, "Write |a - b| x4 per channel to this PNG");

  // stress
  std::string stressOut = "out/stress";
  bool stressQuick = false, stressQuiet = false;
  auto* stressCmd = app.add_subcommand(
      "stress", "Numerical stability: depth precision of the three depth modes over far/near "
                "ratios 10..1e6 and view angles 0..85 deg (Δ² noise, quads, corner and world "
                "errors, PSNR), and degenerate/extreme cameras; writes stress.json, CSVs, plots, "
                "index.html; exit 1 if a degenerate case fails");
  stressCmd->add_option("--out", stressOut, "Output directory")->capture_default_str();
  stressCmd->add_flag("--quick", stressQuick, "Smaller images and fewer cases");
  stressCmd->add_flag("--quiet", stressQuiet, "No progress line");

  // schedule-study
  Common studyC;
  std::string studyOut = "out/schedule", studySpacings = "4,6,8,10,15,20", studyTargets,
              studyPredictor = "auto", studyPlanBy = "worst";
  StudyLod studyLod;
  bool studyQuiet = false;
  int studyRef = 10;
  keyframe::PlannerOptions studyPlan;
  auto* studyCmd = app.add_subcommand(
      "schedule-study",
      "Fixed vs error-driven keyframe schedules: the walk with a keyframe every N frames, the "
      "predictors' correlation with its measured PSNR, then planned schedules at several "
      "target PSNRs; keyframes per 100 frames vs median/p5 in-between PSNR. Writes "
      "schedule.json, runs.csv, correlation.csv, schedule.png, predictor.png, index.html");
  addCommon(studyCmd, studyC);
  addStudyLodOptions(studyCmd, studyLod);
  studyCmd->add_option("--spacings", studySpacings, "Fixed schedules: keyframe_every values, frames")
      ->capture_default_str();
  studyCmd->add_option("--reference-spacing", studyRef,
                       "Fixed spacing the headline compares with, frames")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  studyCmd->add_option("--targets", studyTargets,
                       "Target PSNRs of the adaptive runs, dB, comma-separated (default: per fixed "
                       "spacing, the target whose plan has as many keyframes)");
  addPlannerOptions(studyCmd, studyPlan, studyPredictor, studyPlanBy, true);
  studyCmd->add_option("--out", studyOut, "Output directory")->capture_default_str();
  studyCmd->add_flag("--quiet", studyQuiet, "No progress lines");

  // schedule-oracle
  Common oracleC;
  std::string oracleOut = "out/schedule-oracle", oracleSpacings = "4,6,8,10,15,20";
  StudyLod oracleLod;
  bool oracleQuiet = false;
  int oracleRef = 10, oracleMaxGap = 20, oracleWidth = 0, oracleHeight = 0;
  auto* oracleCmd = app.add_subcommand(
      "schedule-oracle",
      "The best any keyframe schedule can do on a path: measures the PSNR of every in-between "
      "frame for every keyframe pair up to --max-gap frames apart (--max-gap*(--max-gap+1)/2-1 "
      "walks), then finds by dynamic programming the fewest keyframes whose median in-between "
      "PSNR reaches each fixed schedule's. The bound for issue #8's error-driven schedule. "
      "Writes oracle.json, oracle.csv, oracle.png, segments.csv (the measured table, for "
      "--table) and features.csv (the planner's probe features of every entry)");
  addCommon(oracleCmd, oracleC);
  addStudyLodOptions(oracleCmd, oracleLod);
  oracleCmd->add_option("--max-gap", oracleMaxGap,
                        "Longest gap between keyframes considered, frames (cost grows with its square)")
      ->check(CLI::Range(2, 60))
      ->capture_default_str();
  oracleCmd->add_option("--spacings", oracleSpacings,
                        "Fixed schedules compared: keyframe_every values, frames, each <= --max-gap")
      ->capture_default_str();
  oracleCmd->add_option("--reference-spacing", oracleRef,
                        "Fixed spacing the headline compares with, frames (one of --spacings)")
      ->check(CLI::Range(1, 60))
      ->capture_default_str();
  oracleCmd->add_option("--width", oracleWidth, "Frame width, pixels (0 = the path's)")
      ->check(CLI::Range(0, 8192))
      ->capture_default_str();
  oracleCmd->add_option("--height", oracleHeight, "Frame height, pixels (0 = the path's)")
      ->check(CLI::Range(0, 8192))
      ->capture_default_str();
  std::string oracleTable;
  bool oracleNoPlanner = false;
  oracleCmd->add_option("--table", oracleTable,
                        "Score from an earlier run's segments.csv instead of walking (same scene, "
                        "path, size, --frames, --max-gap and LOD options)");
  oracleCmd->add_flag("--no-planner", oracleNoPlanner,
                      "Do not score the error-driven planner (targets 18..40 dB predicted, "
                      "worst-frame and segment-median criteria) on the table");
  bench::ScheduleOracleOptions oracleDefaults;
  int oracleProbePsnrSize = oracleDefaults.probePsnrSize;
  keyframe::ProbeErrorOptions oracleProbeError = oracleDefaults.probeError;
  bool oracleProbePsnrOnly = false;
  oracleCmd->add_option("--probe-psnr-size", oracleProbePsnrSize,
                        "Also score the probe predictors (probe-psnr, probe-psnr+distance) with "
                        "probes of this size, pixels on the longer side (0 = not scored); writes "
                        "probe_error.csv")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  oracleCmd->add_flag("--probe-psnr-only", oracleProbePsnrOnly,
                      "Score only the probe predictors (not the default predictor's curves or "
                      "features.csv)");
  oracleCmd->add_option("--probe-hole-mse", oracleProbeError.holeMse,
                        "Probe predictors with --probe-no-previous-fill: squared error charged per "
                        "hole pixel of the warped probe, (0-255)^2 units")
      ->check(CLI::Range(0.0, 65025.0))
      ->capture_default_str();
  oracleCmd->add_option("--probe-blur", oracleProbeError.blurRadius,
                        "Probe predictors: box-blur radius of the compared probes, probe pixels (0 = none)")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  oracleCmd->add_option("--probe-tolerance", oracleProbeError.shiftTolerance,
                        "Probe predictors without blur: compare each warped pixel with the best "
                        "reference pixel within this many probe pixels (0 = the same pixel)")
      ->check(CLI::Range(0, 4))
      ->capture_default_str();
  bool oracleNoPreviousFill = false;
  oracleCmd->add_flag("--probe-no-previous-fill", oracleNoPreviousFill,
                      "Probe predictors: charge --probe-hole-mse per hole of the warped probe "
                      "instead of filling it from the previous frame's, as the walk does");
  oracleCmd->add_option("--probe-supersample", oracleProbeError.supersample,
                        "Probe predictors: render probes at this many times their size and "
                        "box-filter down (1 = off)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  oracleCmd->add_option("--out", oracleOut, "Output directory")->capture_default_str();
  oracleCmd->add_flag("--quiet", oracleQuiet, "No progress line");

  // scenes fetch | list
  auto* scenesCmd = app.add_subcommand("scenes", "Real scenes from Debian packages");
  scenesCmd->require_subcommand(1);
  std::string cacheDir = scenes::defaultSceneCacheDir();
  bool fetchQuiet = false;
  auto* fetchCmd = scenesCmd->add_subcommand(
      "fetch", "Download the OpenArena map, texture and data packages with apt-get download and "
               "unpack them into the cache (nothing is installed system-wide; idempotent). Maps "
               "are then named q3:MAPNAME");
  fetchCmd->add_option("--dir", cacheDir, "Cache directory ($HYBRIDWALK_CACHE overrides the default)")
      ->capture_default_str();
  fetchCmd->add_flag("--quiet", fetchQuiet, "No progress");
  bool fetchOutdoor = false;
  fetchCmd->add_flag("--outdoor", fetchOutdoor,
                     "Also the outdoor scenes: torcs-data (TORCS tracks, torcs:NAME, 333 MB) and "
                     "morse-simulator-data (MORSE environments, morse:ENV/FILE, 82 MB)");
  auto* listCmd = scenesCmd->add_subcommand("list", "List the built-in scenes and the q3: maps in the cache");
  listCmd->add_option("--dir", cacheDir, "Cache directory")->capture_default_str();

  // CLI11 only says "A subcommand is required" for a misspelt command; name it.
  auto checkCommand = [&](CLI::App* parent, int argi) -> bool {
    if (argi >= argc || argv[argi][0] == '-') return true;
    std::string names;
    for (const CLI::App* sub : parent->get_subcommands({})) {
      if (sub->get_name() == argv[argi]) return true;
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    std::fprintf(stderr, "hybridwalk: error: unknown command '%s' (expected one of: %s; see --help)\n",
                 argv[argi], names.c_str());
    return false;
  };
  if (!checkCommand(&app, 1)) return kExitUsage;
  if (argc > 1 && std::string(argv[1]) == "scenes" && !checkCommand(scenesCmd, 2)) return kExitUsage;

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitUsage;
  }
  if (const std::string err = app::checkParsedOptions(app); !err.empty()) {
    std::fprintf(stderr, "hybridwalk: error: %s\n", err.c_str());
    return kExitUsage;
  }

  if (render->parsed()) return runRender(renderC, renderOut);

  if (stressCmd->parsed()) {
    auto ctx = gl::createHeadlessContext();
    if (!ctx) return fail(ctx.error().message);
    bench::StressOptions so;
    so.outDir = stressOut;
    so.quick = stressQuick;
    so.progress = !stressQuiet;
    so.glRenderer = (*ctx)->renderer();
    so.glVersion = (*ctx)->version();
    auto res = bench::runStress(so);
    if (!res) return fail(res.error().message);
    const int failed = (*res)["cases_failed"].get<int>();
    std::printf("stress: %s; recommended default depth mode: %s; open %s/index.html\n",
                failed ? "SOME DEGENERATE CASES FAILED" : "all degenerate cases passed",
                (*res)["recommended_default"].dump().c_str(), stressOut.c_str());
    if (failed) return fail(std::to_string(failed) + " degenerate-camera cases failed (see cases.csv)");
    return 0;
  }

  if (fetchCmd->parsed()) {
    if (auto st = scenes::fetchScenePackages(cacheDir, !fetchQuiet, fetchOutdoor); !st)
      return fail(st.error().message);
    auto maps = scenes::listQ3Maps(scenes::defaultPk3Paths(cacheDir));
    if (!maps) return fail(maps.error().message);
    std::printf("scenes: %zu OpenArena maps in %s; use --scene q3:MAPNAME (e.g. q3:oa_dm5)\n",
                maps->size(), cacheDir.c_str());
    return 0;
  }
  if (listCmd->parsed()) {
    std::printf("built-in: indoor, outdoor (append :N for ~N triangles, e.g. indoor:1M)\n");
    const auto pk3s = scenes::defaultPk3Paths(cacheDir);
    if (pk3s.empty()) {
      std::printf("no pk3 files in %s: run 'hybridwalk scenes fetch' for the OpenArena maps\n",
                  cacheDir.c_str());
      return 0;
    }
    auto maps = scenes::listQ3Maps(pk3s);
    if (!maps) return fail(maps.error().message);
    for (const auto& m : *maps) std::printf("q3:%s\n", m.c_str());
    return 0;
  }

  if (viewCmd->parsed()) {
    if (!parseTau(viewTau, &vo.tau))
      return fail("--tau: expected a non-negative number like 2048 or 2^11, got '" + viewTau + "'");
    if (std::string err; !parseTauGradient(viewTauGradS, &vo.tauGradient, &err)) return fail(err);
    if (!viewC.path.empty()) {
      vo.playPath = viewC.path;
    }
    vo.sceneLabel = viewC.scene;
    using VP = app::ViewerOptions::KeyframePacing;
    vo.keyframePacing = viewPacing == "time"     ? VP::Time
                        : viewPacing == "slices" ? VP::Slices
                        : viewPacing == "steps"  ? VP::Steps
                                                 : VP::None;
    vo.frameBudgetMs = viewFb.ms();
    vo.frameBudgetAuto = viewFb.isAuto();
    vo.frameBudgetQuantile = viewFb.quantile;
    vo.frameBudgetWindow = viewFb.window;
    vo.startHybrid = !viewGeometry;
    vo.hud = !viewNoHud;
    auto s = scenes::loadScene(viewC.scene);
    if (!s) return fail(s.error().message);
    auto p = scenes::defaultPathFor(viewC.scene);
    if (!p) return fail(p.error().message);
    if (!viewKeyframes.empty()) {  // baked keyframes (docs/keyframe-db.md)
      auto db = keyframe::KeyframeDb::open(viewKeyframes);
      if (!db) return fail(db.error().message);
      scenes::CameraPath played = *p;
      if (!viewC.path.empty()) {
        auto pp = scenes::loadCameraPath(viewC.path);
        if (!pp) return fail(pp.error().message);
        played = std::move(*pp);
      }
      for (const char* opt : {"--width", "--height"}) {
        const int want = opt[2] == 'w' ? played.width : played.height;
        const int given = opt[2] == 'w' ? vo.width : vo.height;
        if (viewCmd->count(opt) > 0 && given != want)
          return fail(std::string(opt) + " " + std::to_string(given) + ": the database " +
                      viewKeyframes + " holds " + std::to_string(played.width) + "x" +
                      std::to_string(played.height) + " keyframes (omit " + opt +
                      " to take the database's size)");
      }
      vo.width = played.width;
      vo.height = played.height;
      // Scene, path and size must match; the LOD options, depth mode and frame
      // count are the database's own (they only decide what it holds).
      if (auto st = db->checkMatches(
              bench::bakeProvenance(viewC.scene, s->triangleCount(), played, played.frames, {},
                                    kDefaultDepthMode),
              {"scene", "triangles", "path_hash", "resolution"});
          !st)
        return fail(st.error().message);
      db->setExpectation({[p = played](int f) { return p.cameraAt(f); }, std::nullopt});
      vo.keyframeDb = std::make_shared<keyframe::KeyframeDb>(std::move(*db));
    }
    return app::runViewer(*s, *p, vo);
  }

  if (cmpCmd->parsed()) {
    if (!cmpDiff.empty())
      if (auto st = checkOutputPath(cmpDiff, "--diff"); !st) return fail(st.error().message);
    auto ia = readPng(cmpA, metricImageLimits());
    if (!ia) return fail(ia.error().message);
    auto ib = readPng(cmpB, metricImageLimits());
    if (!ib) return fail(ib.error().message);
    if (ia->width() != ib->width() || ia->height() != ib->height())
      return fail("compare: " + cmpA + " is " + std::to_string(ia->width()) + "x" +
                  std::to_string(ia->height()) + ", " + cmpB + " is " + std::to_string(ib->width()) +
                  "x" + std::to_string(ib->height()) + " (expected the same size)");
    long differing = 0;
    int maxDiff = 0;
    for (int y = 0; y < ia->height(); ++y)
      for (int x = 0; x < ia->width(); ++x) {
        const Rgba8 p = ia->at(x, y), q = ib->at(x, y);
        const int d = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
        differing += d > 0;
        maxDiff = std::max(maxDiff, d);
      }
    if (!cmpDiff.empty())
      if (auto st = writePng(cmpDiff, diffImage(*ia, *ib)); !st) return fail(st.error().message);
    std::printf("psnr_db %.2f ssim %.4f differing_pixels %ld of %ld max_channel_diff %d\n",
                psnrCapped(*ia, *ib), ssim(*ia, *ib), differing,
                static_cast<long>(ia->width()) * ia->height(), maxDiff);
    return 0;
  }

  if (exportCmd->parsed()) {
    auto in = loadInputs(exportC);
    if (!in) return fail(in.error().message);
    bench::ExportOptions eo;
    eo.inBetween = !exportNoInBetween;
    eo.maxFrames = exportC.frames;
    eo.progress = !exportQuiet;
    eo.depthMode = depthModeOf(exportC.depth);
    if (auto st = bench::exportKeyframes(in->scene, in->path, exportOut, eo); !st)
      return fail(st.error().message);
    std::printf("exported keyframes of %s to %s (cameras.json lists them)\n", exportC.scene.c_str(),
                exportOut.c_str());
    return 0;
  }

  if (bakeCmd->parsed()) {
    keyframe::LodOptions lo;
    if (!parseTau(bakeTau, &lo.tau))
      return fail("--tau: expected a non-negative number like 2048 or 2^11, got '" + bakeTau + "'");
    lo.tauParallaxPx = bakeTauPx;
    keyframe::parseDeltaCriterion(bakeCriterion.c_str(), &lo.criterion);
    keyframe::parsePlanarity(bakePlanarity.c_str(), &lo.planarity);
    lo.mergeStrips = bakeMerge;
    if (std::string err; !parseTauGradient(bakeTauGradS, &lo.tauGradient, &err)) return fail(err);
    return runBake(bakeC, lo, bakeOut, bakePerTask, bakeQuiet, bakeDist, argc, argv);
  }

  if (benchCmd->parsed()) {
    bench::BenchOptions bo;
    bo.outDir = benchOut;
    bo.progress = !benchQuiet;
    if (benchQuick) {
      bo.sizes = {100000, 300000};
      bo.keyframeSpacings = {5, 10, 20};
      bo.renderFrames = 6;
      bo.walkFrames = 21;
      bo.traceTriangles = 100000;
      bo.skips.frames = 11;
      bo.skips.scenes = {{"indoor", ""}};
    }
    bo.parts = benchOnly;
    if (!benchSizes.empty()) {
      bo.sizes.clear();
      std::size_t start = 0;
      while (start < benchSizes.size()) {
        std::size_t end = benchSizes.find(',', start);
        if (end == std::string::npos) end = benchSizes.size();
        std::string t = benchSizes.substr(start, end - start);
        double mul = 1;
        if (!t.empty() && (t.back() == 'k' || t.back() == 'K')) mul = 1e3, t.pop_back();
        else if (!t.empty() && (t.back() == 'm' || t.back() == 'M')) mul = 1e6, t.pop_back();
        double v = 0;
        if (!parseTau(t, &v) || v * mul < 1000 || v * mul > 5e7)
          return fail("--sizes: expected triangle counts between 1k and 50M like 100k,1M, got '" +
                      benchSizes.substr(start, end - start) + "'");
        bo.sizes.push_back(static_cast<std::size_t>(v * mul));
        start = end + 1;
      }
    }
    auto ctx = gl::createHeadlessContext();
    if (!ctx) return fail(ctx.error().message);
    bo.glRenderer = (*ctx)->renderer();
    bo.glVersion = (*ctx)->version();
    auto res = bench::runBenchSuite(bo);
    if (!res) return fail(res.error().message);
    std::printf("bench: done in %.0f s; open %s/index.html; data in bench.json and CSVs\n",
                (*res)["elapsed_s"].get<double>(), benchOut.c_str());
    return 0;
  }

  if (sweep->parsed()) {
    bench::SweepOptions so;
    std::size_t start = 0;
    while (start < sweepTaus.size()) {
      std::size_t end = sweepTaus.find(',', start);
      if (end == std::string::npos) end = sweepTaus.size();
      const std::string t = sweepTaus.substr(start, end - start);
      double v = 0;
      if (!parseTau(t, &v))
        return fail("--tau: expected comma-separated non-negative numbers like 2^11,2^15, got '" + t + "'");
      so.taus.push_back(v);
      start = end + 1;
    }
    so.bothCriteria = !sweepOneCriterion;
    so.baselines = !sweepNoBaselines;
    so.variants = !sweepNoVariants;
    if (std::string err; !parseTauGradient(sweepTauGradS, &so.tauGradient, &err)) return fail(err);
    so.maxFrames = sweepC.frames;
    so.depthMode = depthModeOf(sweepC.depth);
    so.overlayFrame = sweepOverlayFrame;
    so.outDir = sweepOut;
    so.progress = !sweepQuiet;
    auto in = loadInputs(sweepC);
    if (!in) return fail(in.error().message);
    so.glRenderer = in->context->renderer();
    so.glVersion = in->context->version();
    auto cells = bench::sweepCellCount(in->path, so);
    if (!cells) return fail(cells.error().message);
    const int chunks = (*cells + sweepPerTask - 1) / sweepPerTask;
    const std::string work = sweepOut + "/.chunks";
    if (sweepDist.chunk >= 0) {  // one chunk: its cells' rows to WORK/chunk-I.json
      if (sweepDist.chunk >= chunks)
        return fail("--chunk: " + std::to_string(sweepDist.chunk) + " out of range 0.." + std::to_string(chunks - 1));
      if (auto st = bench::failChunkHook(sweepDist.chunk); !st) return fail(st.error().message);
      so.progress = false;
      auto rows = bench::runSweepCells(in->scene, sweepC.scene, in->path, so, sweepDist.chunk * sweepPerTask,
                                       std::min(*cells, (sweepDist.chunk + 1) * sweepPerTask));
      if (!rows) return fail(rows.error().message);
      if (auto st = bench::writeChunkResult(work, sweepDist.chunk, {{"rows", *rows}}); !st)
        return fail(st.error().message);
      return 0;
    }
    if (sweepDist.d.resume && !bench::distributed(sweepDist.d))
      return fail("--resume: only with --slurm or --workers N > 1 (an in-process sweep has no chunks to resume)");
    Result<json> res = makeError("");
    if (bench::distributed(sweepDist.d)) {
      if (auto st = ensureWritableDir(sweepOut); !st) return fail(st.error().message);
      bench::ChunkPlan plan{"sweep", work, chunks, bench::chunkCommand(argc, argv)};
      sweepDist.d.progress = !sweepQuiet;
      if (auto st = bench::runChunks(plan, sweepDist.d); !st) return fail(st.error().message);
      auto results = bench::readChunkResults(plan);
      if (!results) return fail(results.error().message);
      json rows = json::array();
      for (const json& r : *results)
        for (const json& row : r.at("rows")) rows.push_back(row);
      res = bench::finishSweep(in->scene, sweepC.scene, in->path, so, rows);
      if (res) bench::removeChunkDir(work);
    } else {
      res = bench::runSweep(in->scene, sweepC.scene, in->path, so);
    }
    if (!res) return fail(res.error().message);
    std::printf("sweep: %zu runs; open %s/index.html (plots, table, overlays); data in sweep.json, sweep.csv\n",
                (*res)["rows"].size(), sweepOut.c_str());
    return 0;
  }

  if (studyCmd->parsed()) {
    bench::ScheduleStudyOptions so;
    if (std::string e = parseSpacings(studySpacings, 0, "", &so.fixedSpacings); !e.empty()) return fail(e);
    if (!studyTargets.empty() && !parseList(studyTargets, &so.targets))
      return fail("--targets: expected comma-separated dB values like 28,30,32, got '" + studyTargets + "'");
    if (studyPlan.minGap > studyPlan.maxGap)
      return fail("--min-gap " + std::to_string(studyPlan.minGap) + " exceeds --max-gap " +
                  std::to_string(studyPlan.maxGap));
    if (std::string e = applyStudyLod(studyLod, &so.walk.lod); !e.empty()) return fail(e);
    so.walk.depthMode = depthModeOf(studyC.depth);
    so.walk.maxFrames = studyC.frames;
    so.referenceSpacing = studyRef;
    keyframe::parsePlanCriterion(studyPlanBy.c_str(), &studyPlan.criterion);
    so.planner = studyPlan;
    so.autoPredictor = studyPredictor == "auto";
    if (!so.autoPredictor) keyframe::parsePredictor(studyPredictor.c_str(), &so.planner.predictor);
    so.outDir = studyOut;
    so.progress = !studyQuiet;
    auto in = loadInputs(studyC);
    if (!in) return fail(in.error().message);
    so.walk.glRenderer = in->context->renderer();
    so.walk.glVersion = in->context->version();
    auto res = bench::runScheduleStudy(in->scene, studyC.scene, in->path, so);
    if (!res) return fail(res.error().message);
    const json& h = (*res)["headline"];
    auto n = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
    std::printf("schedule-study: predictor %s; fixed every %g: %.1f keyframes/100 frames, median %.2f dB;\n"
                "  adaptive at that median: %s%.1f keyframes/100 (%+.0f %% vs fixed; goal -30 %%); at equal count "
                "median %+.2f dB, p5 %+.2f dB;\n  at its p5 (%.2f dB): %s%.1f keyframes/100 (%+.0f %% vs fixed)\n  open %s/index.html\n",
                (*res)["planner"]["predictor"].get<std::string>().c_str(), n(h["reference_spacing"]),
                n(h["reference_keyframes_per_100"]), n(h["reference_psnr_median"]),
                h["adaptive_keyframes_is_upper_bound"].get<bool>() ? "<= " : "",
                n(h["adaptive_keyframes_per_100_at_reference_median"]),
                -100 * n(h["keyframe_reduction"]), n(h["psnr_median_gain_at_equal_count"]),
                n(h["psnr_p5_gain_at_equal_count"]), n(h["reference_psnr_p5"]),
                h["adaptive_keyframes_at_p5_is_upper_bound"].get<bool>() ? "<= " : "",
                n(h["adaptive_keyframes_per_100_at_reference_p5"]),
                -100 * n(h["keyframe_reduction_at_p5"]), studyOut.c_str());
    return 0;
  }

  if (oracleCmd->parsed()) {
    bench::ScheduleOracleOptions so;
    if (std::string e = parseSpacings(oracleSpacings, oracleMaxGap, "--max-gap", &so.fixedSpacings);
        !e.empty())
      return fail(e);
    if (std::find(so.fixedSpacings.begin(), so.fixedSpacings.end(), oracleRef) == so.fixedSpacings.end())
      return fail("--reference-spacing: expected one of --spacings '" + oracleSpacings + "', got " +
                  std::to_string(oracleRef));
    if ((oracleWidth > 0 && oracleWidth < 16) || (oracleHeight > 0 && oracleHeight < 16))
      return fail("--width/--height: expected 0 (the path's) or at least 16 pixels");
    if (std::string e = applyStudyLod(oracleLod, &so.walk.lod); !e.empty()) return fail(e);
    so.walk.depthMode = depthModeOf(oracleC.depth);
    so.walk.maxFrames = oracleC.frames;
    so.referenceSpacing = oracleRef;
    so.maxGap = oracleMaxGap;
    so.tableCsv = oracleTable;
    so.planner = !oracleNoPlanner;
    so.probePsnrSize = oracleProbePsnrSize;
    so.probeError = oracleProbeError;
    if (oracleNoPreviousFill) so.probeError.previousFill = false;
    so.probePsnrOnly = oracleProbePsnrOnly;
    so.outDir = oracleOut;
    so.progress = !oracleQuiet;
    auto in = loadInputs(oracleC);
    if (!in) return fail(in.error().message);
    if (oracleWidth > 0) in->path.width = oracleWidth;
    if (oracleHeight > 0) in->path.height = oracleHeight;
    so.walk.glRenderer = in->context->renderer();
    so.walk.glVersion = in->context->version();
    auto res = bench::runScheduleOracle(in->scene, oracleC.scene, in->path, so);
    if (!res) return fail(res.error().message);
    const json& h = (*res)["headline"];
    auto n = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
    std::printf("schedule-oracle: fixed every %d: %.1f keyframes/100 frames, median %.2f dB; the best "
                "schedule reaching that median: %.1f keyframes/100 (%+.0f %%; goal -30 %%);\n"
                "  the error-driven planner: %.1f keyframes/100 (%+.0f %%)\n  open %s/oracle.png\n",
                oracleRef, n(h["reference_keyframes_per_100"]), n(h["reference_psnr_median"]),
                n(h["oracle_keyframes_per_100"]), -100 * n(h["best_possible_reduction"]),
                n(h["planner_keyframes_per_100"]), -100 * n(h["planner_reduction"]),
                oracleOut.c_str());
    for (const json& pp : h["probe_predictors"])
      std::printf("  %s (%d px): %.1f keyframes/100 (%+.0f %%, %s); fit on this table: %.1f "
                  "(%+.0f %%); one walk-median plan %.0f ms\n",
                  pp["predictor"].get<std::string>().c_str(), pp["probe_size"].get<int>(),
                  n(pp["keyframes_per_100"]), -100 * n(pp["reduction"]),
                  pp["criterion"].get<std::string>().c_str(), n(pp["in_sample_keyframes_per_100"]),
                  -100 * n(pp["in_sample_reduction"]), n(pp["walk_median_plan_ms"]));
    return 0;
  }

  if (lod->parsed()) {
    keyframe::LodOptions lo;
    if (!parseTau(lodTau, &lo.tau))
      return fail("--tau: expected a non-negative number like 2048 or 2^11, got '" + lodTau + "'");
    keyframe::parseDeltaCriterion(lodCriterion.c_str(), &lo.criterion);
    keyframe::parsePlanarity(lodPlanarity.c_str(), &lo.planarity);
    lo.mergeStrips = lodMerge;
    if (std::string err; !parseTauGradient(lodTauGradS, &lo.tauGradient, &err)) return fail(err);
    auto in = loadInputs(lodC);
    if (!in) return fail(in.error().message);
    if (lodFrame >= in->path.frames)
      return fail("--frame: expected 0.." + std::to_string(in->path.frames - 1) + ", got " +
                  std::to_string(lodFrame));
    keyframe::RenderOptions ropt;
    ropt.depthMode = depthModeOf(lodC.depth);
    auto r = keyframe::GeometryRenderer::create(in->scene, ropt);
    if (!r) return fail(r.error().message);
    keyframe::Keyframe kf;
    if (auto s = (*r)->renderKeyframe(in->path.cameraAt(lodFrame), kf); !s) return fail(s.error().message);
    keyframe::QuadMesh mesh;
    keyframe::LodBuilder builder;
    if (auto s = builder.build(kf, lo, &mesh); !s) return fail(s.error().message);
    const auto parent = std::filesystem::path(lodOut).parent_path();
    if (!parent.empty())
      if (auto s = ensureWritableDir(parent.string()); !s) return fail(s.error().message);
    if (auto s = writePng(lodOut, keyframe::drawQuadOverlay(kf.colour, mesh)); !s) return fail(s.error().message);
    const auto& st = mesh.stats;
    json j = {{"scene", {{"name", in->scene.name}, {"triangles", in->scene.triangleCount()}}},
              {"frame", lodFrame},
              {"resolution", {kf.colour.width(), kf.colour.height()}},
              {"tau", lo.tau},
              {"criterion", lodCriterion},
              {"planarity", lodPlanarity},
              {"merge_strips", lodMerge},
              {"tau_gradient", lo.tauGradient},
              {"depth_mode", lodC.depth},
              {"quads", st.quads},
              {"one_pixel_leaves", st.onePixelLeaves},
              {"empty_pixels", st.emptyPixels},
              {"clamped_corners", st.clampedCorners},
              {"ms", {{"delta", st.deltaMs}, {"subdivide", st.subdivideMs}, {"corners", st.cornersMs},
                      {"total", st.deltaMs + st.subdivideMs + st.cornersMs}}}};
    const std::string jsonPath = std::filesystem::path(lodOut).replace_extension(".json").string();
    if (auto s = writeFileAtomic(jsonPath, j.dump(1)); !s) return fail(s.error().message);
    std::printf("%d quads (%d one-pixel leaves) at tau %g in %.2f ms; overlay %s, stats %s\n",
                st.quads, st.onePixelLeaves, lo.tau, st.deltaMs + st.subdivideMs + st.cornersMs,
                lodOut.c_str(), jsonPath.c_str());
    return 0;
  }

  // walk
  bench::WalkOptions wo;
  if (!parseTau(tauS, &wo.lod.tau))
    return fail("--tau: expected a non-negative number like 2048 or 2^11, got '" + tauS + "'");
  wo.lod.tauParallaxPx = tauPx;
  keyframe::parseDeltaCriterion(criterion.c_str(), &wo.lod.criterion);
  keyframe::parsePlanarity(planarity.c_str(), &wo.lod.planarity);
  wo.lod.mergeStrips = mergeStrips;
  if (std::string err; !parseTauGradient(tauGradS, &wo.lod.tauGradient, &err)) return fail(err);
  gapfill::parseComposeMode(compose.c_str(), &wo.compose.mode);
  wo.warp.texcoords = texcoords == "affine" ? warp::TexcoordMode::Affine : warp::TexcoordMode::Projective;
  wo.warp.skyBackdrop = !noSky;
  wo.fusedLayers = layers == "fused";
  wo.skipBackground = !noSkipBg;
  wo.skipPrevious = !noSkipPrev;
  wo.nearDistance = nearDistance;
  wo.warp.subdivision = subdivide == "uniform"    ? warp::Subdivision::Uniform
                        : subdivide == "adaptive" ? warp::Subdivision::Adaptive
                                                  : warp::Subdivision::None;
  wo.warp.subdivideCellPx = subdivideCell;
  warp::parsePrimitives(primitives.c_str(), &wo.warp.primitives);
  wo.warp.cullBackground = cullBg;
  wo.depthMode = depthModeOf(walkC.depth);
  wo.reference = !noRef;
  wo.saveFrames = saveFrames;
  wo.strips = strips;
  wo.maxFrames = walkC.frames;
  wo.outDir = walkOut;
  wo.progress = !quiet;
  wo.keepFrames = false;  // only the summary is printed; frames go to report.json
  if (schedule == "adaptive" && walkPlan.minGap > walkPlan.maxGap)
    return fail("--min-gap " + std::to_string(walkPlan.minGap) + " exceeds --max-gap " +
                std::to_string(walkPlan.maxGap));
  wo.asyncKeyframes = asyncKeyframes;
  wo.keyframeCacheBytes = static_cast<std::size_t>(keyframeCacheMb * 1024 * 1024);
  wo.keyframePrefetch = keyframePrefetch;
  wo.keyframeFlushTriangles = keyframeFlushTriangles;
  wo.keyframeWorkerNice = keyframeWorkerNice;
  wo.keyframeStepsPerFrame = keyframeStepsPerFrame;
  wo.keyframePacing = keyframePacing == "time"     ? bench::WalkOptions::KeyframePacing::Time
                     : keyframePacing == "slices" ? bench::WalkOptions::KeyframePacing::Slices
                     : keyframePacing == "steps"  ? bench::WalkOptions::KeyframePacing::Steps
                                                  : bench::WalkOptions::KeyframePacing::None;
  wo.keyframeBudgetScale = keyframeBudgetScale;
  const bool frameBudgetAuto = fb.isAuto();
  const double frameBudgetMs = fb.ms();
  wo.frameBudgetMs = frameBudgetMs;
  wo.frameBudgetAuto = frameBudgetAuto;
  wo.frameBudgetQuantile = fb.quantile;
  wo.frameBudgetWindow = fb.window;
  wo.staleAfter = staleAfter;
  wo.paceFrames = !noFramePacing;
  wo.pixelAge = pixelAge;
  auto in = loadInputs(walkC);
  if (!in) return fail(in.error().message);
  wo.glRenderer = in->context->renderer();
  wo.glVersion = in->context->version();
  if (!walkKeyframes.empty()) {  // baked keyframes (docs/keyframe-db.md)
    auto db = keyframe::KeyframeDb::open(walkKeyframes);
    if (!db) return fail(db.error().message);
    const int frames = bench::bakeFrames(in->path, walkC.frames);
    if (auto st = db->checkMatches(bench::bakeProvenance(walkC.scene, in->scene.triangleCount(), in->path,
                                                         frames, wo.lod, wo.depthMode));
        !st)
      return fail(st.error().message);
    if (auto st = db->checkSchedule(bench::bakeKeyframeList(in->path, frames)); !st)
      return fail(st.error().message);
    db->setExpectation({[p = in->path](int f) { return p.cameraAt(f); }, wo.depthMode});
    wo.keyframeFrames = db->keyframeFrames();
    wo.keyframeSource = keyframe::makeKeyframeDbSource(std::make_shared<keyframe::KeyframeDb>(std::move(*db)));
  }
  if (!walkKeyframes.empty() && schedule == "adaptive")
    return fail("--keyframes and --schedule adaptive: a baked database has its own keyframe schedule");
  json plannerJson;
  std::vector<bench::PlannedFrame> plannedFrames;  // adaptive: the planner's predictions
  double plannedTarget = 0;
  if (schedule != "adaptive")  // the calibration options only shape an adaptive plan
    for (const char* opt : {"--calibrate-spacing", "--calibration-window", "--plan-uncertainty",
                            "--verify-rounds", "--verify-optimism"})
      if (walk->count(opt) > 0)
        return fail(std::string(opt) + ": expected --schedule adaptive (it shapes the planned "
                    "schedule), got --schedule " + schedule);
  if (schedule == "adaptive") {
    keyframe::parsePredictor(walkPredictor.c_str(), &walkPlan.predictor);
    keyframe::parsePlanCriterion(walkPlanBy.c_str(), &walkPlan.criterion);
    // --target-psnr: dB, or fixed:G (a calibration walk's measured median).
    int targetSpacing = 0;
    std::vector<int> calSpacings;
    if (!walkCalibrate.empty()) {
      if (auto e = parseSpacings(walkCalibrate, 0, "", &calSpacings, "--calibrate-spacing"); !e.empty())
        return fail(e);
    }
    if (walkTarget.rfind("fixed:", 0) == 0) {
      const std::string g = walkTarget.substr(6);
      char* end = nullptr;
      const long v = g.empty() ? 0 : std::strtol(g.c_str(), &end, 10);
      if (g.empty() || *end != '\0' || v < 2 || v > (1 << 20))
        return fail("--target-psnr: expected a PSNR in dB or fixed:G with G a whole number of frames >= 2, "
                    "got '" + walkTarget + "'");
      targetSpacing = static_cast<int>(v);
      if (std::find(calSpacings.begin(), calSpacings.end(), targetSpacing) == calSpacings.end())
        calSpacings.push_back(targetSpacing);
    } else if (!parseFiniteDouble(walkTarget, &walkPlan.targetPsnrDb)) {
      return fail("--target-psnr: expected a PSNR in dB or fixed:G with G a whole number of frames >= 2, "
                  "got '" + walkTarget + "'");
    }
    // --plan-uncertainty: auto/empirical/normal (from the calibration) or a
    // standard deviation in dB.
    double uncertaintyDb = 0;
    const bool uncertaintyNamed =
        walkUncertainty == "auto" || walkUncertainty == "empirical" || walkUncertainty == "normal";
    if (!uncertaintyNamed && (!parseFiniteDouble(walkUncertainty, &uncertaintyDb) || uncertaintyDb < 0))
      return fail("--plan-uncertainty: expected a standard deviation >= 0 in dB, auto, empirical or "
                  "normal, got '" + walkUncertainty + "'");
    if ((walkUncertainty == "empirical" || walkUncertainty == "normal") && calSpacings.empty())
      return fail("--plan-uncertainty " + walkUncertainty +
                  ": expected --calibrate-spacing or --target-psnr fixed:G (the calibration's "
                  "residuals are its error model), got neither");
    if (walkCalWindow > 0 && calSpacings.empty())
      return fail("--calibration-window: expected --calibrate-spacing or --target-psnr fixed:G (the "
                  "window smooths the calibration's residuals), got neither");
    if (walk->count("--verify-optimism") > 0 && walkVerifyRounds == 0)
      return fail("--verify-optimism: expected --verify-rounds 1 or more (it shapes the verified "
                  "plan's search), got --verify-rounds 0");
    if (walkVerifyRounds > 0 && calSpacings.empty())
      return fail("--verify-rounds: expected --calibrate-spacing or --target-psnr fixed:G (the "
                  "verified plan starts from the calibration's measured segments), got neither");
    if (walkVerifyRounds > 0 && walkPlan.criterion != keyframe::PlanCriterion::WalkMedian)
      return fail("--verify-rounds: expected --plan-by walk-median (it counts measured frames "
                  "against the walk's median), got --plan-by " + walkPlanBy);
    std::string uncertaintyModel = uncertaintyDb > 0 ? "normal" : "none";
    keyframe::MeasuredSegments measured;  // the calibration walks' segments
    keyframe::RenderOptions ropt;
    ropt.depthMode = wo.depthMode;
    auto probeRenderer = keyframe::GeometryRenderer::create(in->scene, ropt);
    if (!probeRenderer) return fail(probeRenderer.error().message);
    const int frames = wo.maxFrames > 0 ? std::min(wo.maxFrames, in->path.frames) : in->path.frames;
    const auto cameraOf = [&](int i) { return in->path.cameraAt(i); };
    keyframe::KeyframeProbe probe(**probeRenderer, cameraOf, walkPlan.probeSize, walkPlan.probeError);
    json calibrationJ = nullptr;
    std::string targetSource = "given";
    for (int g : calSpacings)
      if (g < 2 || g > frames - 1)
        return fail(std::string(g == targetSpacing ? "--target-psnr fixed:G" : "--calibrate-spacing") +
                    ": a calibration walk needs keyframes 2.." + std::to_string(frames - 1) +
                    " frames apart on this " + std::to_string(frames) + "-frame walk, got " +
                    std::to_string(g));
    if (!calSpacings.empty()) {
      Stopwatch calSw;
      auto cal = bench::runCalibrationWalks(in->scene, walkC.scene, in->path, frames, calSpacings, wo,
                                            !quiet);
      if (!cal) return fail(cal.error().message);
      measured = cal->measured;
      auto fit = keyframe::calibratePredictor(probe, walkPlan.predictor, cal->samples);
      if (!fit) return fail(fit.error().message);
      walkPlan.useDefaultFit = false;
      walkPlan.fit = fit->fit;
      // The residuals the error model takes: the fit's, or with a window what
      // is left after the path offsets (each sample's offset computed without
      // its own calibration segment, as for a segment the calibration did not
      // walk).
      std::vector<double> residuals;
      std::vector<int> sampleFrames, sampleSegment;  // segment: held out together
      for (std::size_t i = 0; i < cal->samples.size(); ++i) {
        const auto& c = cal->samples[i];
        residuals.push_back(c.psnrDb - fit->predictedDb[i]);
        sampleFrames.push_back(c.frame);
        const bool same = i > 0 && cal->spacing[i] == cal->spacing[i - 1] && c.k0 == cal->samples[i - 1].k0;
        sampleSegment.push_back(i == 0 ? 0 : sampleSegment.back() + (same ? 0 : 1));
      }
      double residualSd = fit->residualStdDb;
      json windowJ = nullptr;
      if (walkCalWindow > 0) {
        auto offsets =
            keyframe::smoothResidualsAlongPath(frames, sampleFrames, residuals, walkCalWindow, 2.0, sampleSegment);
        walkPlan.frameOffsetDb = offsets.offsetDb;
        residuals = offsets.heldOutResidualsDb;
        residualSd = offsets.heldOutRmsDb;
        const auto [lo, hi] = std::minmax_element(offsets.offsetDb.begin(), offsets.offsetDb.end());
        windowJ = {{"frames", walkCalWindow},
                   {"prior_samples", 2.0},
                   {"held_out_residual_rms_db", residualSd},
                   {"offset_min_db", lo == offsets.offsetDb.end() ? 0.0 : *lo},
                   {"offset_max_db", hi == offsets.offsetDb.end() ? 0.0 : *hi}};
      }
      if (walkUncertainty == "normal") {
        uncertaintyDb = residualSd;
        uncertaintyModel = "normal";
      } else if (walkUncertainty == "empirical" || walkUncertainty == "auto") {
        walkPlan.error.setResiduals(std::move(residuals));
        uncertaintyDb = residualSd;
        uncertaintyModel = "empirical";
      }
      for (const auto& w : cal->walks)
        if (w.spacing == targetSpacing) {
          if (!std::isfinite(w.psnrMedian))
            return fail("--target-psnr fixed:" + std::to_string(targetSpacing) +
                        ": the calibration walk has no finite PSNR median");
          walkPlan.targetPsnrDb = w.psnrMedian;
          targetSource = "fixed:" + std::to_string(targetSpacing);
        }
      if (auto st = ensureWritableDir(walkOut); !st) return fail(st.error().message);
      if (auto st = bench::writeCalibration(walkOut, *cal, *fit, walkPlan.predictor, walkPlan.frameOffsetDb);
          !st)
        return fail(st.error().message);
      calibrationJ = bench::calibrationJson(*cal, *fit);
      calibrationJ["window"] = windowJ;
      calibrationJ["ms"] = calSw.ms();
      std::fprintf(stderr, "calibrated %s on %d in-between frames: residual sd %.2f dB, Spearman %.3f",
                   walkPredictor.c_str(), fit->samples, fit->residualStdDb, fit->spearman);
      if (walkCalWindow > 0)
        std::fprintf(stderr, "; along the path (%g frames): %.2f dB left", walkCalWindow, residualSd);
      if (targetSpacing > 0)
        std::fprintf(stderr, "; target %.2f dB (%s)", walkPlan.targetPsnrDb, targetSource.c_str());
      std::fprintf(stderr, "\n");
    }
    if (uncertaintyModel == "normal") walkPlan.error.sigmaDb = uncertaintyDb;
    auto plan = keyframe::planAdaptiveSchedule(probe, frames, walkPlan);
    if (!plan) return fail(plan.error().message);
    wo.keyframeFrames = plan->keyframes;
    json verifyJ = nullptr;
    if (walkVerifyRounds > 0) {
      Stopwatch vsw;
      Status failure;
      const keyframe::PsnrFit fitUsed = plan->fit;
      const keyframe::FramePredictor raw = [&](int k0, int k1, int f) {
        if (!failure.ok()) return -std::numeric_limits<double>::infinity();
        auto ft = keyframe::predictorFeatures(probe, walkPlan.predictor, k0, k1, f);
        if (!ft) {
          failure = ft.error();
          return -std::numeric_limits<double>::infinity();
        }
        return keyframe::predictPsnr(fitUsed, *ft, walkPlan.predictor);
      };
      keyframe::PlanSearch search;
      search.minGap = walkPlan.minGap;
      search.maxGap = walkPlan.maxGap;
      search.error = walkPlan.error;
      keyframe::VerifyOptions verifyOpt;
      verifyOpt.maxRounds = walkVerifyRounds;
      verifyOpt.windowFrames = walkCalWindow;
      verifyOpt.empiricalError = uncertaintyModel == "empirical";
      verifyOpt.optimismDb = walkVerifyOptimism;
      int round = 0;
      const auto measure = [&](const std::vector<std::pair<int, int>>& segs,
                               keyframe::MeasuredSegments& out) {
        int n = 0;
        for (const auto& sg : segs) n += sg.second - sg.first - 1;
        ++round;
        if (!quiet)
          std::fprintf(stderr,
                       "verify round %d/%d: walking %zu planned segments (%d in-between frames)\n",
                       round, walkVerifyRounds, segs.size(), n);
        return bench::measureSegments(in->scene, walkC.scene, in->path, frames, segs, wo, out);
      };
      const std::size_t before = measured.size();
      auto v = keyframe::planVerified(frames, walkPlan.targetPsnrDb, search, raw, measured, measure,
                                      verifyOpt);
      if (!failure.ok()) return fail(failure.error().message);
      if (!v) return fail(v.error().message);
      wo.keyframeFrames = v->keyframes;
      walkPlan.frameOffsetDb = v->offsetDb;
      int referenceKeyframes = 0;
      if (targetSpacing > 0)
        referenceKeyframes = static_cast<int>(
            keyframe::KeyframeSchedule{frames, targetSpacing, {}}.keyframes().size());
      const std::string referenceLabel = "fixed every " + std::to_string(targetSpacing) + " frames";
      if (auto st = bench::writeVerifyPlot(walkOut, *v, referenceKeyframes, referenceLabel); !st)
        return fail(st.error().message);
      json rounds = json::array();
      int framesMeasured = 0;
      for (const auto& r : v->rounds) {
        framesMeasured += r.framesMeasured;
        rounds.push_back({{"keyframes", r.keyframes}, {"unmeasured_segments", r.unmeasured},
                          {"frames_measured", r.framesMeasured},
                          {"guaranteed_keyframes", r.guaranteedKeyframes},
                          {"held_out_residual_rms_db", r.heldOutRmsDb}});
      }
      verifyJ = {{"max_rounds", walkVerifyRounds},
                 {"optimism_db", walkVerifyOptimism},
                 {"rounds", rounds},
                 {"converged", v->converged},
                 {"median_guaranteed", v->guaranteed},
                 {"planned_keyframes", plan->keyframes.size()},
                 {"keyframes", v->keyframes.size()},
                 {"good_frames", v->guaranteed ? json(v->good) : json(nullptr)},
                 {"frames_measured", framesMeasured},
                 {"segments_measured", measured.size() - before},
                 {"ms", vsw.ms()}};
      std::fprintf(stderr,
                   "verified: %zu keyframes (planned %zu) after %zu rounds, %d in-between frames "
                   "measured in %.0f ms; %s\n",
                   v->keyframes.size(), plan->keyframes.size(), v->rounds.size() - 1,
                   framesMeasured, vsw.ms(),
                   v->guaranteed ? "its median guaranteed by measured frames"
                                 : "no guaranteed schedule: the last plan, its median predicted");
    }
    auto predicted = bench::predictSchedule(probe, walkPlan.predictor, plan->fit, wo.keyframeFrames,
                                            walkPlan.frameOffsetDb);
    if (!predicted) return fail(predicted.error().message);
    plannedFrames = std::move(*predicted);
    plannedTarget = walkPlan.targetPsnrDb;
    plannerJson = {{"predictor", walkPredictor}, {"criterion", walkPlanBy},
                   {"target_psnr", walkPlan.targetPsnrDb},
                   {"target_source", targetSource},
                   {"uncertainty", uncertaintyModel},
                   {"uncertainty_db", uncertaintyDb},
                   {"calibration", calibrationJ},
                   {"min_gap", walkPlan.minGap}, {"max_gap", walkPlan.maxGap},
                   {"probe_size", walkPlan.probeSize},
                   {"candidate_stride", walkPlan.candidateStride},
                   {"frames_per_segment", walkPlan.framesPerSegment},
                   {"fit", bench::fitJson(plan->fit)},
                   {"plan_ms", plan->planMs}, {"probe_render_ms", plan->probeRenderMs},
                   {"probes", plan->probes}, {"evaluations", plan->evaluations},
                   {"verify", verifyJ}};
    std::fprintf(stderr, "planned %zu keyframes for %d frames in %.0f ms (%d probes, %.0f ms rendering them)\n",
                 plan->keyframes.size(), frames, plan->planMs, plan->probes, plan->probeRenderMs);
  }
  auto res = bench::runWalk(in->scene, walkC.scene, in->path, wo);
  if (!res) return fail(res.error().message);
  if (!plannerJson.is_null()) {
    // The planner's settings and cost go into the report's summary.
    auto text = readFile(walkOut + "/report.json");
    if (!text) return fail(text.error().message);
    json report = json::parse(*text, nullptr, false);
    if (report.is_discarded()) return fail("cannot parse " + walkOut + "/report.json");
    report["summary"]["keyframe_schedule"] = "adaptive";
    auto predMedian = bench::writePlannedFrames(walkOut, plannedFrames, report["frames"], plannedTarget,
                                                report["summary"]["keyframe_frames"].get<std::vector<int>>());
    if (!predMedian) return fail(predMedian.error().message);
    plannerJson["predicted_psnr_median"] = std::isfinite(*predMedian) ? json(*predMedian) : json(nullptr);
    report["summary"]["planner"] = plannerJson;
    if (auto st = writeFileAtomic(walkOut + "/report.json", report.dump(1)); !st)
      return fail(st.error().message);
  }
  const json& s = res->report["summary"];
  auto num = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
  std::printf(
      "walk: %s (%zu triangles), %dx%d, %d frames (%d keyframes, %s schedule), tau %s, %s\n"
      "  in-between PSNR median %.2f dB (p5 %.2f), SSIM median %.4f\n"
      "  holes before fallback median %.4f%%, after %.4f%%; quads per keyframe median %.0f\n"
      "  in-between frame %.2f ms median (p95 %.2f) vs geometry %.2f ms (p95 %.2f)\n"
      "  every frame (%s keyframes) %.2f ms median, p95 %.2f (p95/median %.2f); "
      "%d keyframe stalls, %.1f ms waited\n",
      walkC.scene.c_str(), in->scene.triangleCount(), in->path.width, in->path.height,
      s["frames"].get<int>(), s["keyframes"].get<int>(), schedule.c_str(), tauS.c_str(),
      s["criterion"].get<std::string>().c_str(), num(s["psnr"]["median"]), num(s["psnr"]["p5"]),
      num(s["ssim"]["median"]), 100 * num(s["holes_before_fallback"]["median"]),
      100 * num(s["holes_after_fallback"]["median"]), num(s["quads_per_keyframe"]["median"]),
      num(s["in_between_ms"]["median"]), num(s["in_between_ms"]["p95"]),
      num(s["reference_ms"]["median"]), num(s["reference_ms"]["p95"]),
      s["keyframe_acquisition"].get<std::string>().c_str(), num(s["frame_ms"]["median"]),
      num(s["frame_ms"]["p95"]), num(s["frame_ms_p95_over_median"]),
      s["keyframe_stalls"].get<int>(), num(s["keyframe_stall_ms_total"]));
  if (frameBudgetAuto)
    std::printf("  frame budget auto: p%.0f of the last %d in-between frames' work, median %.1f ms\n",
                fb.quantile * 100, fb.window, num(s["frame_budget_ms"]));
  if (frameBudgetMs > 0 || frameBudgetAuto)
    std::printf(
        "  frame budget %.1f ms: %d frames refreshed (%.0f px median, %.2f ms median), stale "
        "pixels median %.0f; presented interval %.2f ms median, p95/median %.2f (work %.2f); "
        "%d frames over budget\n",
        num(s["frame_budget_ms"]), s["frames_refreshed"].get<int>(), num(s["refreshed_pixels"]["median"]),
        num(s["refresh_ms"]["median"]), num(s["stale_pixels"]["median"]),
        num(s["frame_interval_ms"]["median"]), num(s["frame_interval_ms_p95_over_median"]),
        num(s["frame_ms_p95_over_median"]), s["budget_overruns"].get<int>());
  std::printf("report: %s/report.json\n", walkOut.c_str());
  return 0;
}

// Every subcommand runs inside one guard: an exception that escapes (out of
// memory above all) becomes one line and exit 1, with temporaries removed,
// instead of std::terminate's abort.
int main(int argc, char** argv) {
  hw::fixMallocMmapThreshold();  // flat RSS in long walks (core/memory.h)
  hw::dieWithParentIfWorker();   // a --workers chunk stops when its parent does
  hw::installSignalCleanup();    // SIGINT/SIGTERM: temporaries removed, exit 130/143
  try {
    return runMain(argc, argv);
  } catch (const std::bad_alloc&) {
    hw::removeRegisteredTemporaries();
    std::fprintf(stderr,
                 "hybridwalk: error: out of memory (an input asked for more than this machine "
                 "has; see docs/bad-input.md for the limits)\n");
  } catch (const std::exception& e) {
    hw::removeRegisteredTemporaries();
    std::fprintf(stderr, "hybridwalk: error: internal error: %s\n", e.what());
  } catch (...) {
    hw::removeRegisteredTemporaries();
    std::fprintf(stderr, "hybridwalk: error: internal error: unknown exception\n");
  }
  return kExitRuntime;
}
