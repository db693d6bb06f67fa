#include "app/cli_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/option_checks.h"
#include "core/check.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/memory_budget.h"
#include "core/safe_io.h"
#include "core/timer.h"
#include "scenes/catalogue.h"
#include "scenes/loader.h"

namespace hw::app {

int fail(const std::string& msg) {
  std::fprintf(stderr, "hybridwalk: error: %s\n", msg.c_str());
  return kExitRuntime;
}

int failUsage(const std::string& msg) {
  fail(msg);
  return kExitUsage;
}

std::string closestName(const std::string& typed, const std::vector<std::string>& known) {
  // Optimal string alignment distance: a swap of two letters is one edit.
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
        d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    return d[a.size()][b.size()];
  };
  std::string best;
  std::size_t bestD = std::max<std::size_t>(2, typed.size() / 4) + 1;
  for (const std::string& k : known)
    if (const std::size_t dk = distance(typed, k); dk < bestD) {
      bestD = dk;
      best = k;
    }
  return best;
}

int reportParseError(const CLI::App& app, const CLI::ParseError& e) {
  if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
  std::string msg = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    const CLI::App* where = &app;
    for (bool deeper = true; deeper;) {
      deeper = false;
      for (const CLI::App* sub : where->get_subcommands())
        if (sub->parsed()) {
          where = sub;
          deeper = true;
          break;
        }
    }
    for (const std::string& arg : app.remaining(true)) {
      if (arg.size() < 2 || arg[0] != '-') continue;
      const std::string typed = arg.substr(0, arg.find('='));
      std::vector<std::string> known;
      for (const CLI::Option* o : where->get_options())
        for (const std::string& n : o->get_lnames()) known.push_back("--" + n);
      const std::string command = where == &app ? "hybridwalk" : where->get_name();
      msg = "unknown option '" + typed + "' for " + command;
      if (const std::string near = closestName(typed, known); !near.empty())
        msg += "; did you mean " + near + "?";
      break;
    }
  }
  fail(msg);
  std::fprintf(stderr, "Run with --help for more information.\n");
  return kExitUsage;
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
std::string misfitToleranceText() {
  char buf[48];
  std::snprintf(buf, sizeof buf, "max(tau/%g, %g)", keyframe::kMisfitTauDivisor,
                keyframe::kMergeNoiseFloor);
  return buf;
}
bool parseTauGradient(const std::string& s, double* out, std::string* err) {
  if (parseTau(s, out)) return true;
  *err = "--tau-gradient: expected a finite non-negative number like " +
         suggestedTauGradient() + ", got '" + s + "'";
  return false;
}


int applyPresetCli(const CLI::App* c, const PresetCli& o, session::Preset* preset,
                   session::WalkOptions* out) {
  resolveWalkOptions(c, o, preset, out);
  return 0;
}

int refusePaperDeparture(session::Preset preset, const session::WalkOptions& wo,
                         const std::function<std::string(const std::string&)>& spelledAs) {
  if (preset != session::Preset::Paper) return 0;
  const auto c = session::differenceFromPaper(wo);
  if (c.option.empty()) return 0;
  const std::string option = spelledAs ? spelledAs(c.option) : c.option;
  return failUsage(option + ": contradicts --preset paper (the paper's: " + c.paperValue +
                   "); drop one of them");
}

CLI::Option* addTauText(CLI::App* c, std::string& tau) {
  return c->add_option("--tau", tau, "LOD threshold in z' units ('2^11' or '2048')")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            double x = 0;
            if (parseTau(v, &x)) return {};
            return "expected a non-negative number like 2048 or 2^11, got '" + v + "'";
          },
          "TAU", "tau"))
      ->capture_default_str();
}

void addStudyLodOptions(CLI::App* c, StudyLod& o) {
  addTauText(c, o.tau);
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
                          std::vector<int>* out, const std::string& option) {
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

// Keyframe schedule options of walk and schedule-study.
void addPlannerOptions(CLI::App* c, session::PlannerOptions& p, std::string& predictor,
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
  for (auto pr : session::kAllPredictors) names.push_back(session::predictorName(pr));
  for (auto pr : session::kProbePredictors) names.push_back(session::predictorName(pr));
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


void addScenePath(CLI::App* c, Common& o) {
  c->add_option("--scene", o.scene, scenes::sceneSpecHelp())->capture_default_str();
  c->add_option("--path", o.path,
                "Camera path JSON (docs/camera-path.md: width, height, fov_y_deg, near, far, up, "
                "keys[{eye, look_at}], frames, keyframe_every; scene units). Default: the "
                "scene's built-in path ('hybridwalk path --scene S' prints it)");
  c->add_option("--keyframe-every", o.keyframeEvery,
                "Frames from one keyframe to the next: replaces the path's keyframe_every "
                "(0 = the path's)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
}

void addGlOptions(CLI::App* c) {
  c->add_option_function<std::string>(
       "--gl",
       [](const std::string& v) {
         gl::HeadlessOptions o = gl::headlessOptions();
         gl::parseBackend(v, &o.backend);  // the check below admits only valid names
         gl::setHeadlessOptions(o);
       },
       "Headless OpenGL: auto (EGL when it gives a 4.5 core context, else OSMesa), egl or "
       "osmesa; default HYBRIDWALK_GL from the environment, else auto (docs/gpu.md)")
      ->check(CLI::IsMember({"auto", "egl", "osmesa"}));
  c->add_option_function<int>(
       "--gl-device",
       [](int n) {
         gl::HeadlessOptions o = gl::headlessOptions();
         o.eglDevice = n;
         gl::setHeadlessOptions(o);
       },
       "EGL device to render on (0-based, as `hybridwalk info` lists them; default: the first "
       "GPU device, else Mesa's surfaceless platform (llvmpipe), else device 0)")
      ->check(CLI::Range(0, 999));
}

void addForceOption(CLI::App* c) {
  c->add_flag("--force")->description(
      "Write into an output folder that is not empty and not hybridwalk's, belongs to "
      "another command, or is a symlink (docs/output-folders.md); a folder in use by another "
      "run is still refused");
}

Result<std::unique_ptr<OutputDir>> claimOutputDir(const CLI::App* c, const std::string& dir,
                                                  const std::vector<std::string>& summaries) {
  const CLI::Option* force = c->get_option_no_throw("--force");
  auto out = OutputDir::open(dir, c->get_name(), force != nullptr && force->count() > 0);
  if (out)
    for (const auto& s : summaries) (*out)->provisional(s);
  return out;
}

int runInOutputDir(const CLI::App* c, const std::string& dir,
                   const std::vector<std::string>& summaries, const std::function<int()>& body) {
  auto out = claimOutputDir(c, dir, summaries);
  if (!out) return fail(out.error().message);
  const int code = body();
  if (code == 0) (*out)->commit();
  return code;
}

void addMaxMemoryOption(CLI::App* c) {
  c->add_option_function<std::string>(
       "--max-memory",
       [](const std::string& v) {
         if (auto b = parseMemorySize(v)) setMemoryBudget(*b);
       },
       "Memory budget of the run for decoded textures and imported meshes, e.g. 4G or 512M "
       "(default 40% of the least of physical memory, the cgroup limit and ulimit -v); what "
       "would pass it is refused before it is read")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            auto b = parseMemorySize(v);
            return b ? std::string() : b.error().message;
          },
          "", "memory size"))
      ->type_name("SIZE");
}

void addCommon(CLI::App* c, Common& o) {
  addGlOptions(c);
  addScenePath(c, o);
  c->add_option("--speed", o.pathOptions.metresPerFrame,
                "Default path on a TORCS track: metres per frame along the centreline (0: 450 m "
                "over 240 frames)")
      ->check(nonNegativeNumber())
      ->capture_default_str();
  c->add_option("--eye-height", o.pathOptions.eyeHeight,
                "Default path: eye above the floor or road in scene units (0: 1.2 m in a TORCS "
                "car, 1.7 m on a MORSE terrain, from the scene's size in a model file)")
      ->check(nonNegativeNumber())
      ->capture_default_str();
  c->add_option("--depth", o.depth,
                "Keyframe depth buffer: float32-reversed (default: keeps corner accuracy at "
                "far/near 1e5..1e6), fixed24 (the paper's 24-bit z-buffer), float32; all mapped "
                "to the same z' scale")
      ->check(CLI::IsMember({"fixed24", "float32", "float32-reversed"}))
      ->capture_default_str();
  c->add_option("--frames", o.frames, "Stop after this many frames of the path (0 = all)")
      ->check(nonNegativeNumber())
      ->capture_default_str();
  c->add_flag_callback("--allow-external-refs", [] { scenes::setExternalRefsAllowed(true); },
                       "Let a model file name files outside its own folder tree (glTF buffers "
                       "and images, OBJ mtllib, textures); refused by default");
  c->add_option_function<int>(
       "--max-texture-size", [](const int& px) { setMaxTextureSize(px); },
       "Scene textures with a side above this are downscaled (with a warning); images over "
       "max(8192, this)^2 pixels are not decoded")
      ->check(CLI::Range(16, 65536))
      ->default_str(std::to_string(maxTextureSize()));
  addMaxMemoryOption(c);
  const CLI::Validator size(
      [](std::string& v) -> std::string {
        char* end = nullptr;
        const long x = std::strtol(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || (x != 0 && (x < 16 || x > 16384)))
          return "expected 0 (the path's) or 16 to 16384 pixels, got '" + v + "'";
        return {};
      },
      "PIXELS", "frame size");
  c->add_option("--width", o.width, "Frame width, pixels (0 = the camera path's)")
      ->check(size)
      ->capture_default_str();
  c->add_option("--height", o.height, "Frame height, pixels (0 = the camera path's)")
      ->check(size)
      ->capture_default_str();
}


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
    std::vector<std::string> notes;
    auto p = scenes::defaultPathFor(o.scene, o.pathOptions, &notes);
    for (const auto& n : notes) std::fprintf(stderr, "hybridwalk: note: %s\n", n.c_str());
    if (!p) return p.error();
    l.path = std::move(*p);
  }
  if (o.width > 0) l.path.width = o.width;
  if (o.height > 0) l.path.height = o.height;
  if (o.keyframeEvery > 0) l.path.keyframeEvery = o.keyframeEvery;
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
      ->check(numberRange(0.1, 600.0))
      ->capture_default_str();
  c->add_option("--chunk", o.chunk, "internal: run one chunk")->group("");
}

std::string GroupedHelp::make_help(const CLI::App* app, std::string name,
                                   CLI::AppFormatMode mode) const {
  if (mode == CLI::AppFormatMode::Sub) return make_expanded(app);
  static const std::vector<std::string> kOrder = {"Essentials", "Options",  "Level of detail",
                                                  "Composition", "Keyframes", "Timing",
                                                  "Studies"};
  std::vector<std::string> groups;
  for (const std::string& g : kOrder) groups.push_back(g);
  for (const std::string& g : app->get_groups())
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  std::string out = make_description(app) + make_usage(app, name) + make_positionals(app);
  bool first = true;
  for (const std::string& g : groups) {
    auto opts = app->get_options([&g](const CLI::Option* o) {
      return o->get_group() == g && o->nonpositional();
    });
    if (g.empty() || opts.empty()) continue;
    if (!first) out += "\n";
    first = false;
    out += make_group(g, false, opts);
  }
  return out + make_subcommands(app, mode) + "\n" + make_footer(app);
}

namespace {
int columns(const std::string& s) {
  int n = 0;
  for (unsigned char ch : s) n += (ch & 0xC0) != 0x80;
  return n;
}
constexpr int kDescColumn = 30;  // where option descriptions start

// "  LEFT  description..." with the description from kDescColumn (on the
// next line when LEFT is wider), wrapped at the help width.
std::string helpEntry(std::string left, const std::string& desc) {
  // A left column wider than a line (a long value set) breaks after a comma.
  std::string lines;
  while (columns(left) + 2 > GroupedHelp::kHelpColumns) {
    std::size_t cut = left.rfind(',', GroupedHelp::kHelpColumns - 3);
    if (cut == std::string::npos || cut == 0) break;
    lines += "  " + left.substr(0, cut + 1) + "\n";
    left = "    " + left.substr(cut + 1);
  }
  std::string out = lines + "  " + left;
  int used = columns(out);
  if (desc.empty()) return out + "\n";
  if (used + 2 > kDescColumn) {
    out += "\n";
    used = 0;
  }
  out += std::string(static_cast<std::size_t>(kDescColumn - used), ' ');
  return out + wrapText(desc, kDescColumn, kDescColumn, GroupedHelp::kHelpColumns) + "\n";
}
}  // namespace

std::string wrapText(const std::string& text, int indent, int used, int width) {
  std::string out;
  int col = used;
  bool lineEmpty = true;
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '\n') {
      out += "\n" + std::string(static_cast<std::size_t>(indent), ' ');
      col = indent;
      lineEmpty = true;
      ++i;
      continue;
    }
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && text[j] != ' ' && text[j] != '\n') ++j;
    const std::string word = text.substr(i, j - i);
    const int w = columns(word);
    if (!lineEmpty && col + 1 + w > width) {
      out += "\n" + std::string(static_cast<std::size_t>(indent), ' ');
      col = indent;
      lineEmpty = true;
    }
    if (!lineEmpty) {
      out += ' ';
      ++col;
    }
    out += word;
    col += w;
    lineEmpty = false;
    i = j;
  }
  return out;
}

std::string GroupedHelp::make_option_name(const CLI::Option* opt, bool isPositional) const {
  if (isPositional) return CLI::Formatter::make_option_name(opt, isPositional);
  std::string names;
  for (const std::string& n : opt->get_snames()) names += (names.empty() ? "-" : ", -") + n;
  for (const std::string& n : opt->get_lnames()) names += (names.empty() ? "--" : ", --") + n;
  return names;
}

std::string GroupedHelp::make_option(const CLI::Option* opt, bool isPositional) const {
  std::string left = make_option_name(opt, isPositional);
  if (!isPositional && opt->get_type_name().empty())  // a flag; a pair shows its default
    left += opt->get_default_str().empty() ? "" : " (default: " + opt->get_default_str() + ")";
  else
    left += make_option_opts(opt);
  return helpEntry(left, make_option_desc(opt));
}

std::string GroupedHelp::make_description(const CLI::App* app) const {
  const std::string d = app->get_description();
  return d.empty() ? std::string() : wrapText(d, 0, 0, kHelpColumns) + "\n";
}

std::string GroupedHelp::make_subcommand(const CLI::App* sub) const {
  return helpEntry(sub->get_display_name(true), sub->get_description());
}

void setGroups(CLI::App* c,
               const std::vector<std::pair<std::string, std::vector<std::string>>>& groups) {
  for (const auto& [group, names] : groups)
    for (const std::string& n : names) {
      CLI::Option* o = n == "--help" ? c->get_help_ptr() : c->get_option_no_throw(n);
      HW_CHECK(o != nullptr);
      o->group(group);
    }
}

}  // namespace hw::app
