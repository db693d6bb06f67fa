// hybridwalk: the command-line program. Subcommands render (geometry frames),
// lod (a keyframe's quad mesh overlay, paper Plate I-A) and walk (the hybrid
// walkthrough with its report, the main job). Errors from outside (files,
// options, GL) are printed as "hybridwalk: error: ..." with a non-zero exit.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "app/viewer.h"
#include "bench/bench_suite.h"
#include "bench/export.h"
#include "bench/stress.h"
#include "bench/sweep.h"
#include "bench/walk.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
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

struct Common {
  std::string scene = "indoor";
  std::string path;  // empty: the scene's default path
  std::string depth = depthModeName(kDefaultDepthMode);
  int frames = 0;
};

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

}  // namespace

int main(int argc, char** argv) {
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
      ->check(CLI::NonNegativeNumber);
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
  walk->add_flag("--no-reference", noRef,
                 "Skip the geometry reference render (no PSNR/SSIM; faster)");
  walk->add_flag("--save-frames", saveFrames, "Write every frame and hole mask as PNG");
  walk->add_option("--strips", strips,
                   "Number of reference|hybrid|diff×4|holes strips to write")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  walk->add_option("--out", walkOut, "Output directory")->capture_default_str();
  walk->add_flag("--quiet", quiet, "No progress line");
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
                   "per keyframe of worker time), steps (--keyframe-steps-per-frame steps per "
                   "frame) or none (as fast as it can); lifted while a frame waits")
      ->check(CLI::IsMember({"time", "steps", "none"}))
      ->capture_default_str();
  walk->add_option("--keyframe-budget-scale", keyframeBudgetScale,
                   "With --keyframe-pacing time: the worker's time per frame as a multiple of its "
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
  sweep->add_option("--overlay-frame", sweepOverlayFrame,
                    "Frame whose quad mesh is drawn per tau (default -1: the middle keyframe)")
      ->check(CLI::Range(-1, 1 << 30));
  sweep->add_option("--out", sweepOut, "Output directory")->capture_default_str();
  sweep->add_flag("--quiet", sweepQuiet, "No progress line");

  // bench
  std::string benchOut = "out/bench", benchSizes;
  bool benchQuick = false, benchQuiet = false;
  auto* benchCmd = app.add_subcommand(
      "bench", "Frame-timing benchmark: geometry vs in-between ms over scene sizes 100k..4M "
               "triangles (tau 2^11, 2^15), a walkthrough trace with per-stage ms, and PSNR vs "
               "keyframe spacing; writes bench.json, CSVs, plots and index.html");
  benchCmd->add_option("--out", benchOut, "Output directory")->capture_default_str();
  benchCmd->add_option("--sizes", benchSizes,
                       "Comma-separated triangle counts for the complexity part (k/M suffixes), "
                       "default 100k,300k,1M,2M,4M");
  benchCmd->add_flag("--quick", benchQuick,
                     "Small version: sizes 100k,300k, fewer frames, trace at 100k, 3 spacings");
  benchCmd->add_flag("--quiet", benchQuiet, "No progress lines");

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
    if (!viewC.path.empty()) {
      vo.playPath = viewC.path;
    }
    vo.sceneLabel = viewC.scene;
    vo.startHybrid = !viewGeometry;
    vo.hud = !viewNoHud;
    auto s = scenes::loadScene(viewC.scene);
    if (!s) return fail(s.error().message);
    auto p = scenes::defaultPathFor(viewC.scene);
    if (!p) return fail(p.error().message);
    return app::runViewer(*s, *p, vo);
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
    }
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
    so.maxFrames = sweepC.frames;
    so.depthMode = depthModeOf(sweepC.depth);
    so.overlayFrame = sweepOverlayFrame;
    so.outDir = sweepOut;
    so.progress = !sweepQuiet;
    auto in = loadInputs(sweepC);
    if (!in) return fail(in.error().message);
    so.glRenderer = in->context->renderer();
    so.glVersion = in->context->version();
    auto res = bench::runSweep(in->scene, sweepC.scene, in->path, so);
    if (!res) return fail(res.error().message);
    std::printf("sweep: %zu runs; open %s/index.html (plots, table, overlays); data in sweep.json, sweep.csv\n",
                (*res)["rows"].size(), sweepOut.c_str());
    return 0;
  }

  if (lod->parsed()) {
    keyframe::LodOptions lo;
    if (!parseTau(lodTau, &lo.tau))
      return fail("--tau: expected a non-negative number like 2048 or 2^11, got '" + lodTau + "'");
    keyframe::parseDeltaCriterion(lodCriterion.c_str(), &lo.criterion);
    keyframe::parsePlanarity(lodPlanarity.c_str(), &lo.planarity);
    lo.mergeStrips = lodMerge;
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
  gapfill::parseComposeMode(compose.c_str(), &wo.compose.mode);
  wo.warp.texcoords = texcoords == "affine" ? warp::TexcoordMode::Affine : warp::TexcoordMode::Projective;
  wo.warp.skyBackdrop = !noSky;
  wo.depthMode = depthModeOf(walkC.depth);
  wo.reference = !noRef;
  wo.saveFrames = saveFrames;
  wo.strips = strips;
  wo.maxFrames = walkC.frames;
  wo.outDir = walkOut;
  wo.progress = !quiet;
  wo.keepFrames = false;  // only the summary is printed; frames go to report.json
  wo.asyncKeyframes = asyncKeyframes;
  wo.keyframeCacheBytes = static_cast<std::size_t>(keyframeCacheMb * 1024 * 1024);
  wo.keyframePrefetch = keyframePrefetch;
  wo.keyframeFlushTriangles = keyframeFlushTriangles;
  wo.keyframeWorkerNice = keyframeWorkerNice;
  wo.keyframeStepsPerFrame = keyframeStepsPerFrame;
  wo.keyframePacing = keyframePacing == "time"    ? bench::WalkOptions::KeyframePacing::Time
                     : keyframePacing == "steps" ? bench::WalkOptions::KeyframePacing::Steps
                                                 : bench::WalkOptions::KeyframePacing::None;
  wo.keyframeBudgetScale = keyframeBudgetScale;
  auto in = loadInputs(walkC);
  if (!in) return fail(in.error().message);
  wo.glRenderer = in->context->renderer();
  wo.glVersion = in->context->version();
  auto res = bench::runWalk(in->scene, walkC.scene, in->path, wo);
  if (!res) return fail(res.error().message);
  const json& s = res->report["summary"];
  auto num = [](const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); };
  std::printf(
      "walk: %s (%zu triangles), %dx%d, %d frames (%d keyframes), tau %s, %s\n"
      "  in-between PSNR median %.2f dB (p5 %.2f), SSIM median %.4f\n"
      "  holes before fallback median %.4f%%, after %.4f%%; quads per keyframe median %.0f\n"
      "  in-between frame %.2f ms median (p95 %.2f) vs geometry %.2f ms (p95 %.2f)\n"
      "  every frame (%s keyframes) %.2f ms median, p95 %.2f (p95/median %.2f); "
      "%d keyframe stalls, %.1f ms waited\n"
      "report: %s/report.json\n",
      walkC.scene.c_str(), in->scene.triangleCount(), in->path.width, in->path.height,
      s["frames"].get<int>(), s["keyframes"].get<int>(), tauS.c_str(),
      s["criterion"].get<std::string>().c_str(), num(s["psnr"]["median"]), num(s["psnr"]["p5"]),
      num(s["ssim"]["median"]), 100 * num(s["holes_before_fallback"]["median"]),
      100 * num(s["holes_after_fallback"]["median"]), num(s["quads_per_keyframe"]["median"]),
      num(s["in_between_ms"]["median"]), num(s["in_between_ms"]["p95"]),
      num(s["reference_ms"]["median"]), num(s["reference_ms"]["p95"]),
      s["keyframe_acquisition"].get<std::string>().c_str(), num(s["frame_ms"]["median"]),
      num(s["frame_ms"]["p95"]), num(s["frame_ms_p95_over_median"]),
      s["keyframe_stalls"].get<int>(), num(s["keyframe_stall_ms_total"]), walkOut.c_str());
  return 0;
}
