#pragma once
// CPU counterpart of the GL warp: reprojects sample points of each quad into
// a target camera (the paper's Q = H_{E'}⁻¹ H_E P), used to test the GL pass.
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"

namespace hw::warp {

struct WarpSample {
  double sourceU = 0, sourceV = 0;  // keyframe image position
  double targetU = 0, targetV = 0;  // position in the target image
  double targetZ = 0;               // depth along the target camera's W
  Rgba8 colour;                     // keyframe colour at the source pixel
};

// For every quad, samples at the centres of an n×n grid of its keyframe pixels
// (fewer for small quads), reprojected into `target`. Samples behind the
// target eye are dropped.
std::vector<WarpSample> reprojectSamples(const keyframe::Keyframe& keyframe,
                                         const keyframe::QuadMesh& mesh, const Camera& target,
                                         int samplesPerAxis);

}  // namespace hw::warp
