#pragma once
// PFM (portable float map) for single-channel float images: the depth half of
// DESIGN.md "Keyframe export". Header "Pf\n<w> <h>\n-1.0\n" (negative scale =
// little-endian), then w·h float32 with rows BOTTOM to TOP (PFM convention),
// so our row 0 (top) is the last row in the file.
#include <string>
#include <string_view>

#include "core/image.h"
#include "core/result.h"

namespace hw {

// Bytes of a little-endian single-channel PFM of `image` (any size ≥ 1×1;
// values, including NaN/inf, stored bit-exactly). Precondition: not empty.
std::string encodePfm(const Image<float>& image);

// Decodes PFM bytes. Accepts "Pf" with either scale sign (negative =
// little-endian, positive = big-endian) and returns row 0 = top. Errors name
// `source`: 3-channel "PF" ("expected 1 channel"), a bad magic, missing or
// non-numeric fields, dimensions outside [1, kPfmMaxSide], a zero or
// non-finite scale, and a pixel block that is not exactly w·h·4 bytes
// (expected vs got). Never reads past `bytes`.
Result<Image<float>> decodePfm(std::string_view bytes, const std::string& source);

// Writes atomically (writeFileAtomic); an empty image is an error.
Status writePfm(const std::string& path, const Image<float>& image);
Result<Image<float>> readPfm(const std::string& path);

// Largest width or height readPfm accepts (bounds the allocation a corrupt
// header can ask for).
constexpr int kPfmMaxSide = 1 << 16;

}  // namespace hw
