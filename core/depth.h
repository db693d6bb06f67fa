#pragma once
// Raw depth-buffer values → z' (eq. 2 of Zheng et al. 1999, in 2^24 units)
// and eye-space distance, for the three depth modes (DESIGN.md "Depth z'").
// Rows are flipped: GL row 0 is the bottom, Image row 0 the top.
#include <cstdint>

#include "core/camera.h"
#include "core/image.h"

namespace hw {

// `raw` points to width*height values in GL row order: uint32 (Fixed24 read
// as GL_UNSIGNED_INT; the top 24 bits are the depth) or float (Float32 /
// Float32Reversed). Empty pixels (at the clear value: far for standard, 0 for
// reversed) get zPrime = kZPrimeScale, eyeZ = 0, covered = 0. Non-finite
// values are treated as empty. Output images are resized if needed.
void convertDepth(const void* raw, int width, int height, DepthMode mode, double nearPlane,
                  double farPlane, Image<double>& zPrime, Image<float>& eyeZ,
                  Image<std::uint8_t>& covered);

}  // namespace hw
