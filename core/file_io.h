#pragma once
// File output that never leaves a half-written file: write to a temporary
// name beside the target, then rename over it. PNG through stb.
#include <string>
#include <string_view>

#include "core/image.h"
#include "core/result.h"

namespace hw {

Status writeFileAtomic(const std::string& path, std::string_view bytes);
Result<std::string> readFile(const std::string& path);

Status writePng(const std::string& path, const Image<Rgba8>& image);
Result<Image<Rgba8>> readPng(const std::string& path);
// PNG of a single-channel image, values mapped [lo, hi] → [0, 255].
Status writePngGray(const std::string& path, const Image<float>& image, float lo, float hi);

// Creates `dir` (and parents) and checks it is writable.
Status ensureWritableDir(const std::string& dir);

}  // namespace hw
