#pragma once
// The in-between frame (Zheng et al. 1999 §2.2): the two bracketing
// keyframes' quad meshes backward-warped to the frame's camera, the nearer
// keyframe in front, composed with the previous frame where both miss, and
// near objects drawn as geometry on top (§3). One function for the walk, the
// viewer and the library: the same pair, camera and options give the same
// frame bit for bit wherever it is drawn.
#include <cstdint>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/image.h"
#include "core/result.h"
#include "gapfill/compose.h"
#include "gapfill/fallback.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe.h"
#include "warp/layer.h"
#include "warp/warper.h"

namespace hw::session {

struct InBetweenOptions {
  gapfill::ComposeOptions compose;  // the paper's overlay, the depth merge or the blend
  // Both layers in one render target, composed on the GPU by the overlay rule
  // (Warper::warpPair); off = the paper's two layers read back and composed
  // on the CPU. The depth merge and the blend always use two layers (the
  // fused pass draws the background only where the foreground left pixels
  // empty, so neither could see both): fusedLayers is ignored with them.
  bool fusedLayers = true;
  // No background layer when the foreground covers every pixel; the frame is
  // bit-identical. Ignored by the blend, which needs the background wherever
  // it covers.
  bool skipBackground = true;
  // No previous-frame pass when the layers leave no holes (fused: the frame is
  // the layer image itself); the frame is bit-identical.
  bool skipPrevious = true;
  // Near objects (§3): the scene clusters within this distance (scene units)
  // of the frame's eye or of its keyframes' eyes are drawn as geometry into
  // the frame, composed by depth (NearGeometry). 0 = off.
  double nearDistance = 0;
  // What fills the pixels neither layer covers: the same pixel of the
  // previous frame (the paper's), or the previous frame reprojected with its
  // depth (gapfill/fallback.h; frames then carry Frame::eyeZ and camera).
  gapfill::Fallback fallback = gapfill::Fallback::Copy;

  bool fused() const { return fusedLayers && compose.mode == gapfill::ComposeMode::Overlay; }
  bool skipsBackground() const {
    return skipBackground && compose.mode != gapfill::ComposeMode::Blend;
  }
  bool reprojects() const { return fallback == gapfill::Fallback::Reproject; }
  // Whether the warper must write Layer::eyeZ for these options.
  bool needsEyeZ() const {
    return compose.mode != gapfill::ComposeMode::Overlay || nearDistance > 0 || reprojects();
  }
};

// What one in-between frame did and cost (ms).
struct InBetweenStats {
  bool fused = false;
  bool previousSkipped = false;
  bool backgroundDrawn = false;  // false: skipped (covered, or no background given)
  int foregroundUncovered = 0;  // pixels the foreground layer left empty
  int backgroundCulled = 0;     // fused: background quads left out (WarpOptions::cullBackground)
  int quadsForeground = 0, quadsBackground = 0;
  double warpAMs = 0, warpBMs = 0;          // fused: draws; separate: draw + readback
  double warpADrawMs = 0, warpBDrawMs = 0;  // separate only
  double readbackMs = 0;
  double cullMs = 0;  // fused, first frame of a pair: deciding the culled quads
  double composeMs = 0;
  double nearMs = -1, nearDrawMs = 0;  // -1: no near geometry this frame
  // The fallback: holes filled from the reprojected previous frame, and from
  // its same pixel where reprojection left nothing (Fallback::Reproject);
  // its time (reprojection + fill), in composeMs too. -1: not run.
  int reprojectedPixels = 0, copiedPixels = 0;
  double fallbackMs = -1;
  bool backgroundSkipped() const { return !backgroundDrawn; }
  int quads() const { return quadsForeground + quadsBackground; }
  double warpMs() const { return fused ? warpAMs + warpBMs + readbackMs : warpAMs + warpBMs; }
};

// A fused pair's draw (Warper::warpPair or warpPairOnGpu) into the frame's
// stats: what was drawn, skipped and culled, and its times.
void setPairStats(const warp::PairStats& ps, InBetweenStats& st);

// The near objects of a frame: drawn by `renderer` at the frame's camera, the
// scene clusters (scenes/clusters.h) within the options' distance D of the
// frame's own eye or of any of `eyes` (the eyes of the keyframes it warps).
// The rule that keeps every frame whole: a keyframe leaves out the clusters
// within D of its own eye (RenderOptions::keyframeExcludeNear = D), and every
// frame that warps it draws them, since its eye is among `eyes`; the clusters
// within D of the frame's eye are drawn too (its keyframes may hold them as
// well: drawn in front by depth, they replace the magnified warped view of
// what is right before the viewer). So the cost follows the triangles within
// D of three points, not the size of the meshes they belong to.
struct NearGeometry {
  keyframe::GeometryRenderer* renderer = nullptr;
  glm::dvec3 eyes[2];
  int eyeCount = 0;
};

// Owns the layers and scratch images so that frames after the first allocate
// nothing (their size is kept).
class InBetweenStep {
 public:
  explicit InBetweenStep(const InBetweenOptions& options) : opt_(options) {}
  const InBetweenOptions& options() const { return opt_; }

  // Draws the frame at `cam` from `foreground` (the keyframe whose eye is
  // nearer: gapfill::chooseForeground) and `background` (null: one layer),
  // then `previous` (null for the first frame; must not be `&frame`) where
  // both miss, then near objects when `near` is given and nearDistance > 0.
  // With the reprojected fallback `previous` must carry its eyeZ and camera
  // (a frame of this step, or setKeyframeDepth; checked), and `frame` gets
  // its own.
  // Errors: GL failures from the warper or the renderer.
  Status draw(warp::Warper& warper, const warp::WarpSource& foreground,
              const warp::WarpSource* background, const Camera& cam,
              const gapfill::Frame* previous, const NearGeometry* near, gapfill::Frame& frame,
              InBetweenStats& stats);

  // Near objects put in front of `frame` wherever they are nearer than
  // `behindZ` (eye z per pixel; 0 or kSkyEyeZ = nothing there; empty image =
  // nothing anywhere); holes they cover stop being holes. Also used on a
  // displayed keyframe (with its own eye z).
  Status drawNear(const NearGeometry& near, const Camera& cam, const Image<float>& behindZ,
                  gapfill::Frame& frame, InBetweenStats& stats);

  // The layers of the last draw: A = foreground (fused: both layers, composed),
  // B = background (separate layers only).
  warp::Layer& layerA() { return layerA_; }
  warp::Layer& layerB() { return layerB_; }

  // Forgets that pixel p came from a large leaf (something else drew it).
  void clearLargeQuad(std::size_t p);

 private:
  // The reprojected fallback: frame.camera = cam, and the pixels compose()
  // left unfilled from `previous` reprojected (gapfill::fillHoles).
  Status fillFromPrevious(const Camera& cam, const gapfill::Frame* previous,
                          gapfill::Frame& frame, InBetweenStats& st);

  InBetweenOptions opt_;
  warp::Layer layerA_, layerB_;
  Image<Rgba8> nearColour_;
  Image<float> nearEyeZ_;
  Image<std::uint8_t> nearCovered_;
  gapfill::Frame reprojected_;  // the previous frame seen from this frame's camera
};

// A frame that is a keyframe image, or a geometry render, shown as it is (no
// holes, nothing older). `colour` may be frame.colour itself (rendered in place).
void showKeyframe(const Image<Rgba8>& colour, gapfill::Frame& frame);
// The shown keyframe's depth and camera (for the reprojected fallback of the
// next frame): frame.eyeZ = its eyeZ, empty pixels (nothing drawn: sky) at
// warp::kSkyEyeZ. Precondition (checked): frame.colour has its size.
void setKeyframeDepth(const keyframe::Keyframe& keyframe, gapfill::Frame& frame);

}  // namespace hw::session
