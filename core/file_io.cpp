#include "core/file_io.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "core/memory_budget.h"
#include "core/safe_io.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_FAILURE_USERMSG
#include <stb_image.h>
#include <stb_image_write.h>

namespace hw {

Status writeFileAtomic(const std::string& path, std::string_view bytes) {
  if (path.empty()) return makeError("cannot write an output to an empty path");
  HW_TRY(checkOutputPath(path));
  TemporaryFile tmpFile(path + ".tmp-" + std::to_string(::getpid()));
  const std::string& tmp = tmpFile.path();
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return makeError("cannot write " + path + ": " + std::strerror(errno));
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int werr = errno;
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !closed) {
    std::remove(tmp.c_str());
    return makeError("cannot write " + path + ": " + std::strerror(wrote ? errno : werr));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    return makeError("cannot rename " + tmp + " to " + path + ": " + std::strerror(e));
  }
  tmpFile.release();
  return {};
}

Result<std::string> readFile(const std::string& path, std::uint64_t maxBytes) {
  return readRegularFile(path, maxBytes);
}

static void appendBytes(void* ctx, void* data, int size) {
  static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<size_t>(size));
}

Status writePng(const std::string& path, const Image<Rgba8>& image) {
  if (image.empty()) return makeError("cannot write " + path + ": image is empty");
  std::string bytes;
  if (!stbi_write_png_to_func(appendBytes, &bytes, image.width(), image.height(), 4, image.data(),
                              image.width() * 4))
    return makeError("cannot encode PNG " + path);
  return writeFileAtomic(path, bytes);
}

Status writePngGray(const std::string& path, const Image<float>& image, float lo, float hi) {
  Image<Rgba8> out(image.width(), image.height());
  const float scale = hi > lo ? 255.0f / (hi - lo) : 0.0f;
  for (size_t i = 0; i < image.size(); ++i) {
    float v = image.data()[i];
    float t = std::isfinite(v) ? std::clamp((v - lo) * scale, 0.0f, 255.0f) : 255.0f;
    auto g = static_cast<std::uint8_t>(t + 0.5f);
    out.data()[i] = Rgba8{g, g, g, 255};
  }
  return writePng(path, out);
}

namespace {

// stb_image (libstb-dev 0.0~git20220908, stbi__parse_png_file) copies each
// IDAT chunk into its buffer with memcpy(idata + off, p, length) and only
// allocates that buffer for a non-empty chunk, so a PNG whose first IDAT is
// empty makes it call memcpy(NULL, p, 0): nothing is copied, but it is
// undefined behaviour and aborts the sanitized builds. An empty IDAT adds
// nothing to the image (the zlib stream is the concatenation of the IDAT
// data fields: PNG specification, 2nd edition, 11.2.4), so the decoders
// below drop such chunks first. Only the chunk framing is read (4-byte
// big-endian length, type, data, 4-byte CRC); the scan stops at IEND or at
// the first chunk that does not fit, and stb reports whatever is wrong with
// the rest. Returns false, leaving *out untouched, when there is no empty
// IDAT to drop.
bool dropEmptyPngIdat(const stbi_uc* bytes, std::size_t size, std::string* out) {
  static constexpr stbi_uc kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size < 8 || std::memcmp(bytes, kSignature, 8) != 0) return false;
  std::vector<std::pair<std::size_t, std::size_t>> drop;  // [begin, end) byte ranges
  std::size_t pos = 8;
  while (size - pos >= 8) {
    const std::uint32_t length =
        (std::uint32_t{bytes[pos]} << 24) | (std::uint32_t{bytes[pos + 1]} << 16) |
        (std::uint32_t{bytes[pos + 2]} << 8) | std::uint32_t{bytes[pos + 3]};
    const stbi_uc* type = bytes + pos + 4;
    if (length == 0 && std::memcmp(type, "IDAT", 4) == 0) {
      const std::size_t end = pos + std::min<std::size_t>(12, size - pos);  // CRC may be cut off
      drop.emplace_back(pos, end);
      pos = end;
      continue;
    }
    if (std::memcmp(type, "IEND", 4) == 0 || length > size - pos - 8 || size - pos - 8 - length < 4)
      break;
    pos += 12 + static_cast<std::size_t>(length);
  }
  if (drop.empty()) return false;
  out->clear();
  std::size_t from = 0;
  for (const auto& [begin, end] : drop) {
    out->append(reinterpret_cast<const char*>(bytes) + from, begin - from);
    from = end;
  }
  out->append(reinterpret_cast<const char*>(bytes) + from, size - from);
  return true;
}

// Width and height from a PNG's IHDR chunk. stb_image refuses an image over
// 2^24 a side or 2^30 bytes decoded as "not of any known type, or corrupt";
// the header says what it is, so a size can be refused as a size.
bool pngHeaderSize(const stbi_uc* b, std::size_t n, int* w, int* h) {
  static const stbi_uc kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n < 24 || std::memcmp(b, kSig, 8) != 0 || std::memcmp(b + 12, "IHDR", 4) != 0) return false;
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t(b[at]) << 24) | (std::uint32_t(b[at + 1]) << 16) |
           (std::uint32_t(b[at + 2]) << 8) | std::uint32_t(b[at + 3]);
  };
  const std::uint32_t pw = be32(16), ph = be32(20);
  if (pw == 0 || ph == 0 || pw > INT32_MAX || ph > INT32_MAX) return false;
  *w = static_cast<int>(pw);
  *h = static_cast<int>(ph);
  return true;
}

}  // namespace

Result<Image<Rgba8>> readPng(const std::string& path, const ImageLimits& limits) {
  auto bytes = readFile(path, limits.maxFileBytes);
  if (!bytes) return bytes.error();
  int w = 0, h = 0, comp = 0;
  if (bytes->size() > static_cast<std::size_t>(INT32_MAX))
    return makeError("cannot decode image " + path + ": larger than 2 GiB");
  std::string withoutEmptyIdat;
  if (dropEmptyPngIdat(reinterpret_cast<const stbi_uc*>(bytes->data()), bytes->size(),
                       &withoutEmptyIdat))
    bytes->swap(withoutEmptyIdat);
  // Header first: the decoded size is checked before anything is allocated.
  if (!stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(bytes->data()),
                             static_cast<int>(bytes->size()), &w, &h, &comp) &&
      !pngHeaderSize(reinterpret_cast<const stbi_uc*>(bytes->data()), bytes->size(), &w, &h))
    return makeError("cannot decode image " + path + ": " + stbi_failure_reason());
  if (w < limits.minSide || h < limits.minSide || w > limits.maxSide || h > limits.maxSide ||
      static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > limits.maxPixels)
    return makeError(path + ": image is " + std::to_string(w) + "x" + std::to_string(h) +
                     ", expected sides in [" + std::to_string(limits.minSide) + ", " +
                     std::to_string(limits.maxSide) + "] and at most " +
                     std::to_string(limits.maxPixels / 1000000) + " megapixels" +
                     (w < limits.minSide || h < limits.minSide ? limits.minSideReason : ""));
  stbi_uc* px = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes->data()),
                                      static_cast<int>(bytes->size()), &w, &h, &comp, 4);
  if (!px) return makeError("cannot decode image " + path + ": " + stbi_failure_reason());
  Image<Rgba8> img(w, h);
  std::memcpy(img.data(), px, static_cast<size_t>(w) * h * 4);
  stbi_image_free(px);
  return img;
}

namespace {
int gMaxTextureSize = 8192;
int gMinDecodeBudgetSide = 8192;
}  // namespace

void setTextureDecodeBudgetSide(int px) { gMinDecodeBudgetSide = std::max(1, px); }

void setMaxTextureSize(int px) { gMaxTextureSize = std::max(1, px); }
int maxTextureSize() { return gMaxTextureSize; }

Result<Image<Rgba8>> decodeTexture(const void* bytes, std::size_t size, const std::string& what,
                                   std::string* warning) {
  if (size == 0 || size > static_cast<std::size_t>(INT32_MAX))
    return makeError("cannot decode image " + what + ": empty or larger than 2 GiB");
  const auto* b = static_cast<const stbi_uc*>(bytes);
  std::string withoutEmptyIdat;
  if (dropEmptyPngIdat(b, size, &withoutEmptyIdat)) {
    b = reinterpret_cast<const stbi_uc*>(withoutEmptyIdat.data());
    size = withoutEmptyIdat.size();
  }
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(b, static_cast<int>(size), &w, &h, &comp) &&
      !pngHeaderSize(b, size, &w, &h))
    return makeError("cannot decode image " + what + ": " + stbi_failure_reason());
  const std::uint64_t budgetSide =
      static_cast<std::uint64_t>(std::max(gMinDecodeBudgetSide, gMaxTextureSize));
  const std::uint64_t pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
  if (w < 1 || h < 1 || pixels > budgetSide * budgetSide)
    return makeError(what + ": texture is " + std::to_string(w) + "x" + std::to_string(h) + " (" +
                     formatBytes(pixels * 4) + " decoded), over the decode budget of " +
                     std::to_string(budgetSide) + "x" + std::to_string(budgetSide) +
                     " pixels (--max-texture-size raises it); not decoded");
  // The full-size decode is charged before it is allocated; what the
  // downscale does not keep is given back.
  const std::uint64_t decodedBytes = pixels * 4;
  HW_TRY(chargeMemory(decodedBytes, what + ": texture " + std::to_string(w) + "x" +
                                        std::to_string(h) + " decoded",
                      "--max-memory raises it, --max-texture-size lowers what is kept"));
  stbi_uc* px = stbi_load_from_memory(b, static_cast<int>(size), &w, &h, &comp, 4);
  if (!px) {
    releaseMemory(decodedBytes);
    return makeError("cannot decode image " + what + ": " + stbi_failure_reason());
  }
  const int f = std::max(1, (std::max(w, h) + gMaxTextureSize - 1) / gMaxTextureSize);
  const int ow = std::max(1, w / f), oh = std::max(1, h / f);
  Image<Rgba8> img(ow, oh);
  if (f == 1) {
    std::memcpy(img.data(), px, static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  } else {
    // Box filter over f×f source pixels (the last partial row/column dropped).
    for (int y = 0; y < oh; ++y)
      for (int x = 0; x < ow; ++x) {
        unsigned sum[4] = {0, 0, 0, 0};
        int n = 0;
        for (int dy = 0; dy < f && y * f + dy < h; ++dy)
          for (int dx = 0; dx < f && x * f + dx < w; ++dx) {
            const stbi_uc* p = px + (static_cast<std::size_t>(y * f + dy) * w + (x * f + dx)) * 4;
            for (int c = 0; c < 4; ++c) sum[c] += p[c];
            ++n;
          }
        img.at(x, y) = Rgba8{static_cast<std::uint8_t>(sum[0] / n), static_cast<std::uint8_t>(sum[1] / n),
                             static_cast<std::uint8_t>(sum[2] / n), static_cast<std::uint8_t>(sum[3] / n)};
      }
    if (warning)
      *warning = what + ": texture " + std::to_string(w) + "x" + std::to_string(h) +
                 " downscaled to " + std::to_string(ow) + "x" + std::to_string(oh) +
                 " (--max-texture-size " + std::to_string(gMaxTextureSize) + ")";
  }
  stbi_image_free(px);
  releaseMemory(decodedBytes - static_cast<std::uint64_t>(ow) * static_cast<std::uint64_t>(oh) * 4);
  return img;
}

Result<Image<Rgba8>> readTexture(const std::string& path, std::string* warning) {
  auto bytes = readFile(path, 1ull << 30);
  if (!bytes) return bytes.error();
  return decodeTexture(bytes->data(), bytes->size(), path, warning);
}

Status ensureWritableDir(const std::string& dir) {
  if (dir.empty()) return makeError("output directory: expected a path, got an empty string");
  HW_TRY(checkOutputPath(dir, "output directory"));
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return makeError("cannot create output directory " + dir + ": " + ec.message());
  if (!std::filesystem::is_directory(dir, ec))
    return makeError("output path " + dir + " exists and is not a directory");
  if (::access(dir.c_str(), W_OK) != 0)
    return makeError("output directory " + dir + " is not writable: " + std::strerror(errno));
  // Permission bits do not stop root, and say nothing of read-only or special
  // filesystems: probe with a real file.
  const std::string probe = dir + "/.hybridwalk-probe-" + std::to_string(::getpid());
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) return makeError("output directory " + dir + " is not writable: " + std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
  return {};
}

}  // namespace hw
