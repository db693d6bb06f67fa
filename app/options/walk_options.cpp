#include "app/options/walk_options.h"

#include <cmath>
#include <cstdlib>
#include <string>

#include "app/cli_common.h"
#include "app/option_checks.h"
#include "gapfill/compose.h"
#include "gapfill/fallback.h"
#include "keyframe/delta_buffer.h"
#include "keyframe/lod_builder.h"
#include "warp/warper.h"

namespace hw::app {

using session::WalkOptions;

namespace {

constexpr const char* kEssentials = "Essentials";
constexpr const char* kLod = "Level of detail";
constexpr const char* kComposition = "Composition";
constexpr const char* kKeyframes = "Keyframes";
constexpr const char* kTiming = "Timing";
constexpr const char* kStudies = "Studies";

// Enum names, each from the module that owns the enum.
const auto kFrameModes = enumNames<session::FrameMode>(
    {session::FrameMode::Auto, session::FrameMode::Hybrid, session::FrameMode::Geometry},
    session::frameModeName);
const auto kCriteria = enumNames<keyframe::DeltaCriterion>(
    {keyframe::DeltaCriterion::FivePoint, keyframe::DeltaCriterion::PerAxisMax},
    keyframe::deltaCriterionName);
const auto kPlanarities = enumNames<keyframe::Planarity>(
    {keyframe::Planarity::Stencil, keyframe::Planarity::RegionLocal}, keyframe::planarityName);
const auto kComposeModes = enumNames<gapfill::ComposeMode>(
    {gapfill::ComposeMode::Overlay, gapfill::ComposeMode::DepthMerge, gapfill::ComposeMode::Blend},
    gapfill::composeModeName);
const auto kFallbacks = enumNames<gapfill::Fallback>(
    {gapfill::Fallback::Copy, gapfill::Fallback::Reproject}, gapfill::fallbackName);
const auto kTexcoords = enumNames<warp::TexcoordMode>(
    {warp::TexcoordMode::Projective, warp::TexcoordMode::Affine}, warp::texcoordModeName);
const auto kSubdivisions = enumNames<warp::Subdivision>(
    {warp::Subdivision::None, warp::Subdivision::Uniform, warp::Subdivision::Adaptive},
    warp::subdivisionName);
const auto kPrimitives = enumNames<warp::Primitives>(
    {warp::Primitives::Independent, warp::Primitives::Indexed, warp::Primitives::Shared,
     warp::Primitives::Points},
    warp::primitivesName);
const auto kPacings = enumNames<session::KeyframePacing>(
    {session::KeyframePacing::Time, session::KeyframePacing::Slices, session::KeyframePacing::Steps,
     session::KeyframePacing::None},
    session::keyframePacingName);
const auto kAutoPins = enumNames<session::AutoPin>(
    {session::AutoPin::Use, session::AutoPin::Measure, session::AutoPin::Off},
    session::autoPinName);
// Layers: the two names of InBetweenOptions::fusedLayers.
const std::vector<std::pair<std::string, bool>> kLayers = {{"fused", true}, {"separate", false}};
const auto kWarpers = enumNames<warp::WarperChoice>(
    {warp::WarperChoice::Auto, warp::WarperChoice::Gl, warp::WarperChoice::Cpu},
    warp::warperChoiceName);

OptionRow<WalkOptions> withHelp(OptionRow<WalkOptions> r, std::string help) {
  r.help = std::move(help);
  return r;
}

// A value option that takes a text parsed by `parse` (a message on error).
template <class F, class Show, class Copy>
OptionRow<WalkOptions> parsedRow(std::string name, std::string group, std::string unit,
                                 std::string typeName, std::string help, F parse, Show show,
                                 Copy copy) {
  OptionRow<WalkOptions> r;
  r.name = std::move(name);
  r.group = std::move(group);
  r.unit = std::move(unit);
  r.help = std::move(help);
  r.bind = [parse, typeName, optName = r.name](CLI::App* c, WalkOptions* s, const std::string& d) {
    return c
        ->add_option_function<std::string>(
            optName, [parse, s](const std::string& v) { parse(v, s); }, d)
        ->check(CLI::Validator(
            [parse](std::string& v) -> std::string {
              WalkOptions scratch;
              return parse(v, &scratch);
            },
            typeName, optName));
  };
  r.show = show;
  r.copy = copy;
  return r;
}

std::string tauError(const std::string& v) {
  return "expected a non-negative number like 2048 or 2^11, got '" + v + "'";
}

}  // namespace

WalkRows modeRows() {
  return {choiceRow<WalkOptions>(
      "--mode", +[](WalkOptions& o) -> session::FrameMode& { return o.mode; }, kFrameModes,
      kEssentials,
      "How frames are drawn: auto (per keyframe segment, warped or drawn as geometry, whichever "
      "costs less as measured in this run; geometry when about even), hybrid (every frame "
      "warped or a keyframe, the paper's) or geometry (every frame drawn by the geometry "
      "renderer; no keyframes)")};
}

WalkRows lodRows() {
  WalkRows rows;
  rows.push_back(parsedRow(
      "--tau", kLod, "z' units", "TAU",
      "LOD threshold on |Δ²z'| (2^24 scale), '2^11' or '2048' form; replaces --tau-px (the "
      "paper's threshold; --preset paper: 2^11)",
      [](const std::string& v, WalkOptions* o) -> std::string {
        if (!parseTau(v, &o->lod.tau)) return tauError(v);
        o->lod.tauParallaxPx = 0;  // the threshold in z' units
        return {};
      },
      // None while --tau-px sets the threshold.
      [](const WalkOptions& o) {
        return o.lod.tauParallaxPx > 0 ? std::string() : formatOptionNumber(o.lod.tau);
      },
      [](const WalkOptions& from, WalkOptions* to) {
        to->lod.tau = from.lod.tau;
        to->lod.tauParallaxPx = 0;
      }));
  rows.push_back(valueRow<WalkOptions, double>(
      "--tau-px", +[](WalkOptions& o) -> double& { return o.lod.tauParallaxPx; }, kLod,
      "pixels per scene unit",
      "LOD threshold as parallax error per unit of camera motion (the same meaning indoors and "
      "out); 0 = use --tau",
      nonNegativeNumber()));
  rows.push_back(choiceRow<WalkOptions>(
      "--criterion", +[](WalkOptions& o) -> keyframe::DeltaCriterion& { return o.lod.criterion; },
      kCriteria, kLod, "Planarity test: five-point (paper's eq. 3) or per-axis-max (max(|Δ²x|,|Δ²y|))"));
  rows.push_back(choiceRow<WalkOptions>(
      "--planarity", +[](WalkOptions& o) -> keyframe::Planarity& { return o.lod.planarity; },
      kPlanarities, kLod,
      "Planarity test: stencil (paper: Δ² stencils reach across region borders) or "
      "region-local (second differences only inside the region; no one-pixel strips along "
      "edges)"));
  rows.push_back(togglePair<WalkOptions>(
      "--merge-strips", "--no-merge-strips", +[](WalkOptions& o) -> bool& { return o.lod.mergeStrips; },
      kLod, "Merge adjacent coplanar leaves (within max(tau/4, 4) z' units) into larger quads, or not"));
  rows.push_back(togglePair<WalkOptions>(
      "--split-misfit", "--no-split-misfit", +[](WalkOptions& o) -> bool& { return o.lod.splitMisfit; },
      kLod,
      "Cut a leaf that passed the planarity test but whose least-squares plane misses its own "
      "pixels (by " + misfitToleranceText() +
          " z' units), or whose corners cross a crease; no mis-warped quads "
          "(docs/quad-validation.md), more quads"));
  rows.push_back(parsedRow(
      "--tau-gradient", kLod, "", "A", tauGradientHelp(),
      [](const std::string& v, WalkOptions* o) -> std::string {
        std::string err;
        if (parseTauGradient(v, &o->lod.tauGradient, &err)) return {};
        return err.substr(err.find(": ") + 2);  // CLI11 names the option
      },
      [](const WalkOptions& o) { return formatOptionNumber(o.lod.tauGradient); },
      [](const WalkOptions& from, WalkOptions* to) { to->lod.tauGradient = from.lod.tauGradient; }));
  return rows;
}

namespace {

WalkRows warpLodRows() {
  return {
      choiceRow<WalkOptions>(
          "--subdivide", +[](WalkOptions& o) -> warp::Subdivision& { return o.warp.subdivision; },
          kSubdivisions, kLod,
          "Cut large quads into cells at upload (paper §2.1): none, uniform (every quad, the "
          "paper's), adaptive (only quads whose corner depths differ by 1.5x or whose pixels "
          "leave their plane by > 0.2 %); interior cell corners follow the keyframe depth"),
      valueRow<WalkOptions, int>(
          "--subdivide-cell", +[](WalkOptions& o) -> int& { return o.warp.subdivideCellPx; }, kLod,
          "keyframe pixels", "Cell size for --subdivide", CLI::Range(2, 4096)),
      choiceRow<WalkOptions>(
          "--primitives", +[](WalkOptions& o) -> warp::Primitives& { return o.warp.primitives; },
          kPrimitives, kLod,
          "How quads are drawn (same pixels, different vertex work): independent (6 vertices "
          "per quad), indexed (4 vertices + 6 indices), shared (indexed, corners identical "
          "between neighbouring quads stored once), points (indexed, 1x1 leaves as one GL "
          "point each, sized to their footprint; not pixel-identical)"),
  };
}

WalkRows holeRows() {
  return {
      togglePair<WalkOptions>(
          "--render-holes", "--no-render-holes",
          +[](WalkOptions& o) -> bool& { return o.renderHoles; }, kComposition,
          "After the fallback, draw the larger holes with the geometry renderer: the tiles "
          "(--hole-tile-px) at least 1/32 holes, as tight rectangles (up to --hole-rects-max, "
          "the most holes first; scissored, the scene's clusters culled to each); isolated "
          "cracks keep the fallback's pixels"),
      valueRow<WalkOptions, int>(
          "--hole-tile-px", +[](WalkOptions& o) -> int& { return o.holeTilePx; }, kComposition,
          "pixels",
          "With --render-holes: the side of the tiles the hole rectangles are made of; a tile "
          "is drawn when at least 1/32 of its pixels are holes",
          CLI::Range(2, 256)),
      valueRow<WalkOptions, int>(
          "--hole-rects-max", +[](WalkOptions& o) -> int& { return o.holeRectsMax; },
          kComposition, "rectangles",
          "With --render-holes: at most this many hole rectangles a frame, those with the most "
          "holes; 0 = every one found (in --mode auto the budget alone caps them)",
          CLI::Range(0, 1000000)),
      valueRow<WalkOptions, double>(
          "--render-holes-budget", +[](WalkOptions& o) -> double& { return o.renderHolesBudget; },
          kComposition, "fraction of a geometry frame",
          "With --render-holes and --mode auto: the hole pass may take up to this much of a "
          "geometry frame's time (measured in this run); rectangles are drawn, most holes "
          "first, while their estimated cost fits it and keeps the frame below one geometry "
          "frame. 0 = no cap; --mode hybrid draws every rectangle (frames independent of "
          "timings)",
          numberRange(0.0, 100.0)),
      togglePair<WalkOptions>(
          "--simplify-holes", "--no-simplify-holes",
          +[](WalkOptions& o) -> bool& { return o.simplifyHoles; }, kComposition,
          "With --render-holes: draw the rectangles from a copy of the scene whose flat, evenly "
          "textured surfaces are cut into fewer, larger triangles (outlines and seams kept, "
          "nothing moves; made when the scene loads). The same surfaces at a cost that follows "
          "the rectangles' pixels more than the scene's triangle count"),
  };
}

OptionRow<WalkOptions> warperRow() {
  return choiceRow<WalkOptions, warp::WarperChoice>(
      "--warper", +[](WalkOptions& o) -> warp::WarperChoice& { return o.warper; }, kWarpers,
      kComposition,
      "What draws the warped layers: auto (cpu where OpenGL is itself a CPU rasteriser, such "
      "as Mesa's llvmpipe, and the options allow it; else gl), gl (textured quads through "
      "OpenGL) or cpu (the same quads rasterised on the CPU, 8 pixels at a time; no "
      "--subdivide, --primitives points, --texcoords affine or --cull-background)");
}

OptionRow<WalkOptions> warperThreadsRow() {
  return valueRow<WalkOptions, int>(
      "--warper-threads", +[](WalkOptions& o) -> int& { return o.warperThreads; }, kComposition,
      "threads",
      "With the CPU warper: threads drawing the layers (each sets up a share of the quads, then "
      "draws a band of rows; the pixels do not depend on it)",
      CLI::Range(1, 64));
}

WalkRows compositionRows() {
  WalkRows rows = {
      choiceRow<WalkOptions>(
          "--compose",
          +[](WalkOptions& o) -> gapfill::ComposeMode& { return o.inBetween.compose.mode; },
          kComposeModes, kComposition,
          "Composition: overlay (paper: nearer keyframe in front), depth-merge (per-pixel "
          "nearer of the two layers) or blend (where both layers see the same surface, a mean "
          "weighted toward the keyframe that sees it sharper: closer view direction, less "
          "magnified; else the nearer). depth-merge and blend use separate layers whatever "
          "--layers says"),
      valueRow<WalkOptions, float>(
          "--blend-softness",
          +[](WalkOptions& o) -> float& { return o.inBetween.compose.blendSoftness; }, kComposition,
          "radians or relative magnification",
          "With --compose blend: view penalty difference over which the two weights change by "
          "a factor e",
          numberRange(1e-4, 10.0)),
      choiceRow<WalkOptions>(
          "--fallback", +[](WalkOptions& o) -> gapfill::Fallback& { return o.inBetween.fallback; },
          kFallbacks, kComposition,
          "Pixels neither layer covers: copy (paper: the same pixel of the previous frame) or "
          "reproject (the previous frame warped to this camera with its depth; the same pixel "
          "only where that leaves nothing)"),
  };
  for (auto& r : holeRows()) rows.push_back(r);
  WalkRows more = {
      choiceRow<WalkOptions, bool>(
          "--layers", +[](WalkOptions& o) -> bool& { return o.inBetween.fusedLayers; }, kLayers,
          kComposition,
          "How the two warped layers are composed (overlay rule): fused (one render target, "
          "background drawn only where the foreground left pixels empty, one readback) or "
          "separate (the paper's two layers read back and composed on the CPU). Depth-merge "
          "always uses separate"),
      warperRow(),
      warperThreadsRow(),
      valueRow<WalkOptions, double>(
          "--near", +[](WalkOptions& o) -> double& { return o.inBetween.nearDistance; },
          kComposition, "scene units",
          "Draw objects near the viewpoint directly (paper §3): scene clusters (a few hundred "
          "triangles each) within this distance of a keyframe's eye are left out of that "
          "keyframe, and each frame draws as geometry the clusters within it of its own eye or "
          "of the keyframes it warps; 0 = off",
          nonNegativeNumber()),
      choiceRow<WalkOptions>(
          "--texcoords", +[](WalkOptions& o) -> warp::TexcoordMode& { return o.warp.texcoords; },
          kTexcoords, kComposition,
          "Warp texture mapping: projective (exact for planar quads) or affine (plain "
          "perspective-correct s,t; for comparison)"),
      flagRow<WalkOptions>(
          "--no-sky-backdrop", +[](WalkOptions& o) -> bool& { return o.warp.skyBackdrop; }, false,
          kComposition,
          "Do not draw empty keyframe pixels (sky) as a backdrop at infinity; they then count "
          "as holes, as in the paper"),
      flagRow<WalkOptions>(
          "--no-skip-background",
          +[](WalkOptions& o) -> bool& { return o.inBetween.skipBackground; }, false, kComposition,
          "Draw the background layer even when the foreground covers every pixel (by default "
          "a coverage test skips it; the frame is identical)"),
      flagRow<WalkOptions>(
          "--no-skip-previous", +[](WalkOptions& o) -> bool& { return o.inBetween.skipPrevious; },
          false, kComposition, "Run the previous-frame fill even when the layers leave no holes"),
      flagRow<WalkOptions>(
          "--cull-background", +[](WalkOptions& o) -> bool& { return o.warp.cullBackground; }, true,
          kComposition,
          "Leave out background quads whose surfaces the foreground keyframe sees (they mostly "
          "land under foreground pixels; lossy: cracks along edges then come from the previous "
          "frame). Needs --primitives indexed or shared"),
  };
  for (auto& r : more) rows.push_back(r);
  return rows;
}

OptionRow<WalkOptions> asyncRow() {
  return togglePair<WalkOptions>(
      "--async-keyframes", "--sync-keyframes", +[](WalkOptions& o) -> bool& { return o.asyncKeyframes; },
      kKeyframes,
      "Render and mesh keyframes ahead of need on a worker thread with a second OSMesa "
      "context, or when first needed, in the frame that shows them (frames are identical; "
      "only their timing changes)");
}

// The worker's pacing options (walk and view).
WalkRows workerRows() {
  return {
      choiceRow<WalkOptions>(
          "--keyframe-pacing",
          +[](WalkOptions& o) -> session::KeyframePacing& { return o.keyframePacing; }, kPacings,
          kKeyframes,
          "With --async-keyframes: how the worker spreads a keyframe over the frames before "
          "its need: time (each frame allows budget-scale x last build ms / frames per "
          "keyframe of worker time, alongside the frame), slices (the same budget, run at the "
          "end of each frame while the frame waits: the two never share the CPUs; counted in "
          "the frame's time), steps (--keyframe-steps-per-frame steps per frame) or none (as "
          "fast as it can); lifted while a frame waits"),
      valueRow<WalkOptions, double>(
          "--keyframe-budget-scale",
          +[](WalkOptions& o) -> double& { return o.keyframeBudgetScale; }, kKeyframes, "",
          "With --keyframe-pacing time or slices: the worker's time per frame as a multiple of "
          "its even share (> 1 lets it get ahead)",
          numberRange(1.0, 100.0)),
      valueRow<WalkOptions, int>(
          "--keyframe-steps-per-frame",
          +[](WalkOptions& o) -> int& { return o.keyframeStepsPerFrame; }, kStudies, "steps",
          "With --keyframe-pacing steps: worker steps (a flushed piece of the render, the "
          "readback, a mesh-build step) per frame",
          CLI::Range(1, 1000)),
      valueRow<WalkOptions, std::size_t>(
          "--keyframe-flush-triangles",
          +[](WalkOptions& o) -> std::size_t& { return o.keyframeFlushTriangles; }, kStudies,
          "triangles",
          "With --async-keyframes: the worker flushes its keyframe render after about this "
          "many triangles, so frames on the main context wait behind one piece of it on "
          "llvmpipe's shared rasteriser threads (0 = one flush)"),
  };
}

// --frame-budget-ms MS|auto, its quantile and window (walk and view).
WalkRows frameBudgetRows(const std::string& what) {
  return {
      parsedRow(
          "--frame-budget-ms", kTiming, "ms", "MS|auto",
          "Per-frame time budget of frame work (0 = off), or 'auto': " + what +
              ". 'auto' sets each frame's budget to the --frame-budget-quantile of the work of "
              "the last --frame-budget-window frames, so the frame rate stays steady on any "
              "scene and machine",
          [](const std::string& v, WalkOptions* o) -> std::string {
            if (v == "auto") {
              o->frameBudgetAuto = true;
              return {};
            }
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (v.empty() || *end != '\0' || !std::isfinite(x) || x < 0 || x > 60000)
              return "expected milliseconds from 0 (off) to 60000, or 'auto', got '" + v + "'";
            o->frameBudgetAuto = false;
            o->frameBudgetMs = x;
            return {};
          },
          [](const WalkOptions& o) {
            return o.frameBudgetAuto ? std::string("auto") : formatOptionNumber(o.frameBudgetMs);
          },
          [](const WalkOptions& from, WalkOptions* to) {
            to->frameBudgetAuto = from.frameBudgetAuto;
            to->frameBudgetMs = from.frameBudgetMs;
          }),
      valueRow<WalkOptions, double>(
          "--frame-budget-quantile", +[](WalkOptions& o) -> double& { return o.frameBudgetQuantile; },
          kTiming, "",
          "With --frame-budget-ms auto: the budget is this quantile of the recent frames' work "
          "(walk: in-between frames, without their refresh; above 0, at most 1; 0.9 = 90th "
          "percentile: about one frame in ten is late, the others present at the budget)",
          CLI::Validator(
              [](std::string& v) -> std::string {
                char* end = nullptr;
                const double x = std::strtod(v.c_str(), &end);
                if (v.empty() || *end != '\0' || !std::isfinite(x) || x <= 0 || x > 1)
                  return "expected a quantile above 0 and at most 1, got '" + v + "'";
                return {};
              },
              "Q", "budget quantile")),
      valueRow<WalkOptions, int>(
          "--frame-budget-window", +[](WalkOptions& o) -> int& { return o.frameBudgetWindow; },
          kTiming, "frames",
          "With --frame-budget-ms auto: how many of the last frames the quantile is taken over "
          "(1 to 100000)",
          wholeFrames(1, 100000, "budget window")),
  };
}

}  // namespace

WalkRows walkRows() {
  WalkRows rows = modeRows();
  rows.push_back(choiceRow<WalkOptions>(
      "--auto-pin", +[](WalkOptions& o) -> session::AutoPin& { return o.autoPin; }, kAutoPins,
      kEssentials,
      "With --mode auto: use (draw each frame as the last measured run of the same walk did, "
      "when there is one: same scene, path, options, machine and build; else choose and pin "
      "the choices), measure (choose from this run's costs and pin them) or off (choose, pin "
      "nothing). Pins are kept in $HYBRIDWALK_PINS, else ~/.cache/hybridwalk/mode-pins "
      "(docs/mode-pins.md)"));
  rows.push_back(valueRow<WalkOptions, int>(
      "--strips", +[](WalkOptions& o) -> int& { return o.strips; }, kEssentials, "",
      "Number of reference|hybrid|diff×4|holes strips to write", CLI::Range(0, 100)));
  rows.push_back(flagRow<WalkOptions>(
      "--save-frames", +[](WalkOptions& o) -> bool& { return o.saveFrames; }, true, kEssentials,
      "Write every frame and hole mask as PNG"));
  rows.push_back(flagRow<WalkOptions>(
      "--no-reference", +[](WalkOptions& o) -> bool& { return o.reference; }, false, kEssentials,
      "Skip the geometry reference render (no PSNR/SSIM; faster)"));
  for (auto& r : lodRows()) rows.push_back(r);
  for (auto& r : warpLodRows()) rows.push_back(r);
  for (auto& r : compositionRows()) rows.push_back(r);
  rows.push_back(asyncRow());
  rows.push_back(parsedRow(
      "--keyframe-cache-mb", kKeyframes, "MiB", "MIB",
      "Memory bound of the keyframe cache (colour + depth + quad mesh; the two keyframes of "
      "the current bracket are always kept); capped by what --max-memory has left",
      [](const std::string& v, WalkOptions* o) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !std::isfinite(x) || x <= 0 || x > 1e9)
          return "expected a finite number of MiB above 0, got '" + v + "'";
        o->keyframeCacheBytes = static_cast<std::size_t>(x * 1024 * 1024);
        return {};
      },
      [](const WalkOptions& o) {
        return formatOptionNumber(static_cast<double>(o.keyframeCacheBytes) / (1024 * 1024));
      },
      [](const WalkOptions& from, WalkOptions* to) {
        to->keyframeCacheBytes = from.keyframeCacheBytes;
      }));
  rows.push_back(valueRow<WalkOptions, int>(
      "--keyframe-prefetch", +[](WalkOptions& o) -> int& { return o.keyframePrefetch; }, kKeyframes,
      "keyframes", "With --async-keyframes: keyframes past the current pair built ahead",
      CLI::Range(0, 64)));
  for (auto& r : workerRows()) rows.push_back(r);
  rows.push_back(valueRow<WalkOptions, int>(
      "--keyframe-worker-nice", +[](WalkOptions& o) -> int& { return o.keyframeWorkerNice; },
      kStudies, "", "With --async-keyframes: nice increment of the worker thread (0-19)",
      CLI::Range(0, 19)));
  for (auto& r : frameBudgetRows(
           "with time left after an in-between frame is composed, the region of pixels carried "
           "over from earlier frames longest is re-rendered by the geometry renderer if its "
           "estimated cost fits, and frames are presented every this many ms"))
    rows.push_back(r);
  rows.push_back(valueRow<WalkOptions, int>(
      "--stale-after", +[](WalkOptions& o) -> int& { return o.staleAfter; }, kTiming, "frames",
      "With --frame-budget-ms: frames a pixel must have been carried over from the previous "
      "frame before it counts for a refresh (at least 1)",
      wholeFrames(1, 255, "stale after")));
  rows.push_back(flagRow<WalkOptions>(
      "--no-frame-pacing", +[](WalkOptions& o) -> bool& { return o.paceFrames; }, false, kTiming,
      "With --frame-budget-ms: refresh within the budget but do not wait for it to pass before "
      "the next frame"));
  rows.push_back(flagRow<WalkOptions>(
      "--pixel-age", +[](WalkOptions& o) -> bool& { return o.pixelAge; }, true, kTiming,
      "Track and report per-pixel age (frames carried over from the previous frame) without a "
      "budget (always on with --frame-budget-ms); frames are identical"));
  return rows;
}

WalkRows bakeRows() { return lodRows(); }

WalkRows viewRows() {
  WalkRows rows;
  rows.push_back(withHelp(
      modeRows()[0],
      "How frames are drawn: auto (every 10 frames hybrid or geometry, whichever costs less as "
      "measured in this session, geometry when about even; the walk's rule), hybrid (every "
      "frame warped from two keyframes, the paper's) or geometry (the geometry renderer, as "
      "--geometry); g switches between hybrid and geometry by hand (and ends auto)"));
  for (auto& r : lodRows()) rows.push_back(r);
  for (auto& r : holeRows()) rows.push_back(r);
  rows.push_back(warperRow());
  rows.push_back(warperThreadsRow());
  rows.push_back(withHelp(
      asyncRow(),
      "Render and mesh keyframes ahead on a worker thread with a second OpenGL context (a "
      "hidden window): the viewer requests the next keyframe and warps the ones it has until "
      "it is ready instead of rendering it in the frame (keyframes are identical; when one "
      "arrives changes), or render them in the frame that needs them. Lost (no keyframe within "
      "reach) it waits for the one in flight if that is within reach, else renders one in the "
      "frame; baked --keyframes are read as without it. With s s, the statistics show keyframe "
      "stalls and waits"));
  WalkRows worker = workerRows();
  worker[0].help =
      "With --async-keyframes, as for walk: time (per frame the worker may take budget-scale x "
      "last build ms / F of wall time, F = the frames the viewer takes per keyframe: measured "
      "from its requests, at most the frames until it would be lost, starting from "
      "keyframe_every / 2 of the path), slices (the same budget, run after each frame is shown, "
      "counted in its time), steps (--keyframe-steps-per-frame steps per frame) or none (as "
      "fast as it can)";
  for (auto& r : worker) {
    if (r.group == kStudies) r.group = kKeyframes;
    rows.push_back(r);
  }
  for (auto& r : frameBudgetRows(
           "after a frame is shown the viewer waits until this many ms have passed since it "
           "started, so frames are presented at a steady cadence (pacing only: the viewer does "
           "not refresh stale pixels)"))
    rows.push_back(r);
  return rows;
}

void addWalkOptionSet(CLI::App* c, WalkOptionSet* s, WalkRows rows, const std::string& presetHelp) {
  c->add_option("--preset", s->preset, presetHelp)
      ->check(CLI::IsMember({session::presetName(session::Preset::Default),
                             session::presetName(session::Preset::Paper)}))
      ->group(kEssentials)
      ->capture_default_str();
  s->rows = std::move(rows);
  addOptionRows(c, s->rows, &s->parsed, session::presetOptions(session::Preset::Default));
  CLI::Option* tau = c->get_option_no_throw("--tau");
  CLI::Option* tauPx = c->get_option_no_throw("--tau-px");
  if (tau != nullptr && tauPx != nullptr) tauPx->excludes(tau);
}

void resolveWalkOptions(const CLI::App* c, const WalkOptionSet& s, session::Preset* preset,
                        session::WalkOptions* out) {
  *preset = session::Preset::Default;
  session::parsePreset(s.preset, preset);  // checked by the option's validator
  *out = session::presetOptions(*preset);
  copyGivenOptions(c, s.rows, s.parsed, out);
}

std::string walkOptionsMarkdown() {
  return "`--preset default|paper` (default: default) chooses the settings the walk starts "
         "from; the defaults below are the default preset's, and an option given replaces the "
         "preset's value (with paper, an option departing from the paper is an error).\n" +
         optionRowsMarkdown(walkRows(), session::presetOptions(session::Preset::Default));
}

}  // namespace hw::app
