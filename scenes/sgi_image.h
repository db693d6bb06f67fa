#pragma once
// SGI images (.rgb/.rgba/.sgi/.bw), the texture format of TORCS tracks.
#include <string>

#include "core/image.h"
#include "core/result.h"

namespace hw::scenes {

// True when `bytes` start with the SGI magic (474).
bool isSgiImage(const std::string& bytes);

// Decodes an SGI image (.rgb/.rgba/.bw: 1–4 channels, 8 bits, verbatim or
// RLE). Grey → RGB, missing alpha → 255; row 0 = top. Errors name `what`.
Result<Image<Rgba8>> decodeSgiImage(const std::string& bytes, const std::string& what);

}  // namespace hw::scenes
