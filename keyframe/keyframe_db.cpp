#include "keyframe/keyframe_db.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

#include "core/file_io.h"
#include "core/json_guard.h"
#include "core/safe_io.h"
#include "core/short_number.h"
#include "core/timer.h"

namespace hw::keyframe {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the keyframe database is little-endian; a big-endian reader must swap");

using nlohmann::json;

constexpr std::size_t kQuadBytes = 4 * 4 + 12 * 8 + 8 * 8 + 4 * 8 + 4;  // 212
// camera (12 + 1 + 2 + 2 doubles/ints, depth mode), render stats, mesh header
constexpr std::size_t kCameraBytes = 12 * 8 + 8 + 4 + 4 + 8 + 8 + 4;  // 132
constexpr std::size_t kRenderBytes = 8 + 8;
constexpr std::size_t kMeshHeaderBytes = 4 + 4 + 8 + 4 + 4 + 8 + 4 + 4 + 8 + 8;  // 56
constexpr std::size_t kPixelBytes = 4 + 8 + 4 + 1;  // colour, z', eye z, covered
constexpr int kMaxSide = 16384;

std::uint64_t rotl(std::uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }

class Writer {
 public:
  explicit Writer(std::string& out) : out_(out) {}
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&v);
    out_.append(p, sizeof v);
  }
  void bytes(const void* p, std::size_t n) { out_.append(static_cast<const char*>(p), n); }

 private:
  std::string& out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  template <class T>
  T get() {
    T v;
    HW_CHECK_LE(pos_ + sizeof v, in_.size());  // sizes are checked before reading
    std::memcpy(&v, in_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  void bytes(void* p, std::size_t n) {
    HW_CHECK_LE(pos_ + n, in_.size());
    std::memcpy(p, in_.data() + pos_, n);
    pos_ += n;
  }
  std::size_t pos() const { return pos_; }

 private:
  std::string_view in_;
  std::size_t pos_ = 0;
};

void putVec(Writer& w, const glm::dvec3& v) {
  w.put(v.x);
  w.put(v.y);
  w.put(v.z);
}
glm::dvec3 getVec(Reader& r) {
  glm::dvec3 v;
  v.x = r.get<double>();
  v.y = r.get<double>();
  v.z = r.get<double>();
  return v;
}
// The camera block of a keyframe file (docs/keyframe-db.md); returns the depth
// mode stored after it, unchecked.
std::uint32_t readCamera(Reader& r, Camera& c) {
  c.eye = getVec(r);
  c.right = getVec(r);
  c.up = getVec(r);
  c.forward = getVec(r);
  c.fovYRadians = r.get<double>();
  c.width = r.get<std::int32_t>();
  c.height = r.get<std::int32_t>();
  c.nearPlane = r.get<double>();
  c.farPlane = r.get<double>();
  return r.get<std::uint32_t>();
}

struct Header {
  std::uint32_t version = 0, headerBytes = 0;
  std::int32_t frame = 0, width = 0, height = 0;
  std::uint64_t payloadBytes = 0, payloadChecksum = 0, headerChecksum = 0;
};

Result<Header> parseHeader(std::string_view bytes, const std::string& file) {
  if (bytes.size() < kKeyframeHeaderBytes)
    return makeError(file + ": truncated keyframe file: expected a " +
                     std::to_string(kKeyframeHeaderBytes) + "-byte header, found " +
                     std::to_string(bytes.size()) + " bytes");
  if (std::memcmp(bytes.data(), kKeyframeFileMagic, 8) != 0)
    return makeError(file + ": not a hybridwalk keyframe file: expected magic 'HWKFRAME', found '" +
                     std::string(bytes.substr(0, 8)) + "'");
  Reader r(bytes);
  char magic[8];
  r.bytes(magic, 8);
  Header h;
  h.version = r.get<std::uint32_t>();
  h.headerBytes = r.get<std::uint32_t>();
  h.frame = r.get<std::int32_t>();
  h.width = r.get<std::int32_t>();
  h.height = r.get<std::int32_t>();
  (void)r.get<std::uint32_t>();
  h.payloadBytes = r.get<std::uint64_t>();
  h.payloadChecksum = r.get<std::uint64_t>();
  h.headerChecksum = r.get<std::uint64_t>();
  const std::uint64_t hc = hw64(bytes.data(), 48);
  if (h.version != kKeyframeFormatVersion)
    return makeError(file + ": keyframe format version " + std::to_string(h.version) +
                     ", this program reads version " + std::to_string(kKeyframeFormatVersion) +
                     " (re-bake the database)");
  if (hc != h.headerChecksum)
    return makeError(file + ": header checksum mismatch: header says " + hex64(h.headerChecksum) +
                     ", its bytes hash to " + hex64(hc) + " (file corrupt)");
  if (h.headerBytes != kKeyframeHeaderBytes)
    return makeError(file + ": header size " + std::to_string(h.headerBytes) + ", expected " +
                     std::to_string(kKeyframeHeaderBytes));
  if (h.width < 1 || h.width > kMaxSide || h.height < 1 || h.height > kMaxSide || h.frame < 0)
    return makeError(file + ": header has frame " + std::to_string(h.frame) + ", size " +
                     std::to_string(h.width) + "x" + std::to_string(h.height) +
                     "; expected frame >= 0 and sides in [1, 16384]");
  return h;
}

bool finiteVec(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What is wrong with a decoded quad's corners, or "" when they are usable:
// finite world corners, image corners within a pixel of the image, depths in
// front of the camera.
std::string badQuadCorner(const Quad& q, int width, int height) {
  for (int k = 0; k < 4; ++k) {
    const std::string corner = "corner " + std::to_string(k);
    if (!finiteVec(q.world[k])) return corner + " has a non-finite world position";
    const glm::dvec2 p = q.pixel[k];
    if (!(p.x >= -1.0 && p.x <= width + 1.0 && p.y >= -1.0 && p.y <= height + 1.0))
      return corner + " lies outside the image (pixel " + shortNumber(p.x) + ", " +
             shortNumber(p.y) + ")";
    if (!(std::isfinite(q.eyeZ[k]) && q.eyeZ[k] > 0.0))
      return corner + " has eye depth " + shortNumber(q.eyeZ[k]) + ", expected finite > 0";
  }
  return "";
}

// A keyframe file whose size is not the one index.json records.
Error sizeMismatch(const std::string& path, std::uint64_t want, std::uint64_t have) {
  return makeError(path + ": " + (have < want ? "truncated" : "grown") + ": index.json says " +
                   std::to_string(want) + " bytes, file has " + std::to_string(have));
}

}  // namespace

std::uint64_t hw64(const void* data, std::size_t bytes, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = seed;
  std::size_t i = 0;
  for (; i + 8 <= bytes; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = rotl(h ^ w, 31) * 0x9E3779B97F4A7C15ull;
  }
  if (i < bytes) {
    std::uint64_t w = 0;
    std::memcpy(&w, p + i, bytes - i);
    h = rotl(h ^ w, 31) * 0x9E3779B97F4A7C15ull;
  }
  h ^= static_cast<std::uint64_t>(bytes);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBull;
  h ^= h >> 31;
  return h;
}

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string keyframeFileName(int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "kf_%06d.hwkf", frame);
  return buf;
}

std::string encodeKeyframe(int frame, const Keyframe& kf, const QuadMesh& mesh,
                           const RenderStats& render) {
  const int w = kf.colour.width(), h = kf.colour.height();
  HW_CHECK(w >= 1 && h >= 1 && w <= kMaxSide && h <= kMaxSide);
  HW_CHECK(kf.zPrime.width() == w && kf.zPrime.height() == h);
  HW_CHECK(kf.eyeZ.width() == w && kf.eyeZ.height() == h);
  HW_CHECK(kf.covered.width() == w && kf.covered.height() == h);
  HW_CHECK(kf.camera.width == w && kf.camera.height == h);
  HW_CHECK(mesh.width == w && mesh.height == h);
  HW_CHECK_GE(frame, 0);
  std::string payload;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  payload.reserve(kCameraBytes + kRenderBytes + n * kPixelBytes + kMeshHeaderBytes +
                  mesh.quads.size() * kQuadBytes);
  Writer p(payload);
  const Camera& c = kf.camera;
  putVec(p, c.eye);
  putVec(p, c.right);
  putVec(p, c.up);
  putVec(p, c.forward);
  p.put(c.fovYRadians);
  p.put(std::int32_t(c.width));
  p.put(std::int32_t(c.height));
  p.put(c.nearPlane);
  p.put(c.farPlane);
  p.put(std::uint32_t(kf.depthMode));
  p.put(std::uint64_t(render.meshesDrawn));
  p.put(std::uint64_t(render.trianglesDrawn));
  p.bytes(kf.colour.data(), n * 4);
  p.bytes(kf.zPrime.data(), n * 8);
  p.bytes(kf.eyeZ.data(), n * 4);
  p.bytes(kf.covered.data(), n);
  p.put(std::int32_t(mesh.width));
  p.put(std::int32_t(mesh.height));
  p.put(std::uint64_t(mesh.quads.size()));
  const QuadMeshStats& s = mesh.stats;
  p.put(std::int32_t(s.quads));
  p.put(std::int32_t(s.onePixelLeaves));
  p.put(std::int64_t(s.emptyPixels));
  p.put(std::int32_t(s.clampedCorners));
  p.put(std::uint32_t(s.criterion));
  p.put(s.tauZPrime);
  p.put(s.tauParallaxPx);
  for (const Quad& q : mesh.quads) {
    p.put(std::int32_t(q.rect.x0));
    p.put(std::int32_t(q.rect.y0));
    p.put(std::int32_t(q.rect.x1));
    p.put(std::int32_t(q.rect.y1));
    for (const auto& v : q.world) putVec(p, v);
    for (const auto& v : q.pixel) {
      p.put(v.x);
      p.put(v.y);
    }
    for (double z : q.eyeZ) p.put(z);
    p.put(q.maxDelta);
  }

  std::string out;
  out.reserve(kKeyframeHeaderBytes + payload.size());
  Writer hd(out);
  hd.bytes(kKeyframeFileMagic, 8);
  hd.put(kKeyframeFormatVersion);
  hd.put(std::uint32_t(kKeyframeHeaderBytes));
  hd.put(std::int32_t(frame));
  hd.put(std::int32_t(w));
  hd.put(std::int32_t(h));
  hd.put(std::uint32_t(0));
  hd.put(std::uint64_t(payload.size()));
  hd.put(hw64(payload.data(), payload.size()));
  hd.put(hw64(out.data(), 48));
  hd.put(std::uint64_t(0));
  HW_CHECK_EQ(out.size(), kKeyframeHeaderBytes);
  out += payload;
  return out;
}

Result<std::uint64_t> keyframeFileChecksum(std::string_view headerBytes, const std::string& file) {
  auto h = parseHeader(headerBytes, file);
  if (!h) return h.error();
  return h->payloadChecksum;
}

Status decodeKeyframe(std::string_view bytes, const std::string& file, CachedKeyframe& out) {
  auto hr = parseHeader(bytes, file);
  if (!hr) return hr.error();
  const Header& h = *hr;
  const std::uint64_t have = bytes.size() - kKeyframeHeaderBytes;
  if (have != h.payloadBytes)
    return makeError(file + ": " + (have < h.payloadBytes ? "truncated" : "trailing bytes") +
                     ": header says " + std::to_string(kKeyframeHeaderBytes + h.payloadBytes) +
                     " bytes, file has " + std::to_string(bytes.size()));
  const std::string_view payload = bytes.substr(kKeyframeHeaderBytes);
  const std::uint64_t sum = hw64(payload.data(), payload.size());
  if (sum != h.payloadChecksum)
    return makeError(file + ": checksum mismatch: header says " + hex64(h.payloadChecksum) +
                     ", payload hashes to " + hex64(sum) + " (file corrupt)");
  const std::size_t n = static_cast<std::size_t>(h.width) * h.height;
  const std::size_t fixed = kCameraBytes + kRenderBytes + n * kPixelBytes + kMeshHeaderBytes;
  if (payload.size() < fixed)
    return makeError(file + ": payload of " + std::to_string(payload.size()) +
                     " bytes, expected at least " + std::to_string(fixed) + " for " +
                     std::to_string(h.width) + "x" + std::to_string(h.height));
  Reader r(payload);
  Keyframe& kf = out.keyframe;
  Camera& c = kf.camera;
  const auto dm = readCamera(r, c);
  if (c.width != h.width || c.height != h.height)
    return makeError(file + ": camera is " + std::to_string(c.width) + "x" +
                     std::to_string(c.height) + ", header says " + std::to_string(h.width) + "x" +
                     std::to_string(h.height));
  if (dm > std::uint32_t(DepthMode::Float32Reversed))
    return makeError(file + ": depth mode " + std::to_string(dm) + ", expected 0..2");
  if (!finiteVec(c.eye) || !finiteVec(c.right) || !finiteVec(c.up) || !finiteVec(c.forward) ||
      !(c.fovYRadians > 0.0 && c.fovYRadians < 3.15) || !(c.nearPlane > 0.0) ||
      !(c.farPlane > c.nearPlane) || !std::isfinite(c.farPlane))
    return makeError(file + ": camera is not a valid camera (expected finite vectors, a field of "
                            "view in (0, pi) and 0 < near < far finite)");
  kf.depthMode = static_cast<DepthMode>(dm);
  out.render = RenderStats{};
  out.render.meshesDrawn = r.get<std::uint64_t>();
  out.render.trianglesDrawn = r.get<std::uint64_t>();
  out.renderMs = 0;
  kf.colour.resize(h.width, h.height);
  kf.zPrime.resize(h.width, h.height);
  kf.eyeZ.resize(h.width, h.height);
  kf.covered.resize(h.width, h.height);
  r.bytes(kf.colour.data(), n * 4);
  r.bytes(kf.zPrime.data(), n * 8);
  r.bytes(kf.eyeZ.data(), n * 4);
  r.bytes(kf.covered.data(), n);
  QuadMesh& m = out.mesh;
  m.width = r.get<std::int32_t>();
  m.height = r.get<std::int32_t>();
  const auto quads = r.get<std::uint64_t>();
  QuadMeshStats& s = m.stats;
  s = QuadMeshStats{};
  s.quads = r.get<std::int32_t>();
  s.onePixelLeaves = r.get<std::int32_t>();
  s.emptyPixels = r.get<std::int64_t>();
  s.clampedCorners = r.get<std::int32_t>();
  const auto crit = r.get<std::uint32_t>();
  s.tauZPrime = r.get<double>();
  s.tauParallaxPx = r.get<double>();
  if (m.width != h.width || m.height != h.height)
    return makeError(file + ": mesh is " + std::to_string(m.width) + "x" +
                     std::to_string(m.height) + ", header says " + std::to_string(h.width) + "x" +
                     std::to_string(h.height));
  if (crit > std::uint32_t(DeltaCriterion::PerAxisMax))
    return makeError(file + ": criterion " + std::to_string(crit) + ", expected 0..1");
  s.criterion = static_cast<DeltaCriterion>(crit);
  if (quads > n || payload.size() - r.pos() != quads * kQuadBytes)
    return makeError(file + ": " + std::to_string(quads) + " quads need " +
                     std::to_string(quads * kQuadBytes) + " bytes, " +
                     std::to_string(payload.size() - r.pos()) + " remain (at most " +
                     std::to_string(n) + " quads for " + std::to_string(n) + " pixels)");
  m.quads.resize(quads);
  for (std::size_t i = 0; i < quads; ++i) {
    Quad& q = m.quads[i];
    q.rect.x0 = r.get<std::int32_t>();
    q.rect.y0 = r.get<std::int32_t>();
    q.rect.x1 = r.get<std::int32_t>();
    q.rect.y1 = r.get<std::int32_t>();
    for (auto& v : q.world) v = getVec(r);
    for (auto& v : q.pixel) {
      v.x = r.get<double>();
      v.y = r.get<double>();
    }
    for (double& z : q.eyeZ) z = r.get<double>();
    q.maxDelta = r.get<float>();
    if (auto bad = badQuadCorner(q, h.width, h.height); !bad.empty())
      return makeError(file + ": quad " + std::to_string(i) + ": " + bad +
                       " (expected finite corners inside the keyframe's view; file damaged or "
                       "written by something else)");
    if (q.rect.x0 < 0 || q.rect.y0 < 0 || q.rect.x1 > h.width || q.rect.y1 > h.height ||
        q.rect.x0 >= q.rect.x1 || q.rect.y0 >= q.rect.y1)
      return makeError(file + ": quad " + std::to_string(i) + " rectangle [" +
                       std::to_string(q.rect.x0) + "," + std::to_string(q.rect.x1) + ")x[" +
                       std::to_string(q.rect.y0) + "," + std::to_string(q.rect.y1) +
                       ") is outside the " + std::to_string(h.width) + "x" +
                       std::to_string(h.height) + " image or empty");
  }
  out.frame = h.frame;
  return {};
}

json meshOptionsJson(const LodOptions& lod) {
  json j = {{"method", "lod"},
            {"tau", lod.tau},
            {"tau_px", lod.tauParallaxPx},
            {"criterion", deltaCriterionName(lod.criterion)},
            {"planarity", planarityName(lod.planarity)},
            {"merge_strips", lod.mergeStrips},
            {"merge_tolerance", lod.mergeToleranceZPrime}};
  // Only when used, so that databases baked without it (before it existed)
  // still match a fixed-τ run, and one baked with it never does.
  if (lod.tauGradient > 0) j["tau_gradient"] = lod.tauGradient;
  if (lod.splitMisfit) j["split_misfit"] = lod.misfitToleranceZPrime;  // 0 = automatic
  return j;
}

json provenanceJson(const KeyframeDbProvenance& p) {
  return {{"scene", p.scene},   {"triangles", p.triangles},          {"path_hash", p.pathHash},
          {"frames", p.frames}, {"resolution", {p.width, p.height}}, {"depth_mode", p.depthMode},
          {"mesh", p.mesh}};
}

std::string keyframeDbIndexJson(const KeyframeDbProvenance& p,
                                const std::vector<KeyframeDbEntry>& entries) {
  json ks = json::array();
  for (const auto& e : entries)
    ks.push_back({{"frame", e.frame},
                  {"file", e.file},
                  {"bytes", e.bytes},
                  {"checksum", hex64(e.checksum)}});
  json doc = {{"format", kKeyframeDbFormat},
              {"version", kKeyframeDbVersion},
              {"checksum", "hw64 (docs/keyframe-db.md)"},
              {"baked_from", provenanceJson(p)},
              {"keyframes", ks}};
  doc["index_checksum"] = indexChecksum(doc);
  return doc.dump(1) + "\n";
}

std::string indexChecksum(const json& index) {
  json content = index;
  if (content.is_object()) content.erase("index_checksum");
  const std::string text = content.dump();
  return hex64(hw64(text.data(), text.size()));
}

Result<std::vector<KeyframeDbEntry>> parseKeyframeEntries(const json& entries,
                                                          const std::string& source) {
  if (!entries.is_array()) return makeError(source + ": keyframes: expected an array");
  std::vector<KeyframeDbEntry> out;
  std::set<int> seen;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const json& k = entries[i];
    const std::string where = source + ": keyframes[" + std::to_string(i) + "]";
    if (!k.is_object() || !k.contains("frame") || !k["frame"].is_number_integer() ||
        !k.contains("file") || !k["file"].is_string() || !k.contains("bytes") ||
        !k["bytes"].is_number_integer() ||
        (!k["bytes"].is_number_unsigned() && k["bytes"].get<std::int64_t>() < 0) ||
        !k.contains("checksum") || !k["checksum"].is_string())
      return makeError(where +
                       ": expected {frame: int, file: string, bytes: int >= 0, checksum: hex "
                       "string}");
    const json& f = k["frame"];
    const bool frameOk = f.is_number_unsigned()
                             ? f.get<std::uint64_t>() <= static_cast<std::uint64_t>(INT32_MAX)
                             : f.get<std::int64_t>() >= 0 && f.get<std::int64_t>() <= INT32_MAX;
    if (!frameOk)
      return makeError(where + ".frame: expected an integer in [0, 2147483647], got " + f.dump());
    KeyframeDbEntry e;
    e.frame = static_cast<int>(f.get<std::int64_t>());
    e.file = k["file"].get<std::string>();
    e.bytes = k["bytes"].get<std::uint64_t>();
    const std::string cs = k["checksum"].get<std::string>();
    if (cs.size() != 16 ||
        cs.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
      return makeError(where + ".checksum: expected 16 hex digits, got '" + cs.substr(0, 40) + "'");
    e.checksum = std::strtoull(cs.c_str(), nullptr, 16);
    if (e.file.empty() || e.file.find('/') != std::string::npos ||
        e.file.find("..") != std::string::npos)
      return makeError(source + ": keyframe file '" + e.file +
                       "' must be a plain name inside the database");
    if (!seen.insert(e.frame).second)
      return makeError(where + ".frame: frame " + std::to_string(e.frame) + " listed twice");
    out.push_back(e);
  }
  return out;
}

Result<KeyframeDb> KeyframeDb::open(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return makeError("keyframe database '" + dir +
                     "': " + (fs::exists(dir, ec) ? "not a directory" : "no such directory") +
                     " (expected a directory written by 'hybridwalk bake')");
  const std::string indexPath = dir + "/index.json";
  if (!fs::exists(indexPath, ec) && !fs::is_symlink(indexPath, ec))
    return makeError(indexPath +
                     ": missing (expected the index of a database written by 'hybridwalk bake'; "
                     "an interrupted bake leaves none)");
  auto text = readFile(indexPath, 256ull << 20);
  if (!text) return text.error();
  KeyframeDb db;
  db.dir_ = dir;
  {
    auto parsed = parseJsonStrict(*text, indexPath);
    if (!parsed) {
      std::string m = parsed.error().message;
      const std::string invalid = indexPath + ": invalid JSON";
      if (m.rfind(invalid, 0) == 0) m = indexPath + ": not valid JSON" + m.substr(invalid.size());
      return makeError(m);
    }
    db.index_ = std::move(*parsed);
  }
  const json& ix = db.index_;
  auto field = [&](const char* key, json::value_t t1,
                   json::value_t t2 = json::value_t::discarded) -> Status {
    if (!ix.is_object() || !ix.contains(key) || (ix[key].type() != t1 && ix[key].type() != t2))
      return makeError(indexPath + ": expected key '" + key + "' of the right type");
    return {};
  };
  HW_TRY(field("format", json::value_t::string));
  if (ix["format"] != kKeyframeDbFormat)
    return makeError(indexPath + ": format '" + ix["format"].get<std::string>() + "', expected '" +
                     kKeyframeDbFormat + "'");
  HW_TRY(field("version", json::value_t::number_unsigned, json::value_t::number_integer));
  if (ix["version"] != kKeyframeDbVersion)
    return makeError(indexPath + ": database version " + ix["version"].dump() +
                     ", this program reads version " + std::to_string(kKeyframeDbVersion) +
                     " (re-bake the database)");
  HW_TRY(field("baked_from", json::value_t::object));
  HW_TRY(field("keyframes", json::value_t::array));
  auto entries = parseKeyframeEntries(ix["keyframes"], indexPath);
  if (!entries) return entries.error();
  db.entries_ = std::move(*entries);
  if (db.entries_.empty()) return makeError(indexPath + ": lists no keyframes");
  // Last: a damaged entry is named above; an index edited consistently (an
  // entry dropped or added) is caught here.
  if (!ix.contains("index_checksum") || !ix["index_checksum"].is_string())
    return makeError(indexPath +
                     ": no index_checksum (written by an older hybridwalk, or edited by hand): "
                     "re-bake the database");
  const std::string want = indexChecksum(ix);
  if (ix["index_checksum"].get<std::string>() != want)
    return makeError(indexPath + ": index_checksum " + ix["index_checksum"].dump() +
                     ", its content hashes to \"" + want +
                     "\" (index.json edited or damaged after the bake: re-bake the database)");
  const json& bf = ix["baked_from"];
  if (bf.contains("frames") && bf["frames"].is_number_integer())
    for (const auto& e : db.entries_)
      if (e.frame >= bf["frames"].get<std::int64_t>())
        return makeError(indexPath + ": keyframe frame " + std::to_string(e.frame) +
                         " is past the last frame of the " + bf["frames"].dump() +
                         "-frame walk it was baked for");
  // Every keyframe file is looked at now (a stat, not a read): a walk whose
  // mode never reads a file would otherwise pass over a damaged one.
  for (const auto& e : db.entries_) {
    const std::string path = dir + "/" + e.file;
    auto size = regularFileSize(path);
    if (!size) return size.error();
    if (*size != e.bytes) return sizeMismatch(path, e.bytes, *size);
  }
  std::sort(db.entries_.begin(), db.entries_.end(),
            [](const KeyframeDbEntry& a, const KeyframeDbEntry& b) { return a.frame < b.frame; });
  return db;
}

Status KeyframeDb::checkSchedule(const std::vector<int>& frames) const {
  const std::vector<int> have = keyframeFrames();
  std::vector<int> missing, extra;
  std::set_difference(frames.begin(), frames.end(), have.begin(), have.end(),
                      std::back_inserter(missing));
  std::set_difference(have.begin(), have.end(), frames.begin(), frames.end(),
                      std::back_inserter(extra));
  if (missing.empty() && extra.empty()) return {};
  return makeError(dir_ + "/index.json: " +
                   (missing.empty() ? "holds a keyframe for frame " + std::to_string(extra[0]) +
                                          ", which this walk's schedule does not have"
                                    : "has no keyframe for frame " + std::to_string(missing[0]) +
                                          ", which this walk's schedule needs") +
                   " (" + std::to_string(have.size()) + " keyframes in the database, " +
                   std::to_string(frames.size()) + " in the schedule; re-bake the database)");
}

namespace {

bool near(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max({1.0, std::abs(a), std::abs(b)});
}
bool nearVec(const glm::dvec3& a, const glm::dvec3& b) {
  return near(a.x, b.x) && near(a.y, b.y) && near(a.z, b.z);
}
std::string fmtVec(const glm::dvec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.9g, %.9g, %.9g]", v.x, v.y, v.z);
  return buf;
}

}  // namespace

Status checkKeyframeExpectation(const CachedKeyframe& kf, const KeyframeExpectation& want,
                                const std::string& file) {
  const Camera& c = kf.keyframe.camera;
  const Camera w = want.cameraAt(kf.frame);
  auto differs = [&](const std::string& what, const std::string& have, const std::string& exp) {
    return makeError(file + ": keyframe of frame " + std::to_string(kf.frame) + " has " + what +
                     " " + have + ", this walk's frame " + std::to_string(kf.frame) + " has " +
                     exp + " (a keyframe from another bake: re-bake the database)");
  };
  if (c.width != w.width || c.height != w.height)
    return differs("size", std::to_string(c.width) + "x" + std::to_string(c.height),
                   std::to_string(w.width) + "x" + std::to_string(w.height));
  if (want.depthMode && kf.keyframe.depthMode != *want.depthMode)
    return differs("depth mode", depthModeName(kf.keyframe.depthMode),
                   depthModeName(*want.depthMode));
  if (!nearVec(c.eye, w.eye)) return differs("eye", fmtVec(c.eye), fmtVec(w.eye));
  if (!nearVec(c.forward, w.forward) || !nearVec(c.up, w.up) || !nearVec(c.right, w.right))
    return differs("view direction", fmtVec(c.forward), fmtVec(w.forward));
  if (!near(c.fovYRadians, w.fovYRadians) || !near(c.nearPlane, w.nearPlane) ||
      !near(c.farPlane, w.farPlane))
    return differs("projection (fov, near, far)", "differing", "others");
  return {};
}

std::vector<int> KeyframeDb::keyframeFrames() const {
  std::vector<int> f;
  for (const auto& e : entries_) f.push_back(e.frame);
  return f;
}

Status KeyframeDb::checkMatches(const KeyframeDbProvenance& want,
                                const std::vector<std::string>& fields) const {
  const json& have = index_["baked_from"];
  const json expected = provenanceJson(want);
  auto mismatch = [&](const std::string& key, const json* h, const json& v) {
    return makeError(
        dir_ + "/index.json: database baked for " + key + " " +
        (h ? h->dump() : std::string("(missing)")) + ", this run has " + v.dump() +
        " (bake the database again with the same scene, path, --frames, --depth and LOD options)");
  };
  for (const char* k :
       {"scene", "triangles", "path_hash", "frames", "resolution", "depth_mode", "mesh"}) {
    const std::string key = k;
    if (!fields.empty() && std::find(fields.begin(), fields.end(), key) == fields.end()) continue;
    const json& value = expected[key];
    const json* h = have.contains(key) ? &have[key] : nullptr;
    if (value.is_object() && h && h->is_object()) {  // name the sub-field (mesh.tau)
      for (const auto& [sub, v] : value.items())
        if (!h->contains(sub) || (*h)[sub] != v)
          return mismatch(key + "." + sub, h->contains(sub) ? &(*h)[sub] : nullptr, v);
      for (const auto& [sub, hv] : h->items())  // baked with an option this run lacks
        if (!value.contains(sub)) return mismatch(key + "." + sub, &hv, nullptr);
    }
    if (!h || *h != value) return mismatch(key, h, value);
  }
  return {};
}

Status KeyframeDb::checkFiles() const {
  constexpr std::size_t kPrefix = kKeyframeHeaderBytes + kCameraBytes;
  for (const auto& e : entries_) {
    const std::string path = dir_ + "/" + e.file;
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return makeError("cannot open " + path + ": " + std::strerror(errno));
    struct stat st {};
    std::string bytes(kPrefix, '\0');
    ssize_t got = -1;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) got = ::pread(fd, bytes.data(), kPrefix, 0);
    ::close(fd);
    if (!S_ISREG(st.st_mode))
      return makeError(path + ": expected a regular keyframe file, found " +
                       fileKindName(st.st_mode));
    if (static_cast<std::uint64_t>(st.st_size) != e.bytes)
      return sizeMismatch(path, e.bytes, static_cast<std::uint64_t>(st.st_size));
    bytes.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
    auto h = parseHeader(bytes, path);
    if (!h) return h.error();
    if (h->frame != e.frame)
      return makeError(path + ": holds frame " + std::to_string(h->frame) + ", index.json says " +
                       std::to_string(e.frame));
    if (kKeyframeHeaderBytes + h->payloadBytes != e.bytes)
      return makeError(path + ": header says " +
                       std::to_string(kKeyframeHeaderBytes + h->payloadBytes) +
                       " bytes, index.json and the file " + std::to_string(e.bytes));
    if (h->payloadChecksum != e.checksum)
      return makeError(path + ": checksum " + hex64(h->payloadChecksum) +
                       " differs from index.json's " + hex64(e.checksum) +
                       " (file replaced after the bake)");
    if (bytes.size() < kPrefix)
      return makeError(path + ": truncated: no camera after the header");
    Reader r(std::string_view(bytes).substr(kKeyframeHeaderBytes));
    CachedKeyframe kf;
    Camera& c = kf.keyframe.camera;
    const auto dm = readCamera(r, c);
    if (c.width != h->width || c.height != h->height)
      return makeError(path + ": camera is " + std::to_string(c.width) + "x" +
                       std::to_string(c.height) + ", header says " + std::to_string(h->width) +
                       "x" + std::to_string(h->height));
    if (dm > std::uint32_t(DepthMode::Float32Reversed))
      return makeError(path + ": depth mode " + std::to_string(dm) + ", expected 0..2");
    kf.keyframe.depthMode = static_cast<DepthMode>(dm);
    kf.frame = h->frame;
    if (expect_) HW_TRY(checkKeyframeExpectation(kf, *expect_, path));
  }
  return {};
}

Status KeyframeDb::read(int frame, CachedKeyframe& out) const {
  const auto it = std::lower_bound(entries_.begin(), entries_.end(), frame,
                                   [](const KeyframeDbEntry& e, int f) { return e.frame < f; });
  if (it == entries_.end() || it->frame != frame)
    return makeError(dir_ + "/index.json: no keyframe for frame " + std::to_string(frame) +
                     " (the database's keyframes differ from this walk's schedule)");
  const std::string path = dir_ + "/" + it->file;
  // Never more than index.json promised (plus one byte, to say "grown").
  auto bytes = readFile(path, it->bytes + 1);
  if (!bytes) {
    auto size = regularFileSize(path);
    if (size && *size > it->bytes) return sizeMismatch(path, it->bytes, *size);
    return bytes.error();
  }
  if (bytes->size() != it->bytes) return sizeMismatch(path, it->bytes, bytes->size());
  HW_TRY(decodeKeyframe(*bytes, path, out));
  const std::uint64_t headerSum = *keyframeFileChecksum(*bytes, path);
  if (headerSum != it->checksum)
    return makeError(path + ": checksum " + hex64(headerSum) + " differs from index.json's " +
                     hex64(it->checksum) + " (file replaced after the bake)");
  if (out.frame != frame)
    return makeError(path + ": holds frame " + std::to_string(out.frame) + ", index.json says " +
                     std::to_string(frame));
  if (expect_) HW_TRY(checkKeyframeExpectation(out, *expect_, path));
  return {};
}

namespace {

// One background thread, one slot: the keyframe after the last one asked for.
class PrefetchingSource {
 public:
  PrefetchingSource(std::shared_ptr<const KeyframeDb> db, std::shared_ptr<std::size_t> hits)
      : db_(std::move(db)), hits_(std::move(hits)), worker_([this] { loop(); }) {}
  ~PrefetchingSource() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }

  Status get(int frame, CachedKeyframe& out) {
    Stopwatch sw;
    bool served = false;
    Status status;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (slotFrame_ == frame) {
        cv_.wait(lock, [&] { return slotReady_; });
        std::swap(out.keyframe, slot_.keyframe);
        std::swap(out.mesh, slot_.mesh);
        out.render = slot_.render;
        out.frame = frame;
        status = slotStatus_;
        slotFrame_ = -1;
        slotReady_ = false;
        served = true;
        if (hits_) ++*hits_;
      }
    }
    if (!served) status = db_->read(frame, out);
    out.renderMs = sw.ms();
    if (!status) return status;
    // Queue the next keyframe along the path.
    const auto& e = db_->entries();
    const auto it = std::upper_bound(e.begin(), e.end(), frame,
                                     [](int f, const KeyframeDbEntry& x) { return f < x.frame; });
    if (it != e.end()) {
      std::lock_guard<std::mutex> lock(mutex_);
      want_ = it->frame;
    }
    cv_.notify_all();
    return status;
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      // Wait for a request, and for the slot to be free (taken or never filled).
      cv_.wait(lock, [&] { return stop_ || (want_ >= 0 && (slotFrame_ < 0 || slotReady_)); });
      if (stop_) return;
      const int frame = want_;
      want_ = -1;
      if (slotFrame_ == frame) continue;  // already there
      slotFrame_ = frame;
      slotReady_ = false;
      CachedKeyframe buf;
      std::swap(buf.keyframe, slot_.keyframe);  // reuse the slot's buffers
      std::swap(buf.mesh, slot_.mesh);
      lock.unlock();
      Status st = db_->read(frame, buf);
      lock.lock();
      std::swap(buf.keyframe, slot_.keyframe);
      std::swap(buf.mesh, slot_.mesh);
      slot_.render = buf.render;
      slotStatus_ = st;
      // A request for the same frame arriving meanwhile would wait on slotReady_.
      slotReady_ = true;
      cv_.notify_all();
    }
  }

  std::shared_ptr<const KeyframeDb> db_;
  std::shared_ptr<std::size_t> hits_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  int want_ = -1;
  int slotFrame_ = -1;
  bool slotReady_ = false;
  CachedKeyframe slot_;
  Status slotStatus_;
  std::thread worker_;  // last: started after the members it uses
};

}  // namespace

KeyframeCache::Source makeKeyframeDbSource(std::shared_ptr<const KeyframeDb> db, bool prefetch,
                                           std::shared_ptr<std::size_t> hits) {
  HW_CHECK(db != nullptr);
  if (!prefetch)
    return [db](int frame, CachedKeyframe& out) {
      Stopwatch sw;
      Status s = db->read(frame, out);
      out.renderMs = sw.ms();
      return s;
    };
  auto p = std::make_shared<PrefetchingSource>(std::move(db), std::move(hits));
  return [p](int frame, CachedKeyframe& out) { return p->get(frame, out); };
}

}  // namespace hw::keyframe
