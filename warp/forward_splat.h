#pragma once
// A CPU forward splat of a point-sampled image into another camera: what
// the keyframe planner's low-resolution probes are warped with.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/image.h"
#include "warp/layer.h"

namespace hw::warp {

// An image with its camera, eye depth and coverage per pixel.
struct SplatSource {
  Camera camera;
  Image<Rgba8> colour;
  Image<float> eyeZ;
  Image<std::uint8_t> covered;
  // World point of a covered pixel's centre; unit view direction of an empty one.
  std::vector<glm::dvec3> point;
};

// Forward splat of `src` into `target` (same size): each covered pixel
// becomes a rectangle covering its projected footprint (from the projected
// neighbours, continuous depth only; clamped to 8 pixels per side),
// z-tested; empty pixels become a backdrop at infinity, like the GL warp's
// sky rectangles (eyeZ kSkyEyeZ, as there). Returns the mean |log2 area
// ratio| of the pixels that land in the frame (stretch).
double forwardSplat(const SplatSource& src, const Camera& target, Layer& out);

}  // namespace hw::warp
