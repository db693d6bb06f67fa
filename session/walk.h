#pragma once
// A hybrid walkthrough (the main job): keyframes every N frames drawn by the
// geometry renderer and meshed by the Δ²z' LOD builder; every other frame
// backward-warped from its two bracketing keyframes and composed with the
// previous frame (Zheng et al. 1999 §2); each frame measured against the
// geometry renderer at the same camera. Writes DESIGN.md's walk report.
#include <algorithm>
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/result.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/lod_builder.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"
#include "session/frame_mode.h"
#include "session/in_between.h"
#include "session/mode_pin.h"
#include "warp/cpu_warper.h"
#include "warp/warper.h"

namespace hw::session {

// How an async keyframe worker spreads a keyframe over the frames before its
// need (WalkOptions::keyframePacing, the viewer's too).
enum class KeyframePacing { None, Steps, Time, Slices };
const char* keyframePacingName(KeyframePacing p);  // "none", "steps", "time", "slices"

struct WalkOptions {
  // How frames are drawn: Hybrid (every frame warped or a keyframe, the
  // paper's), Geometry (no keyframes), or Auto: per keyframe segment, the one
  // predicted cheaper from costs measured in this run (session/frame_mode.h).
  // Geometry frames render once: the frame is its own reference.
  FrameMode mode = FrameMode::Hybrid;
  ModeChooserOptions modeChooser;
  // FrameMode::Auto: replay the choices a measured run of the same walk
  // pinned, choose and pin them, or neither (session/mode_pin.h). Pins are
  // kept in modePinDir ("" = none, the library's default; the program sets
  // defaultModePinDir()). modePinContext: what else the choice depends on
  // that the walk does not see (the program's options and scene spec), part
  // of the pin's name.
  AutoPin autoPin = AutoPin::Use;
  std::string modePinDir;
  std::string modePinContext;
  keyframe::LodOptions lod;                     // τ (z' units), criterion, parallax bound
  keyframe::MeshMethod mesh = keyframe::MeshMethod::Lod;  // or a baseline (sweep)
  int tileSize = 8;                             // pixels, MeshMethod::UniformTiles
  DepthMode depthMode = kDefaultDepthMode;     // keyframe depth buffer
  // Composition, layers, skips and near geometry of the in-between frames.
  InBetweenOptions inBetween;
  warp::WarpOptions warp;                       // texcoords, sky backdrop
  // Which warper draws the layers; Auto: the CPU warper on a CPU rasteriser
  // (llvmpipe), where it measured faster, else GL (warp/cpu_warper.h).
  warp::WarperChoice warper = warp::WarperChoice::Auto;
  // The CPU warper's threads (they set up the quads between them, then each
  // draws a band of rows): on 2 cores, beside the keyframe worker and
  // llvmpipe's threads, two drew the layers in 0.68-0.87x one's time on 7
  // scenes (docs/results/2026-12-07/cpu-warper-threads).
  int warperThreads = 2;
  bool reference = true;                        // render and compare the geometry frame
  int maxFrames = 0;                            // 0 = all frames of the path
  // Output (all optional; empty outDir = write nothing).
  std::string outDir;
  bool saveFrames = false;  // frames/NNNN.png and holes/NNNN.png
  int strips = 4;           // side-by-side strips of this many in-between frames
  bool progress = true;     // a progress line on stderr
  // Keep every frame's entry in WalkResult::report["frames"]. Off: entries go
  // only to report.json (streamed through a scratch file; flat memory on long
  // walks) and report["frames"] is empty.
  bool keepFrames = true;
  std::string glRenderer, glVersion;  // recorded in the report's machine block
  // Keyframe frames in order (empty = every path.keyframeEvery frames); the
  // first and last frame are always keyframes.
  std::vector<int> keyframeFrames;
  // Walk only the frames k0..k1 of these segments (each k0 < k1 keyframes of
  // the schedule, none inside another's span); the others are skipped, not
  // rendered nor reported. Empty = every frame. A frame depends only on its
  // segment (the previous-frame chain starts at keyframe k0), so its PSNR is
  // the full walk's (the verified planner measures segments this way).
  std::vector<std::pair<int, int>> onlySegments;
  // Where keyframes come from (empty = rendered and meshed on the fly).
  keyframe::KeyframeCache::Source keyframeSource;
  // Keyframe acquisition. Bound on the bytes of
  // cached keyframes (colour + depth + mesh).
  std::size_t keyframeCacheBytes = keyframe::CacheOptions{}.maxBytes;
  // Render and mesh keyframes ahead of need on a worker thread with a second
  // OSMesa context; the main thread only uploads them. Off = built on first
  // use on the main thread (the reference behaviour). Ignored with a
  // keyframeSource. Frames are bit-identical either way.
  bool asyncKeyframes = false;
  int keyframePrefetch = 2;  // async: keyframes past the current bracket built ahead
  // async: the worker's renderer flushes after about this many triangles, so
  // the main thread's warp waits behind at most one piece of a keyframe on
  // llvmpipe's rasteriser threads, which both contexts share (0 = no flush).
  std::size_t keyframeFlushTriangles = 8192;
  int keyframeWorkerNice = 0;  // async: nice increment of the worker thread (Linux)
  // async pacing of the worker, so a keyframe's cost is spread over the
  // frames before its need instead of landing on one or two:
  //  Time: each frame grants budgetScale × (last build's ms) / (frames per
  //        keyframe) of worker time (AsyncKeyframeOptions::framesPerKeyframe);
  //  Steps: keyframeStepsPerFrame steps (render pieces, readback, mesh build
  //        steps) per frame;  None: as fast as it can.
  //  Slices: the Time budget, but the worker runs it at the end of each
  //        frame's work while the main thread waits (AsyncKeyframeOptions::
  //        slices), counted in the frame's time (ms "keyframe_slice").
  using KeyframePacing = session::KeyframePacing;
  KeyframePacing keyframePacing = KeyframePacing::Time;
  double keyframeBudgetScale = 2.0;
  int keyframeStepsPerFrame = 2;
  // Per-frame time budget (after Qu et al. 2000 §3.4), in ms of
  // frame work; 0 = off (the frames are those of the walk without it). With
  // a budget, after an in-between frame is composed and time is left, the
  // region whose pixels are oldest (tiles of kRefreshTilePx ranked by the
  // summed age of pixels with age >= staleAfter) is re-rendered by the
  // geometry renderer (scissored) if a running estimate of that render's cost
  // says it fits in what is left; up to kMaxRefreshRects regions a frame.
  // With paceFrames the walk then sleeps until frameBudgetMs have passed since
  // the frame started, so frames are presented at a steady cadence.
  double frameBudgetMs = 0;
  // Automatic budget (session/frame_budget.h; frameBudgetMs is then unused):
  // each frame's budget is the frameBudgetQuantile of the work (without the
  // refresh) of the last frameBudgetWindow in-between frames; no budget (no
  // refresh, no pacing) until AutoFrameBudget::minSamples() are known.
  bool frameBudgetAuto = false;
  double frameBudgetQuantile = 0.9;
  int frameBudgetWindow = 30;
  int staleAfter = 2;  // frames carried over before a pixel counts for a refresh (>= 1)
  bool paceFrames = true;
  // Per-pixel age (gapfill/age.h) and the stale-pixel counts without a
  // budget (always on with one). Frames are identical.
  bool pixelAge = false;
  // Holes drawn by the geometry renderer: after the fallback, the tiles of
  // holeTilePx² pixels at least 1/32 of which no keyframe layer (nor near
  // geometry) covers are re-rendered, scissored and with the
  // scene's clusters culled to the rectangle, in tight rectangles
  // (gapfill/hole_rects.h), the holeRectsMax with the most holes, most holes
  // first; in auto mode as many of those as fit renderHolesBudget. What is
  // left (isolated cracks) keeps the fallback's pixels. false = the paper's
  // (every hole from the fallback).
  bool renderHoles = false;
  // At most this many hole rectangles a frame; 0 = every one found (the
  // budget alone caps them in auto mode). 12 measured the better default
  // (docs/results/2026-12-07/hole-rects-uncapped).
  int holeRectsMax = 12;
  // The hole tiles' side, pixels (holeTileMinPixels: the holes that make a
  // tile one to draw).
  int holeTilePx = 16;
  static int holeTileMinPixels(int tilePx) { return std::max(1, tilePx * tilePx / 32); }
  // With FrameMode::Auto, the hole pass's time cap, as a fraction of a
  // geometry frame's time (the mode chooser's median, else this frame's
  // reference render): rectangles are drawn, most holes first, while their
  // estimated cost (HoleCostModel) fits both this cap and what keeps the
  // whole frame below one geometry frame. 0 = no cap. The other modes draw
  // every rectangle, so their frames do not depend on timings.
  double renderHolesBudget = 0;
  // With renderHoles, the rectangles are drawn from a simplified copy of the
  // scene (keyframe::RenderOptions::simplifiedRects): the same surfaces in
  // fewer, larger triangles. false = the scene's own triangles.
  bool simplifyHoles = false;
  static constexpr int kRefreshTilePx = 32;
  static constexpr int kMaxRefreshRects = 4;
};

// Each walked frame's times, for frame_times.png (report/walk_plots.h).
struct FrameTimes {
  std::vector<int> frame;           // frame index
  std::vector<FrameKind> kind;      // how the frame was drawn
  std::vector<char> builtKeyframe;  // 1 = the frame paid for building or uploading a keyframe
  std::vector<double> workMs;       // ms.frame
  std::vector<double> intervalMs;   // ms.interval (work + pacing wait)
  std::vector<double> budgetMs;     // the frame's budget; 0 = none
  std::vector<double> referenceMs;  // geometry render at the same camera; NaN without reference
  double floorMs = -1;  // the fill floor: two layers of one full-screen quad (-1: not measured)
};

struct WalkResult {
  nlohmann::json report;  // {"frames": [...], "summary": {...}}
  FrameTimes frameTimes;
  // reference | hybrid | difference x4 | holes, side by side (4 px gaps), of
  // the frames in report.summary.strips (same order); report/walk_plots.h
  // writes them captioned.
  std::vector<Image<Rgba8>> strips;
};

// Runs the walk on an already loaded scene and path. A GL context must be
// current. With an output directory it writes report.json and (saveFrames)
// every frame; the strips and frame_times.png are report/walk_plots.h's. Errors
// (GL, output) come back as Error; nothing half-written.
Result<WalkResult> runWalk(const scenes::Scene& scene, const std::string& sceneLabel,
                           const scenes::CameraPath& path, const WalkOptions& options);

}  // namespace hw::session
