// libFuzzer target for the image decoders behind scene textures
// (core/file_io.h decodeTexture: stb's PNG, JPEG, TGA, BMP, GIF, PSD, HDR,
// PIC, PNM): any bytes must give an image no larger than the texture limit
// or an error naming the input, never a crash or an allocation beyond the
// decode budget.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/file_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hw::setMaxTextureSize(256);
  hw::setTextureDecodeBudgetSide(1024);  // keeps each run fast: at most 4 MiB decoded
  std::string warning;
  auto img = hw::decodeTexture(data, size, "fuzz.img", &warning);
  if (!img.ok()) {
    if (img.error().message.find("fuzz.img") == std::string::npos) std::abort();
    return 0;
  }
  if (img->width() < 1 || img->height() < 1 || img->width() > 256 || img->height() > 256) {
    std::fprintf(stderr, "texture_fuzz: %dx%d past the 256 limit\n", img->width(), img->height());
    std::abort();
  }
  return 0;
}
