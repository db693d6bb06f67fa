#pragma once
// Debug pictures of the LOD model: leaf outlines over the keyframe like Zheng
// et al. 1999 Plate I-A, and the Δ buffer (§1.2, eq. 3) on a log scale.
#include "core/image.h"
#include "keyframe/quad_mesh.h"

namespace hw::keyframe {

struct OverlayOptions {
  Rgba8 outline{0, 255, 0, 255};         // 1-px leaf outlines
  Rgba8 onePixelTint{255, 0, 255, 255};  // 1×1 leaves (discontinuities)
  float onePixelTintAmount = 0.6f;       // blend weight of the tint, [0, 1]
  float emptyDim = 0.3f;                 // pixels in no quad are scaled by this
};

// The keyframe colour with the mesh's leaves drawn on it. Each leaf gets its
// top row and left column outlined, plus its bottom row / right column where
// no other leaf continues beyond it, so adjacent leaves are separated by one
// pixel and every leaf is closed. Leaves must lie inside the image (checked);
// mesh.width/height must equal the colour's size (checked).
Image<Rgba8> drawQuadOverlay(const Image<Rgba8>& keyframeColour, const QuadMesh& mesh,
                             const OverlayOptions& options = {});

struct DeltaImageOptions {
  // Grey level = log2(1 + |Δ²|) / log2(1 + maxDelta): 0 black, maxDelta white.
  float maxDelta = 67108864.0f;         // 2^26: 4 × the z' range
  float tau = 0.0f;                     // > 0: pixels above τ are tinted orange
  Rgba8 empty{30, 30, 110, 255};        // kDeltaEmpty
  Rgba8 discontinuity{255, 0, 0, 255};  // kDeltaDiscontinuity (+inf)
};

// Visualises a Δ buffer (values as written by computeDeltaBuffer).
Image<Rgba8> deltaToImage(ImageView<const float> delta, const DeltaImageOptions& options = {});

}  // namespace hw::keyframe
