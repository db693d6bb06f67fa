#pragma once
// File output that never leaves a half-written file: write to a temporary
// name beside the target, then rename over it. PNG through stb.
#include <cstdint>
#include <string>
#include <string_view>

#include "core/image.h"
#include "core/result.h"

namespace hw {

// Refuses (before writing) a path that is a device, FIFO or socket
// (checkOutputPath); the temporary is removed on error and on SIGINT/SIGTERM.
Status writeFileAtomic(const std::string& path, std::string_view bytes);
// Regular files only, at most `maxBytes` (core/safe_io.h: readRegularFile).
Result<std::string> readFile(const std::string& path, std::uint64_t maxBytes = 2ull << 30);

// What readPng accepts: decoded size is checked from the header before
// decoding. The defaults admit anything the camera-path sizes allow.
struct ImageLimits {
  int minSide = 1;
  int maxSide = 16384;
  std::uint64_t maxPixels = 64ull << 20;          // 64 Mi pixels: 256 MiB decoded
  std::uint64_t maxFileBytes = 512ull << 20;      // compressed bytes read
  std::string minSideReason;                      // appended when a side is too small
};

// Textures of scenes (not images the metrics compare). Sides above
// maxTextureSize() (--max-texture-size, default 8192) are box-downscaled by an
// integer factor, with *warning set; images of more than
// max(8192, maxTextureSize())² pixels are not decoded at all (error), so a
// small compressed file cannot ask for gigabytes. The header is read before
// anything is allocated; the decoded pixels are held once.
void setMaxTextureSize(int px);
int maxTextureSize();
// The 8192 of the decode budget above (tests and the fuzz target lower it).
void setTextureDecodeBudgetSide(int px);
Result<Image<Rgba8>> decodeTexture(const void* bytes, std::size_t size, const std::string& what,
                                   std::string* warning);
// readFile + decodeTexture.
Result<Image<Rgba8>> readTexture(const std::string& path, std::string* warning);

Status writePng(const std::string& path, const Image<Rgba8>& image);
Result<Image<Rgba8>> readPng(const std::string& path, const ImageLimits& limits = {});
// PNG of a single-channel image, values mapped [lo, hi] → [0, 255].
Status writePngGray(const std::string& path, const Image<float>& image, float lo, float hi);

// Creates `dir` (and parents) and checks it is writable.
Status ensureWritableDir(const std::string& dir);

}  // namespace hw
