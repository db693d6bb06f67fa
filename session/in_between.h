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
#include "keyframe/geometry_renderer.h"
#include "warp/layer.h"
#include "warp/warper.h"

namespace hw::session {

struct InBetweenOptions {
  gapfill::ComposeOptions compose;  // the paper's overlay, or the depth merge
  // Both layers in one render target, composed on the GPU by the overlay rule
  // (Warper::warpPair); off = the paper's two layers read back and composed
  // on the CPU. The depth merge always uses two layers.
  bool fusedLayers = true;
  // No background layer when the foreground covers every pixel; the frame is
  // bit-identical.
  bool skipBackground = true;
  // No previous-frame pass when the layers leave no holes (fused: the frame is
  // the layer image itself); the frame is bit-identical.
  bool skipPrevious = true;
  // Near objects (§3): meshes within this distance (scene units) of the
  // keyframes' eyes are drawn as geometry into the frame, composed by depth.
  // 0 = off.
  double nearDistance = 0;

  bool fused() const { return fusedLayers && compose.mode == gapfill::ComposeMode::Overlay; }
  // Whether the warper must write Layer::eyeZ for these options.
  bool needsEyeZ() const {
    return compose.mode == gapfill::ComposeMode::DepthMerge || nearDistance > 0;
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
  bool backgroundSkipped() const { return !backgroundDrawn; }
  int quads() const { return quadsForeground + quadsBackground; }
  double warpMs() const { return fused ? warpAMs + warpBMs + readbackMs : warpAMs + warpBMs; }
};

// The near objects of a frame: drawn by `renderer` at the frame's camera, the
// meshes within the options' distance of any of `eyes` (the keyframes').
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
  InBetweenOptions opt_;
  warp::Layer layerA_, layerB_;
  Image<Rgba8> nearColour_;
  Image<float> nearEyeZ_;
  Image<std::uint8_t> nearCovered_;
};

// A frame that is a keyframe image, or a geometry render, shown as it is (no
// holes, nothing older). `colour` may be frame.colour itself (rendered in place).
void showKeyframe(const Image<Rgba8>& colour, gapfill::Frame& frame);

}  // namespace hw::session
