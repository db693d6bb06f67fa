#include "scenes/sgi_image.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <vector>

namespace hw::scenes {

bool isSgiImage(const std::string& bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x01 &&
         static_cast<unsigned char>(bytes[1]) == 0xDA;
}

Result<Image<Rgba8>> decodeSgiImage(const std::string& b, const std::string& what) {
  auto u8 = [&](std::size_t o) { return static_cast<unsigned>(static_cast<unsigned char>(b[o])); };
  auto u16 = [&](std::size_t o) { return (u8(o) << 8) | u8(o + 1); };
  auto u32 = [&](std::size_t o) { return (u16(o) << 16) | u16(o + 2); };
  if (b.size() < 512 || !isSgiImage(b))
    return makeError(what + ": not an SGI image (expected magic 474 and a 512-byte header)");
  const unsigned storage = u8(2), bpc = u8(3);
  const unsigned xs = u16(6), ys = u16(8), zs = std::max(1u, u16(10));
  if (bpc != 1)
    return makeError(what + ": SGI image with " + std::to_string(bpc) +
                     " bytes per channel (only 1 is supported)");
  if (storage > 1) return makeError(what + ": unknown SGI storage " + std::to_string(storage));
  if (xs == 0 || ys == 0 || zs > 4)
    return makeError(what + ": bad SGI size " + std::to_string(xs) + "x" + std::to_string(ys) +
                     "x" + std::to_string(zs));
  std::vector<unsigned char> plane(static_cast<std::size_t>(xs) * ys * zs);
  if (storage == 0) {
    if (b.size() < 512 + plane.size()) return makeError(what + ": truncated SGI image");
    std::memcpy(plane.data(), b.data() + 512, plane.size());
  } else {
    const std::size_t rows = static_cast<std::size_t>(ys) * zs;
    if (b.size() < 512 + rows * 8) return makeError(what + ": truncated SGI RLE tables");
    for (std::size_t r = 0; r < rows; ++r) {
      std::size_t o = u32(512 + r * 4);
      const std::size_t len = u32(512 + rows * 4 + r * 4);
      if (o > b.size() || len > b.size() - o)
        return makeError(what + ": SGI RLE row " + std::to_string(r) + " outside the file");
      const std::size_t end = o + len;
      unsigned char* dst = plane.data() + r * xs;
      std::size_t x = 0;
      while (o < end) {
        const unsigned c = u8(o++);
        const unsigned count = c & 0x7F;
        if (count == 0) break;
        if (x + count > xs) return makeError(what + ": SGI RLE row overflows its width");
        if (c & 0x80) {
          if (end - o < count) return makeError(what + ": truncated SGI RLE run");
          std::memcpy(dst + x, b.data() + o, count);
          o += count;
        } else {
          if (o >= end) return makeError(what + ": truncated SGI RLE run");
          std::memset(dst + x, static_cast<int>(u8(o++)), count);
        }
        x += count;
      }
    }
  }
  Image<Rgba8> img(static_cast<int>(xs), static_cast<int>(ys));
  const std::size_t planeSize = static_cast<std::size_t>(xs) * ys;
  for (unsigned y = 0; y < ys; ++y)
    for (unsigned x = 0; x < xs; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * xs + x;  // SGI: row 0 = bottom
      auto ch = [&](unsigned z) { return plane[z * planeSize + i]; };
      Rgba8 p;
      if (zs <= 2) {
        p = Rgba8{ch(0), ch(0), ch(0), zs == 2 ? ch(1) : static_cast<unsigned char>(255)};
      } else {
        p = Rgba8{ch(0), ch(1), ch(2), zs == 4 ? ch(3) : static_cast<unsigned char>(255)};
      }
      img(static_cast<int>(x), static_cast<int>(ys - 1 - y)) = p;
    }
  return img;
}

}  // namespace hw::scenes
