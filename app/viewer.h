#pragma once
// The interactive viewer (`hybridwalk view`): a GLFW window that flies through
// a scene, drawing each frame either with the geometry renderer or the hybrid
// way — two keyframes around the viewer, backward-warped and composed with the
// previous frame (Zheng et al. 1999 §2; DESIGN.md "Viewer conventions").
//
// Controls (also printed by `h`):
//   right mouse button held: mouse look, and W/A/S/D fly (forward/left/back/
//     right along the view), Q/E down/up. Without the button the letters are
//     commands (so `s`/`w` keep their osgviewer meaning). Arrow keys and
//     PageUp/PageDown move at any time. Shift: 4× faster. +/-: speed ×/÷ 1.5.
//   osgviewer keys: s statistics (fps, then per-stage ms, quads, holes, then
//     also keyframe stalls and waits, then off; app/viewer_keys.h),
//     w wireframe (hybrid: the warped keyframe quads' outlines; geometry: the
//     scene's triangles), f full screen, c screenshot (PNG in the current
//     directory), z record a camera path (again: stop and save), Z play it,
//     space home (the path's first camera), Esc quit.
//   ours: h help, g hybrid/geometry, o the foreground keyframe's quad overlay
//     (Plate I-A) in a corner, m hole mask (red: pixels neither keyframe
//     covers), p PSNR of the current view against the geometry reference.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "core/camera.h"
#include "keyframe/keyframe.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "keyframe/quad_mesh.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"
#include "session/frame_mode.h"
#include "session/walk.h"

namespace hw::app {

// Zero/default values work as given. As with session::WalkOptions, the
// struct's own values are the paper's pipeline (every frame hybrid, τ 2^11
// z' units, keyframes rendered in the frame); `view` starts from a preset
// instead (applyWalkOptions, session/presets.h).
struct ViewerOptions {
  std::string sceneLabel;         // window title and HUD
  int width = 800, height = 600;  // window size, pixels (≥ 16)
  // How frames are drawn: Hybrid (warped from two keyframes; `g` toggles to
  // the geometry renderer and back), Geometry (the geometry renderer), or
  // Auto: every 10 frames hybrid or geometry, whichever is predicted cheaper
  // from this session's frame times (the walk's rule, session/frame_mode.h);
  // it starts hybrid, the first choice and (with keyframes from the worker or
  // a database) one in four while hybrid draw a frame as geometry to measure
  // it, and `g` turns it off.
  session::FrameMode mode = session::FrameMode::Hybrid;
  // The keyframes' quad meshes (threshold, planarity test, merging). Baked
  // keyframes keep the database's own.
  keyframe::LodOptions lod;
  // The larger holes both keyframes miss drawn by the geometry renderer
  // (session/hole_pass.h); false: the previous frame's pixels, as the paper.
  bool renderHoles = false;
  // With mode Auto, the hole pass's time cap as a fraction of a geometry
  // frame's time, as WalkOptions::renderHolesBudget (0 = every rectangle).
  double renderHolesBudget = 0;
  // The hole rectangles drawn from the simplified scene (WalkOptions::simplifyHoles).
  bool simplifyHoles = false;
  int holeRectsMax = session::WalkOptions{}.holeRectsMax;  // WalkOptions::holeRectsMax
  int holeTilePx = session::WalkOptions{}.holeTilePx;      // WalkOptions::holeTilePx
  // What draws the warped layers, and the CPU warper's threads
  // (WalkOptions::warper, warperThreads).
  warp::WarperChoice warper = warp::WarperChoice::Auto;
  int warperThreads = session::WalkOptions{}.warperThreads;
  // Where frames are composed with OpenGL's warper: Gpu keeps them there
  // (session::FrameEngine::keepFramesOnGpu: composed, hole-filled and shown
  // from a texture, never read back to draw the next one); Cpu reads each
  // back and composes it as walk does (the same pixels); Auto: the GPU unless
  // OpenGL is itself a CPU rasteriser (Mesa's llvmpipe), where composing on
  // the CPU measured faster (docs/viewer.md). The CPU warper composes on the
  // CPU whatever this says.
  enum class FramesOn { Auto, Gpu, Cpu };
  FramesOn framesOn = FramesOn::Auto;
  // Frames between keyframes of the play/default path (its keyframe_every,
  // which sets the keyframe spacing); 0 = the path's own (`view --keyframe-every`).
  int keyframeEvery = 0;
  std::string playPath;           // camera path JSON file; empty: the default path
  bool play = false;              // start by playing the path (loops; any move stops it)
  int exitAfterFrames = 0;        // scripted exit after this many frames; 0 = until closed
  // Written (window contents, PNG) when the viewer exits, if set. The `c` key
  // writes hybridwalk_screenshot_N.png into the current directory instead.
  std::string screenshotPath;
  // `z` saves the recorded path here and `Z` plays it from here (falling back
  // to the last recording in memory). Empty: hybridwalk_path.json in the cwd.
  std::string recordPath;
  bool hud = true;          // false: never draw the HUD (image comparisons)
  bool visible = true;      // window shown
  // Typed before the first frame, one character per key press, as if from
  // the keyboard (scripted sessions): e.g. "s" for per-stage statistics;
  // "@N" types the keys after it before frame N instead, e.g. "s@30p"
  // (parseScriptedKeys, app/viewer_keys.h; a bad mark is an error exit).
  std::string keys;
  // A new keyframe is rendered when the viewer is this far (scene units) or
  // this much turned from its keyframes. 0 = the play/default path's spacing
  // between its keyframes (arc length / frames × keyframe_every).
  double keyframeDistance = 0;
  double keyframeAngleDeg = 15;
  // Baked keyframes (`view --keyframes DB`, docs/keyframe-db.md). Set, the
  // viewer warps the database's keyframes instead of rendering its own while
  // one is within reach: playing the baked path, exactly the pair the walk
  // uses for that frame (so the frames are `walk --keyframes DB`'s); flying,
  // the two nearest by pose distance (the next one along the path is read
  // ahead on a background thread). Farther than that from every baked
  // keyframe, or at another window size, keyframes are rendered live as
  // without a database. The caller checks that the database was baked from
  // this scene and the play/default path, at the window's size.
  std::shared_ptr<const keyframe::KeyframeDb> keyframeDb;
  // Keyframes rendered and meshed on a worker thread (`view --async-keyframes`,
  // keyframe/gl/async_keyframes.h) with its own context in a hidden window:
  // as soon as the newest keyframe has no successor in flight the viewer
  // requests the next one, about as far beyond the newest as the
  // synchronous viewer would place it (app/keyframe_pacing.h), and puts it
  // into a slot when the synchronous viewer would render one (until then it
  // warps the two it has); it never waits for it unless lost (no keyframe
  // within reach): then it waits for the one in flight if that one is
  // within reach, else renders one in the frame. The first keyframe comes
  // from the worker, waited for (loading). Baked keyframes (keyframeDb) are
  // read as without it.
  bool asyncKeyframes = false;
  // How the worker spreads a keyframe over the frames, as `walk
  // --keyframe-pacing` (AsyncKeyframeOptions): Time and Slices allow
  // budgetScale x (last build ms) / F of worker time per frame, F the
  // viewer's keyframe interval in frames: at first half the play/default
  // path's keyframe_every, then the measured interval between its requests,
  // or fewer frames when at its current speed the viewer would be lost
  // sooner (app/keyframe_pacing.h; lockstep keeps the first F); Steps
  // allows stepsPerFrame steps; None runs flat out. Slices run after each
  // frame is shown, counted in its time.
  using KeyframePacing = session::KeyframePacing;
  KeyframePacing keyframePacing = session::WalkOptions{}.keyframePacing;
  double keyframeBudgetScale = session::WalkOptions{}.keyframeBudgetScale;
  int keyframeStepsPerFrame = session::WalkOptions{}.keyframeStepsPerFrame;
  // AsyncKeyframeOptions::flushEveryTriangles
  std::size_t keyframeFlushTriangles = session::WalkOptions{}.keyframeFlushTriangles;
  // Test hook: each worker keyframe is requested when the synchronous viewer
  // would render it and taken (waited for) in that frame, so keyframes and
  // frames are the synchronous viewer's (no early requests, fixed pacing).
  bool asyncLockstep = false;
  // Frame pacing (`view --frame-budget-ms MS|auto`): after a frame is shown
  // the viewer sleeps until frameBudgetMs (> 0) have passed since the frame
  // started; with frameBudgetAuto the budget is the frameBudgetQuantile of
  // the work of the last frameBudgetWindow frames (bench/frame_budget.h),
  // none until enough are known. Pacing only: no stale-pixel refresh.
  double frameBudgetMs = 0;
  bool frameBudgetAuto = false;
  double frameBudgetQuantile = session::WalkOptions{}.frameBudgetQuantile;
  int frameBudgetWindow = session::WalkOptions{}.frameBudgetWindow;
  // Written at exit if set: one CSV row per frame (frame ms, how it was
  // drawn, keyframe events: rendered in the frame, read, taken from the
  // worker, requested, waited for), for median / p95 of the frame time.
  std::string frameStatsPath;
  // Test hook: called with the window's context current for every keyframe
  // put into a slot except baked ones (fromWorker: built by the worker).
  std::function<void(const keyframe::Keyframe&, const keyframe::QuadMesh&, bool fromWorker)>
      onKeyframe;
  // Test hook: called with the window's GL context current, after the last
  // frame and before the window closes, with that frame's camera (whose size
  // is the window's framebuffer size).
  std::function<void(const Camera& lastCamera)> onExit;
};

// Sets the viewer's share of a walk's options (a preset's, session/presets.h)
// in `out`, leaving its other fields: the frame mode, the LOD options,
// whether keyframes are built ahead on a worker, and the hole pass with its
// budget. Composition, near geometry and subdivision are the engine's
// defaults (session/frame_engine.h), as both presets have them.
void applyWalkOptions(const session::WalkOptions& walk, ViewerOptions* out);

// Options a caller of runViewer got wrong (window size, thresholds, frame
// counts, --keys marks), as an error naming the value; the CLI checks its
// own first.
Status checkViewerOptions(const ViewerOptions& options);

// Runs the viewer until Esc / the window is closed / exitAfterFrames. The
// starting and home camera is the first of the play path (if given) or of
// `defaultPath`; its fov and near/far planes are used throughout. Returns 0,
// or prints "hybridwalk: error: ..." to stderr and returns 1 (no display, GL
// failure, no context for the keyframe worker, unreadable path, unwritable
// screenshot or statistics file).
int runViewer(const scenes::Scene& scene, const scenes::CameraPath& defaultPath,
              const ViewerOptions& options);

}  // namespace hw::app
