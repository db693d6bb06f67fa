#pragma once
// Keyframe: what the geometry renderer hands to the LOD builder (Zheng et al.
// 1999 §1.1): the camera, the colour image and the depth buffer as z' (eq. 2).
#include <cstdint>

#include "core/camera.h"
#include "core/image.h"

namespace hw::keyframe {

struct Keyframe {
  Camera camera;
  DepthMode depthMode = DepthMode::Fixed24;
  Image<Rgba8> colour;          // row 0 = top
  // z' in 2^24 units (eq. 2) whatever the depth mode; exact integers in
  // Fixed24 mode. Empty pixels hold kZPrimeScale (the far plane).
  Image<double> zPrime;
  Image<float> eyeZ;            // distance along W; 0 where empty
  Image<std::uint8_t> covered;  // 1 where something was drawn, 0 = empty
};

}  // namespace hw::keyframe
