#include "core/pfm.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/check.h"
#include "core/file_io.h"

namespace hw {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Next whitespace-separated header token starting at *pos; empty at the end.
std::string_view nextToken(std::string_view s, std::size_t* pos) {
  std::size_t i = *pos;
  while (i < s.size() && isSpace(s[i])) ++i;
  const std::size_t b = i;
  while (i < s.size() && !isSpace(s[i]) && i - b < 64) ++i;
  *pos = i;
  return s.substr(b, i - b);
}

std::uint32_t byteSwap(std::uint32_t x) {
  return (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);
}

bool parseInt(std::string_view t, int* out) {
  const char* end = t.data() + t.size();
  auto [p, ec] = std::from_chars(t.data(), end, *out);
  return ec == std::errc() && p == end;
}

}  // namespace

std::string encodePfm(const Image<float>& image) {
  HW_CHECK(!image.empty());
  const int w = image.width(), h = image.height();
  std::string out = "Pf\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
  const std::size_t header = out.size();
  out.resize(header + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  char* dst = out.data() + header;
  for (int fileRow = 0; fileRow < h; ++fileRow) {
    const float* src = &image(0, h - 1 - fileRow);  // PFM: bottom row first
    for (int x = 0; x < w; ++x) {
      std::uint32_t bits = std::bit_cast<std::uint32_t>(src[x]);
      if constexpr (std::endian::native == std::endian::big) bits = byteSwap(bits);
      std::memcpy(dst, &bits, 4);
      dst += 4;
    }
  }
  return out;
}

Result<Image<float>> decodePfm(std::string_view bytes, const std::string& source) {
  auto fail = [&](const std::string& what) {
    return makeError(source + ": not a valid single-channel PFM: " + what);
  };
  std::size_t pos = 0;
  const std::string_view magic = nextToken(bytes, &pos);
  if (magic == "PF")
    return makeError(source + ": PFM has 3 channels (\"PF\"), expected 1 channel (\"Pf\")");
  if (magic != "Pf")
    return fail("expected magic \"Pf\", got \"" + std::string(magic.substr(0, 16)) + "\"");
  int w = 0, h = 0;
  const std::string_view tw = nextToken(bytes, &pos), th = nextToken(bytes, &pos);
  if (!parseInt(tw, &w) || !parseInt(th, &h))
    return fail("expected width and height, got \"" + std::string(tw.substr(0, 16)) + "\" \"" +
                std::string(th.substr(0, 16)) + "\"");
  if (w < 1 || h < 1 || w > kPfmMaxSide || h > kPfmMaxSide)
    return fail("dimensions " + std::to_string(w) + "x" + std::to_string(h) + " outside [1, " +
                std::to_string(kPfmMaxSide) + "]");
  const std::string ts(nextToken(bytes, &pos));
  char* end = nullptr;
  const double scale = ts.empty() ? 0.0 : std::strtod(ts.c_str(), &end);
  if (ts.empty() || end != ts.c_str() + ts.size() || !std::isfinite(scale) || scale == 0.0)
    return fail("expected a non-zero scale (negative = little-endian), got \"" + ts.substr(0, 16) +
                "\"");
  // Exactly one whitespace byte separates the header from the pixels.
  if (pos >= bytes.size() || !isSpace(bytes[pos]))
    return fail("header does not end with a newline after the scale");
  ++pos;
  const bool littleEndian = scale < 0.0;
  const std::size_t expected = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4;
  const std::size_t got = bytes.size() - pos;
  if (got != expected)
    return makeError(source + ": PFM " + std::to_string(w) + "x" + std::to_string(h) + " is " +
                     (got < expected ? "truncated" : "too long") + ": expected " +
                     std::to_string(expected) + " bytes of pixel data, got " + std::to_string(got));
  const bool swap = littleEndian != (std::endian::native == std::endian::little);
  Image<float> img(w, h);
  const char* src = bytes.data() + pos;
  for (int fileRow = 0; fileRow < h; ++fileRow) {
    float* dst = &img(0, h - 1 - fileRow);
    for (int x = 0; x < w; ++x) {
      std::uint32_t bits;
      std::memcpy(&bits, src, 4);
      src += 4;
      if (swap) bits = byteSwap(bits);
      dst[x] = std::bit_cast<float>(bits);
    }
  }
  return img;
}

Status writePfm(const std::string& path, const Image<float>& image) {
  if (image.empty()) return makeError("cannot write " + path + ": image is empty");
  return writeFileAtomic(path, encodePfm(image));
}

Result<Image<float>> readPfm(const std::string& path) {
  auto bytes = readFile(path);
  if (!bytes) return bytes.error();
  return decodePfm(*bytes, path);
}

}  // namespace hw
