#pragma once
// Composition of the two warped keyframe layers and the previous frame
// (Zheng et al. 1999 §2.2; DESIGN.md "Composition"), with an optional
// depth-aware merge in the spirit of Pulli et al.'s soft z-buffer.
#include <cstdint>
#include <glm/glm.hpp>

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
};
const char* composeModeName(ComposeMode m);  // "overlay", "depth-merge"
// False (and *out unchanged) for an unknown name or null s.
bool parseComposeMode(const char* s, ComposeMode* out);

struct ComposeOptions {
  ComposeMode mode = ComposeMode::Overlay;
  float depthTolerance = 0.02f;  // relative to the foreground's eyeZ, in [0, 1); DepthMerge only
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
  double holeFractionBefore = 0.0;  // fraction of pixels with holesBefore = 1
  double holeFractionAfter = 0.0;   // fraction of pixels still unfilled (valid = 0)
  int fromForeground = 0;           // pixel counts; they sum to width·height
  int fromBackground = 0;
  int fromPrevious = 0;  // the paper's holes, filled from the last frame
  int unfilled = 0;
};

// Unfilled pixels (no layer, no valid previous pixel) get this colour and
// valid = 0. Black, not a loud marker such as magenta: a marker would dominate
// the PSNR of a frame with a few unfilled pixels; `valid`/`unfilled` say where
// they are.
constexpr Rgba8 kUnfilledColour{0, 0, 0, 255};

// Per pixel: foreground where foreground.coverage != 0; else background where
// it covers; else previous->colour where previous->valid != 0; else unfilled.
// With DepthMerge, where both layers cover, see ComposeMode::DepthMerge.
//
// Preconditions (checked): foreground.colour and .coverage have one size;
// background (if given) and previous (if given) have that size too; with
// DepthMerge both layers' eyeZ have that size as well (eyeZ is not read in
// Overlay mode, nor without a background); `previous` (null for the first
// frame) is not `&out`: double-buffer frames instead. Not checked, per pixel:
// eyeZ > 0 where covered (the sky backdrop has warp::kSkyEyeZ, so any surface
// of the other layer beats it).
// Allocation-free when `out` already has the layers' size: its images are
// resized only when their size differs.
void compose(const warp::Layer& foreground, const warp::Layer* background, const Frame* previous,
             const ComposeOptions& options, Frame& out);

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
