#include "session/mode_pin.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "core/file_io.h"
#include "core/json_guard.h"
#include "core/output_dir.h"

namespace hw::session {

namespace {
constexpr const char* kFormat = "hybridwalk mode pin";
constexpr int kVersion = 1;
// A pin of the longest walk a camera path allows is far below this.
constexpr std::uint64_t kMaxPinBytes = 64ull << 20;
}  // namespace

const char* autoPinName(AutoPin p) {
  switch (p) {
    case AutoPin::Use: return "use";
    case AutoPin::Measure: return "measure";
    case AutoPin::Off: return "off";
  }
  return "?";
}

void PinHasher::bytes(const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < n; ++i) {
    h_ ^= b[i];
    h_ *= 1099511628211ull;
  }
}

void PinHasher::text(std::string_view s) {
  number(static_cast<std::int64_t>(s.size()));
  bytes(s.data(), s.size());
}

std::string PinHasher::hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
  return buf;
}

std::string defaultModePinDir() {
  namespace fs = std::filesystem;
  if (const char* d = std::getenv("HYBRIDWALK_PINS"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    return (fs::path(x) / "hybridwalk" / "mode-pins").string();
  if (const char* h = std::getenv("HOME"); h && *h)
    return (fs::path(h) / ".cache" / "hybridwalk" / "mode-pins").string();
  return "";
}

char frameKindLetter(FrameKind k) {
  switch (k) {
    case FrameKind::Geometry: return 'g';
    case FrameKind::Warp: return 'w';
    case FrameKind::Keyframe: return 'k';
  }
  return '?';
}

Result<ModePin> readModePin(const std::string& file, int frames, bool* found) {
  *found = false;
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(file, ec))) return ModePin{};
  auto text = readFile(file, kMaxPinBytes);
  if (!text) return text.error();
  auto j = parseJsonStrict(*text, file);
  if (!j) return j.error();
  const auto& o = *j;
  const auto bad = [&](const std::string& what) -> Error {
    return makeError("mode pin " + file + ": " + what);
  };
  if (!o.is_object() || !o.contains("format") || o["format"] != kFormat)
    return bad(std::string("expected \"format\": \"") + kFormat + "\"");
  if (!o.contains("version") || !o["version"].is_number_integer() || o["version"] != kVersion)
    return bad("expected \"version\": " + std::to_string(kVersion) + ", got " +
               (o.contains("version") ? o["version"].dump() : std::string("none")));
  if (!o.contains("frames") || !o["frames"].is_number_integer() || o["frames"] != frames)
    return bad("expected \"frames\": " + std::to_string(frames) + ", got " +
               (o.contains("frames") ? o["frames"].dump() : std::string("none")));
  if (!o.contains("modes") || !o["modes"].is_string())
    return bad("expected \"modes\", a string of g, w and k, one per frame");
  const std::string& m = o["modes"].get_ref<const std::string&>();
  if (m.size() != static_cast<std::size_t>(frames))
    return bad("\"modes\": expected " + std::to_string(frames) + " letters, got " +
               std::to_string(m.size()));
  ModePin pin;
  pin.kinds.resize(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (m[i] == 'g') pin.kinds[i] = FrameKind::Geometry;
    else if (m[i] == 'w') pin.kinds[i] = FrameKind::Warp;
    else if (m[i] == 'k') pin.kinds[i] = FrameKind::Keyframe;
    else
      return bad("\"modes\": frame " + std::to_string(i) + ": expected g, w or k, got '" +
                 std::string(1, m[i]) + "'");
  }
  if (o.contains("hole_rects")) {
    const auto& h = o["hole_rects"];
    if (!h.is_array() || h.size() != m.size())
      return bad("\"hole_rects\": expected an array of " + std::to_string(frames) +
                 " integers, got " + (h.is_array() ? std::to_string(h.size()) + " entries" : h.dump()));
    pin.holeRects.resize(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) {
      if (!h[i].is_number_integer() || h[i].get<long long>() < -1 || h[i].get<long long>() > 1000000)
        return bad("\"hole_rects\": frame " + std::to_string(i) +
                   ": expected an integer from -1 to 1000000, got " + h[i].dump());
      pin.holeRects[i] = h[i].get<int>();
    }
  }
  *found = true;
  return pin;
}

Status writeModePin(const std::string& file, const ModePin& pin, const std::string& label) {
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  if (!dir.empty()) HW_TRY(ensureWritableDir(dir.string()));
  std::string modes;
  modes.reserve(pin.kinds.size());
  for (FrameKind k : pin.kinds) modes += frameKindLetter(k);
  nlohmann::json o = {{"format", kFormat},           {"version", kVersion},
                      {"scene", label},              {"measured", utcNow()},
                      {"frames", pin.kinds.size()},  {"modes", modes}};
  if (!pin.holeRects.empty()) o["hole_rects"] = pin.holeRects;
  return writeFileAtomic(file, o.dump(1) + "\n");
}

}  // namespace hw::session
