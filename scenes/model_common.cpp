#include "scenes/model_common.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "core/file_io.h"
#include "scenes/sgi_image.h"

namespace hw::scenes::detail {
namespace {

namespace fs = std::filesystem;

Result<Image<Rgba8>> decodeStb(const std::string& bytes, const std::string& what) {
  if (bytes.empty() || bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    return makeError("cannot decode image " + what + ": empty or too large");
  std::string downscaled;  // TORCS/MORSE textures are far below the limit; not reported
  return decodeTexture(bytes.data(), bytes.size(), what, &downscaled);
}

}  // namespace

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool hasCutout(const Image<Rgba8>& img) {
  for (const Rgba8& p : img.pixels())
    if (p.a < 128) return true;
  return false;
}

Result<Image<Rgba8>> decodeAnyImage(const std::string& bytes, const std::string& what) {
  return isSgiImage(bytes) ? decodeSgiImage(bytes, what) : decodeStb(bytes, what);
}

std::optional<fs::path> findTexture(const std::vector<fs::path>& dirs, std::string name) {
  std::replace(name.begin(), name.end(), '\\', '/');
  const fs::path p(name);
  const std::string want = lower(p.filename().string());
  std::error_code ec;
  for (const fs::path& dir : dirs) {
    for (const fs::path& c : {p.is_absolute() ? p : dir / p, dir / p.filename()})
      if (fs::is_regular_file(c, ec)) return c;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (lower(e.path().filename().string()) == want && e.is_regular_file(ec)) return e.path();
  }
  return std::nullopt;
}

bool degenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float e =
      std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
  return !(glm::length(n) > 1e-6f * e) || !std::isfinite(e);
}

}  // namespace hw::scenes::detail
