#pragma once
// Layer: one keyframe's quad mesh warped to the current camera (Zheng et al.
// 1999 §2.1): colour, which pixels it covers, and their depth there.
#include <cstdint>

#include "core/image.h"

namespace hw::warp {

// eyeZ of pixels filled by the sky backdrop (points at infinity), kept
// finite so that no buffer holds Inf.
constexpr float kSkyEyeZ = 1.0e30f;

// The alpha a fused pair (Warper::warpPair) writes per pixel on the GPU, from
// which it derives Layer::coverage and Layer::largeQuad: 0 where neither
// layer covers; foreground 255, background 254, and 2 lower for pixels of
// large leaves (WarpOptions::markLargeQuads).
constexpr std::uint8_t kAlphaForeground = 255, kAlphaBackground = 254, kAlphaLargeForeground = 253,
                       kAlphaLargeBackground = 252;

struct Layer {
  Image<Rgba8> colour;          // row 0 = top
  Image<std::uint8_t> coverage; // non-zero where a quad covers the pixel (Warper::warpPair:
                                // 1 = foreground layer, 2 = background layer)
  Image<float> eyeZ;            // distance along the current camera's W; 0 where not
                                // covered, kSkyEyeZ for the sky backdrop
  // 1 where the pixel was drawn from a subdivision candidate: a leaf larger
  // than one cell (WarpOptions::subdivideCellPx), the leaves Subdivision::
  // Uniform cuts, whatever the mode; 0 elsewhere (sky, small leaves, empty).
  // Empty (0×0) when WarpOptions::markLargeQuads is off.
  Image<std::uint8_t> largeQuad;
};

}  // namespace hw::warp
