#pragma once
// Quad validation: does each leaf quad of a keyframe's mesh warp to where the
// keyframe's own pixels reproject? Every covered pixel of a leaf is
// unprojected twice at its centre — at its own depth (the per-pixel
// reprojection, what a per-pixel view synthesizer draws) and at the quad's
// depth there (what the backward warp of Zheng et al. 1999 §2 draws) — and
// both points are projected into target cameras; the distance between the
// two image positions is the quad's reprojection error in pixels. The two
// points lie on one ray of the keyframe, so the error is zero at the
// keyframe's own view and grows with the parallax (docs/quad-validation.md).
#include <span>
#include <vector>

#include "core/camera.h"
#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"

namespace hw::keyframe {

struct QuadValidationOptions {
  // A quad is flagged when at least minBadPixels of its pixels reproject more
  // than tolerancePx (target pixels) away from the quad's point on the same
  // keyframe ray, in some target. Both finite, tolerancePx > 0,
  // minBadPixels >= 1 (checked).
  double tolerancePx = 1.0;
  int minBadPixels = 1;
};

// One quad's result; `quad` indexes mesh.quads.
struct QuadCheck {
  int quad = -1;
  // Largest reprojection error over the quad's pixels and the targets
  // (target pixels; 0 when no pixel projected into any target).
  double maxErrorPx = 0;
  int worstTarget = -1;        // index into targets; -1: none
  int worstX = -1, worstY = -1;  // keyframe pixel of maxErrorPx
  int badPixels = 0;           // pixels over tolerancePx in at least one target
  // View-independent: max over the pixels of fx·|1/z_pixel − 1/z_quad|, the
  // error in keyframe pixels per scene unit of camera translation across the
  // ray (the quantity LodOptions::tauParallaxPx bounds per pixel of Δ²).
  double parallaxPxPerUnit = 0;
  bool flagged = false;
};

struct QuadValidation {
  std::vector<QuadCheck> quads;  // one per mesh quad, in mesh order
  int flagged = 0;               // quads with flagged == true
  long long badPixels = 0;       // Σ QuadCheck::badPixels
  long long checkedPixels = 0;   // pixel × target pairs compared
  double maxErrorPx = 0;         // over all quads
  int worstQuad = -1;            // index of the quad with maxErrorPx (-1: none)
  double maxParallaxPxPerUnit = 0;
};

// Compares `mesh` (built from `keyframe`) with the keyframe's pixels at each
// target camera. A pixel counts in a target when its own point lies in front
// of the target's near plane and projects inside the target image; the
// quad's point is then projected too, and one in front of the near plane
// projects to an error of +inf (it cannot be drawn where the pixel is).
// Occlusion in the target is ignored: a disagreement hidden behind other
// geometry there is still reported. Pixel depth comes from keyframe.eyeZ
// when it is set, else from zPrime (eq. 2). Preconditions (checked): mesh
// and keyframe of the same size; every quad inside the image; options valid.
QuadValidation validateQuads(const Keyframe& keyframe, const QuadMesh& mesh,
                             std::span<const Camera> targets,
                             const QuadValidationOptions& options = {});

}  // namespace hw::keyframe
