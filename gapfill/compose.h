#pragma once
// Composition of the two warped keyframe layers and the previous frame
// (Zheng et al. 1999 §2.2; DESIGN.md "Composition"), with an optional
// depth-aware merge in the spirit of Pulli et al.'s soft z-buffer, and a
// two-view blend weighted per pixel by how sharply each keyframe sees the
// surface (after Buehler et al. 2001, unstructured lumigraph rendering).
#include <cstdint>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/image.h"
#include "warp/layer.h"

namespace hw::gapfill {

enum class ComposeMode {
  // The paper's rule: foreground where it covers, else background.
  Overlay,
  // Where both layers cover, the nearer one (by eyeZ) wins, except that a
  // background only beats the foreground when it is nearer by more than the
  // relative tolerance: zBackground < (1 − depthTolerance) · zForeground.
  // Elsewhere as Overlay.
  DepthMerge,
  // Where both layers cover with consistent depth (|zF − zB| ≤ depthTolerance
  // · min(zF, zB)), a weighted mean of the two colours: each keyframe's
  // penalty is the angle (radians) between its ray to the surface point and
  // the frame's ray, plus how much farther from the point it is than the
  // frame's eye (max(0, dKey/dFrame − 1): its magnification); the weights are
  // exp(−penalty / blendSoftness). Where both cover with inconsistent depth,
  // the nearer one. Elsewhere as Overlay. Needs BlendViews.
  Blend,
};
const char* composeModeName(ComposeMode m);  // "overlay", "depth-merge", "blend"
// False (and *out unchanged) for an unknown name or null s.
bool parseComposeMode(const char* s, ComposeMode* out);

struct ComposeOptions {
  ComposeMode mode = ComposeMode::Overlay;
  // Relative to the foreground's eyeZ (DepthMerge) or to the nearer eyeZ
  // (Blend: the consistency test), in [0, 1); not read by Overlay.
  float depthTolerance = 0.02f;
  // Blend: penalty difference (radians, or relative magnification) over which
  // the weights change by a factor e; > 0. Smaller = closer to picking the
  // sharper view; 0.05 rad ≈ 2.9°.
  float blendSoftness = 0.05f;
};

// Where the frame and the two keyframes were seen from (ComposeMode::Blend).
struct BlendViews {
  Camera camera;                 // the frame's camera (the layers' size)
  glm::dvec3 foregroundEye{0.0};  // the foreground layer's keyframe eye
  glm::dvec3 backgroundEye{0.0};
};

// One displayed frame and what composition did to get it. Images are all the
// layers' size; masks hold 0/1.
struct Frame {
  Image<Rgba8> colour;              // row 0 = top; unfilled pixels are opaque black
  Image<std::uint8_t> holesBefore;  // 1 = neither layer covers
  Image<std::uint8_t> valid;        // 1 = has content after the previous-frame fill
  // Frames each pixel has been carried over from the previous frame (0 = from
  // a keyframe layer or re-rendered; gapfill/age.h). Empty unless the walk
  // tracks ages; compose() does not touch it.
  Image<std::uint8_t> age;
  // Eye z along `camera`'s W of each pixel's surface (0 = unknown, e.g.
  // unfilled; warp::kSkyEyeZ = at infinity) and the camera the frame was seen
  // from. Empty unless the reprojected fallback is on (gapfill/fallback.h);
  // compose() does not touch either.
  Image<float> eyeZ;
  Camera camera;
  double holeFractionBefore = 0.0;  // fraction of pixels with holesBefore = 1
  double holeFractionAfter = 0.0;   // fraction of pixels still unfilled (valid = 0)
  int fromForeground = 0;           // pixel counts; they sum to width·height
  int fromBackground = 0;
  int fromPrevious = 0;  // the paper's holes, filled from the last frame
  int unfilled = 0;
  // Blend: pixels mixed from both layers (counted also in fromForeground or
  // fromBackground, whichever had the larger weight); 0 in other modes.
  int blended = 0;
};

// Unfilled pixels (no layer, no valid previous pixel) get this colour and
// valid = 0. Black, not a loud marker such as magenta: a marker would dominate
// the PSNR of a frame with a few unfilled pixels; `valid`/`unfilled` say where
// they are.
constexpr Rgba8 kUnfilledColour{0, 0, 0, 255};

// Per pixel: foreground where foreground.coverage != 0; else background where
// it covers; else previous->colour where previous->valid != 0; else unfilled.
// With DepthMerge or Blend, where both layers cover, see ComposeMode.
//
// Preconditions (checked): foreground.colour and .coverage have one size;
// background (if given) and previous (if given) have that size too; with
// DepthMerge both layers' eyeZ have that size as well (eyeZ is not read in
// Overlay mode, nor without a background); `previous` (null for the first
// frame) is not `&out`: double-buffer frames instead. Not checked, per pixel:
// eyeZ > 0 where covered (the sky backdrop has warp::kSkyEyeZ, so any surface
// of the other layer beats it).
// With Blend and a background, `views` must be given and its camera have the
// layers' size (checked), and blendSoftness > 0 (checked).
// Allocation-free when `out` already has the layers' size: its images are
// resized only when their size differs.
void compose(const warp::Layer& foreground, const warp::Layer* background, const Frame* previous,
             const ComposeOptions& options, const BlendViews* views, Frame& out);
inline void compose(const warp::Layer& foreground, const warp::Layer* background,
                    const Frame* previous, const ComposeOptions& options, Frame& out) {
  compose(foreground, background, previous, options, nullptr, out);
}

// The weight of the background layer at a surface point seen by the frame
// along the ray `ray` (world units, from the frame's eye to the point), with
// the keyframe eyes relative to the frame's eye; in [0, 1]. A point at
// infinity (warp::kSkyEyeZ) has no parallax: 0.5. Used by Blend per pixel.
float blendBackgroundWeight(const glm::vec3& ray, const glm::vec3& foregroundEyeOffset,
                            const glm::vec3& backgroundEyeOffset, float softness);

// Which of the two bracketing keyframes is the foreground layer A: 0 for the
// keyframe at eyeA, 1 for eyeB, whichever eye is nearer to `eye`. A tie
// (|dA − dB| ≤ kForegroundTieRelTol · (dA + dB)) returns 0, the earlier
// keyframe: exactly midway the "nearer" test is otherwise decided by rounding,
// and the choice changes the picture (DESIGN.md: 25.3 vs 32.7 dB on a real
// corridor). Choosing the earlier one is deterministic and keeps the layer the
// frames just before the midpoint used when walking from A towards B.
constexpr double kForegroundTieRelTol = 1e-9;
int chooseForeground(const glm::dvec3& eye, const glm::dvec3& eyeA, const glm::dvec3& eyeB);

}  // namespace hw::gapfill
