// Quake 3 BSP (IBSP 46) loader and .pk3 access through libzip. Lump layouts
// follow qfiles.h of the Quake III Arena GPL source; patches are evaluated as
// biquadratic Bézier pieces (tr_curve.c uses the same control grid).
#include "scenes/q3bsp.h"

#include <stb_image.h>  // implementation compiled in core/file_io.cpp
#include <zip.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <tuple>
#include <unordered_map>

#include "core/file_io.h"
#include "scenes/default_paths.h"
#include "scenes/triangle_grid.h"

namespace hw::scenes {
namespace {

// ---------------------------------------------------------------------------
// File layout (qfiles.h)

constexpr int kBspVersion = 46;
constexpr int kNumLumps = 17;
constexpr std::size_t kHeaderBytes = 8 + kNumLumps * 8;

enum Lump : int {
  kLumpEntities = 0,
  kLumpShaders = 1,
  kLumpDrawVerts = 10,
  kLumpDrawIndexes = 11,
  kLumpSurfaces = 13,
};

const char* lumpName(int lump) {
  static const char* const kNames[kNumLumps] = {"entities",
                                                "shaders",
                                                "planes",
                                                "nodes",
                                                "leafs",
                                                "leafsurfaces",
                                                "leafbrushes",
                                                "models",
                                                "brushes",
                                                "brushsides",
                                                "drawverts (vertices)",
                                                "drawindexes (meshverts)",
                                                "fogs",
                                                "surfaces (faces)",
                                                "lightmaps",
                                                "lightgrid",
                                                "visibility"};
  return lump >= 0 && lump < kNumLumps ? kNames[lump] : "?";
}

constexpr std::size_t kShaderBytes = 72;    // char name[64]; int surfaceFlags, contentFlags
constexpr std::size_t kDrawVertBytes = 44;  // xyz[3], st[2], lightmap[2], normal[3], rgba[4]
constexpr std::size_t kSurfaceBytes = 104;  // dsurface_t

constexpr int kSurfSky = 0x4;
constexpr int kSurfNoDraw = 0x80;
constexpr int kContentsFog = 0x40;

enum SurfaceType : int { kPlanar = 1, kPatch = 2, kTriangleSoup = 3, kFlare = 4 };

std::int32_t readI32(const char* p) {
  std::uint32_t u;
  std::memcpy(&u, p, 4);  // little-endian file on a little-endian host
  return static_cast<std::int32_t>(u);
}
float readF32(const char* p) {
  float f;
  std::memcpy(&f, p, 4);
  return f;
}

std::string toLower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Printable text of a fixed-size, possibly unterminated name field.
std::string fixedString(const char* p, std::size_t n) {
  std::string s(p, strnlen(p, n));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return s;
}

struct LumpView {
  const char* data = nullptr;
  std::size_t count = 0;  // elements
};

Result<LumpView> lumpOf(std::string_view bytes, const std::string& source, int lump,
                        std::size_t elementBytes) {
  const char* dir = bytes.data() + 8 + 8 * lump;
  const std::int64_t offset = readI32(dir), length = readI32(dir + 4);
  const std::string where = source + ": lump " + std::to_string(lump) + " (" + lumpName(lump) + ")";
  if (offset < 0 || length < 0 || offset + length > static_cast<std::int64_t>(bytes.size()))
    return makeError(where + ": expected offset and length inside the file's " +
                     std::to_string(bytes.size()) + " bytes, got offset " + std::to_string(offset) +
                     " length " + std::to_string(length));
  if (elementBytes > 1 && length % static_cast<std::int64_t>(elementBytes) != 0)
    return makeError(where + ": expected a length that is a multiple of " +
                     std::to_string(elementBytes) + " bytes, got " + std::to_string(length));
  return LumpView{bytes.data() + offset,
                  static_cast<std::size_t>(length) / std::max<std::size_t>(elementBytes, 1)};
}

// ---------------------------------------------------------------------------
// Text tokens (entities lump, shader scripts): COM_Parse's rules — // and
// /* */ comments, "quoted strings", braces, bare words.

struct Token {
  std::string_view text;
  bool quoted = false;
  int line = 1;
  bool newLine = false;  // first token on its line
};

class Tokenizer {
 public:
  explicit Tokenizer(std::string_view s) : s_(s) {}
  // nullopt at the end; `error` set for an unterminated string or comment.
  std::optional<Token> next() {
    bool nl = pos_ == 0;
    for (;;) {
      while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) {
        if (s_[pos_] == '\n') ++line_, nl = true;
        ++pos_;
      }
      if (pos_ + 1 < s_.size() && s_[pos_] == '/' && s_[pos_ + 1] == '/') {
        while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
      } else if (pos_ + 1 < s_.size() && s_[pos_] == '/' && s_[pos_ + 1] == '*') {
        const std::size_t end = s_.find("*/", pos_ + 2);
        if (end == std::string_view::npos) {
          error = "unterminated /* comment";
          pos_ = s_.size();
          return std::nullopt;
        }
        for (std::size_t i = pos_; i < end; ++i) line_ += s_[i] == '\n';
        pos_ = end + 2;
      } else {
        break;
      }
    }
    if (pos_ >= s_.size() || s_[pos_] == '\0') return std::nullopt;
    Token t;
    t.line = line_;
    t.newLine = nl;
    if (s_[pos_] == '"') {
      const std::size_t end = s_.find('"', pos_ + 1);
      if (end == std::string_view::npos) {
        error = "unterminated quoted string";
        pos_ = s_.size();
        return std::nullopt;
      }
      t.text = s_.substr(pos_ + 1, end - pos_ - 1);
      t.quoted = true;
      for (char c : t.text) line_ += c == '\n';
      pos_ = end + 1;
    } else if (s_[pos_] == '{' || s_[pos_] == '}') {
      t.text = s_.substr(pos_++, 1);
    } else {
      const std::size_t start = pos_;
      while (pos_ < s_.size() && s_[pos_] != '\0' &&
             !std::isspace(static_cast<unsigned char>(s_[pos_])) && s_[pos_] != '{' &&
             s_[pos_] != '}' && s_[pos_] != '"')
        ++pos_;
      t.text = s_.substr(start, pos_ - start);
    }
    return t;
  }
  std::string error;

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

bool isBrace(const Token& t, char c) { return !t.quoted && t.text.size() == 1 && t.text[0] == c; }

// Up to `n` finite numbers separated by spaces; false when fewer or malformed.
template <std::size_t N>
bool parseNumbers(std::string_view text, std::array<double, N>& out) {
  std::string s(text);
  const char* p = s.c_str();
  for (std::size_t i = 0; i < N; ++i) {
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v)) return false;
    out[i] = v;
    p = end;
  }
  return true;
}

glm::dvec3 toYUpMetres(double x, double y, double z) {
  return glm::dvec3(x, z, -y) * kQ3MetresPerUnit;
}

// ---------------------------------------------------------------------------
// Geometry

glm::vec3 yUp(const glm::vec3& q) { return glm::vec3(q.x, q.z, -q.y); }

struct DrawVert {
  glm::vec3 xyz;  // Quake space
  glm::vec2 st;
  glm::vec3 normal;
};

DrawVert drawVert(const char* p) {
  DrawVert v;
  v.xyz = glm::vec3(readF32(p), readF32(p + 4), readF32(p + 8));
  v.st = glm::vec2(readF32(p + 12), readF32(p + 16));
  v.normal = glm::vec3(readF32(p + 28), readF32(p + 32), readF32(p + 36));
  return v;
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

glm::vec3 safeNormalize(const glm::vec3& v, const glm::vec3& fallback) {
  const float len = glm::length(v);
  return std::isfinite(len) && len > 1e-12f ? v / len : fallback;
}

// Biquadratic Bernstein basis and derivative at t.
void bernstein(float t, float b[3], float d[3]) {
  const float s = 1.0f - t;
  b[0] = s * s, b[1] = 2.0f * t * s, b[2] = t * t;
  d[0] = -2.0f * s, d[1] = 2.0f - 4.0f * t, d[2] = 2.0f * t;
}

struct PatchSample {
  glm::vec3 p{0.0f}, pu{0.0f}, pv{0.0f}, n{0.0f};
  glm::vec2 st{0.0f};
};

// cp(i, j): control point i along the patch's width, j along its height.
template <class CP>
PatchSample evalPiece(const CP& cp, int i0, int j0, float u, float v) {
  float bu[3], du[3], bv[3], dv[3];
  bernstein(u, bu, du);
  bernstein(v, bv, dv);
  PatchSample s;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const DrawVert& c = cp(i0 + i, j0 + j);
      const float w = bu[i] * bv[j];
      s.p += w * c.xyz;
      s.pu += du[i] * bv[j] * c.xyz;
      s.pv += bu[i] * dv[j] * c.xyz;
      s.n += w * (finite(c.normal) ? c.normal : glm::vec3(0.0f));
      s.st += w * c.st;
    }
  return s;
}

struct MeshBuilder {
  std::map<std::tuple<int, long long, long long, long long>, std::size_t> byKey;
  std::vector<Mesh> meshes;

  Mesh& meshFor(int material, const glm::vec3& centreQ3, double chunk) {
    auto cell = [&](float c) {
      const double k = std::floor(static_cast<double>(c) / chunk);
      return static_cast<long long>(std::clamp(k, -1e9, 1e9));
    };
    const auto key =
        std::make_tuple(material, cell(centreQ3.x), cell(centreQ3.y), cell(centreQ3.z));
    auto [it, inserted] = byKey.emplace(key, meshes.size());
    if (inserted) {
      Mesh m;
      m.material = material;
      meshes.push_back(std::move(m));
    }
    return meshes[it->second];
  }
};

// Why a surface is not drawn, or nullptr. Flags come from the shader's
// surfaceparms (baked into the BSP by q3map); the names catch tool shaders
// of maps compiled without their shader scripts.
const char* skipReason(const std::string& shaderLower, int surfaceFlags, int contents) {
  if (surfaceFlags & kSurfSky) return "sky";
  if (surfaceFlags & kSurfNoDraw) return "nodraw";
  if (contents & kContentsFog) return "fog";
  std::string_view base(shaderLower);
  if (const auto slash = base.rfind('/'); slash != std::string_view::npos)
    base = base.substr(slash + 1);
  for (const char* word : {"sky", "nodraw", "fog", "trigger", "caulk"})
    if (base.find(word) != std::string_view::npos) return word;
  // clip, weapclip, botclip, playerclip — but not "eclipse".
  const bool common = shaderLower.find("common/") != std::string::npos;
  if (base.find("clip") != std::string_view::npos &&
      (common || (base.size() >= 4 && base.substr(base.size() - 4) == "clip")))
    return "clip";
  if (shaderLower.find("/skies/") != std::string::npos) return "sky";
  return nullptr;
}

}  // namespace

// ---------------------------------------------------------------------------

Result<std::vector<Q3Spawn>> parseQ3Spawns(std::string_view entities, const std::string& source,
                                           const Q3Options& options) {
  const std::string where = source + ": lump 0 (entities)";
  Tokenizer tok(entities);
  std::vector<Q3Spawn> spawns;
  int entity = 0;
  for (;;) {
    auto open = tok.next();
    if (!open) break;
    if (!isBrace(*open, '{'))
      return makeError(where + ", line " + std::to_string(open->line) +
                       ": expected '{' to start entity " + std::to_string(entity) + ", got '" +
                       std::string(open->text.substr(0, 40)) + "'");
    std::map<std::string, std::string> kv;
    for (;;) {
      auto key = tok.next();
      if (!key)
        return makeError(where + ": entity " + std::to_string(entity) +
                         " is not closed (expected '}', got " +
                         (tok.error.empty() ? "the end of the lump" : tok.error) + ")");
      if (isBrace(*key, '}')) break;
      auto value = tok.next();
      if (!value || isBrace(*value, '}') || isBrace(*value, '{'))
        return makeError(where + ", line " + std::to_string(key->line) + ": entity " +
                         std::to_string(entity) + ": expected a value after key '" +
                         std::string(key->text.substr(0, 40)) + "'");
      kv[toLower(std::string(key->text))] = std::string(value->text);
    }
    const std::string cls = kv.count("classname") ? kv["classname"] : "";
    if (cls == "info_player_deathmatch" || cls == "info_player_start") {
      std::array<double, 3> o{};
      if (!parseNumbers(kv["origin"], o))
        return makeError(where + ": entity " + std::to_string(entity) + " (" + cls +
                         "): expected \"origin\" \"x y z\" with 3 finite numbers, got \"" +
                         kv["origin"].substr(0, 60) + "\"");
      // Finite but huge (1e300) gave a NaN camera path and a CHECK abort;
      // maps are at most a few 10^4 units across.
      constexpr double kMaxOriginUnits = 1e7;
      for (double v : o)
        if (!(std::abs(v) <= kMaxOriginUnits))
          return makeError(where + ": entity " + std::to_string(entity) + " (" + cls +
                           "): origin \"" + kv["origin"].substr(0, 60) +
                           "\": expected coordinates of magnitude at most 1e7 units");
      double yaw = 0.0;
      std::array<double, 1> a{};
      std::array<double, 3> pyr{};
      if (kv.count("angles") && parseNumbers(kv["angles"], pyr))
        yaw = pyr[1];
      else if (kv.count("angle") && parseNumbers(kv["angle"], a))
        yaw = a[0];
      Q3Spawn s;
      s.classname = cls;
      s.yawDegrees = yaw;
      s.origin = toYUpMetres(o[0], o[1], o[2]);
      s.eye = toYUpMetres(o[0], o[1], o[2] + options.eyeHeightUnits);
      const double r = yaw * 3.14159265358979323846 / 180.0;
      s.forward = glm::normalize(toYUpMetres(std::cos(r), std::sin(r), 0.0));
      spawns.push_back(std::move(s));
    }
    ++entity;
  }
  if (!tok.error.empty()) return makeError(where + ": " + tok.error);
  return spawns;
}

namespace {

// The header's magic and version.
Status checkBspHeader(std::string_view bytes, const std::string& source) {
  if (bytes.size() < kHeaderBytes)
    return makeError(source + ": not a Quake 3 BSP: expected at least " +
                     std::to_string(kHeaderBytes) + " header bytes, got " +
                     std::to_string(bytes.size()));
  if (bytes.substr(0, 4) != "IBSP")
    return makeError(source + ": not a Quake 3 BSP: expected magic 'IBSP', got '" +
                     fixedString(bytes.data(), 4) + "'");
  const int version = readI32(bytes.data() + 4);
  if (version != kBspVersion)
    return makeError(source + ": unsupported BSP version: expected " + std::to_string(kBspVersion) +
                     " (Quake 3 / OpenArena), got " + std::to_string(version));
  return {};
}

// The lumps a map is built from, each checked against the file's size.
struct BspLumps {
  LumpView entities, shaders, verts, indexes, faces;
};

Result<BspLumps> bspLumps(std::string_view bytes, const std::string& source) {
  auto entLump = lumpOf(bytes, source, kLumpEntities, 1);
  if (!entLump) return entLump.error();
  auto shaderLump = lumpOf(bytes, source, kLumpShaders, kShaderBytes);
  if (!shaderLump) return shaderLump.error();
  auto vertLump = lumpOf(bytes, source, kLumpDrawVerts, kDrawVertBytes);
  if (!vertLump) return vertLump.error();
  auto indexLump = lumpOf(bytes, source, kLumpDrawIndexes, 4);
  if (!indexLump) return indexLump.error();
  auto faceLump = lumpOf(bytes, source, kLumpSurfaces, kSurfaceBytes);
  if (!faceLump) return faceLump.error();
  return BspLumps{*entLump, *shaderLump, *vertLump, *indexLump, *faceLump};
}

// The map's shaders, each turned into a material (and its texture) the first
// time a drawn face uses it.
class Q3Materials {
 public:
  struct ShaderInfo {
    std::string name, lower;
    int flags = 0, contents = 0;
    int material = -2;  // -2: not resolved yet; -1: skipped
  };

  Q3Materials(const LumpView& shaderLump, const std::string& source,
              const Q3TextureResolver& resolve, Q3Map& map)
      : shaders_(shaderLump.count), source_(source), resolve_(resolve), map_(map) {
    for (std::size_t i = 0; i < shaders_.size(); ++i) {
      const char* p = shaderLump.data + i * kShaderBytes;
      shaders_[i].name = fixedString(p, 64);
      shaders_[i].lower = toLower(shaders_[i].name);
      shaders_[i].flags = readI32(p + 64);
      shaders_[i].contents = readI32(p + 68);
    }
  }

  std::size_t size() const { return shaders_.size(); }
  const ShaderInfo& shader(std::size_t i) const { return shaders_[i]; }
  // Per material: its stage's tcMod scale.
  glm::vec2 uvScale(int material) const { return uvScaleOf_[static_cast<std::size_t>(material)]; }

  // The material of shader `shaderIndex`, or -1 when its faces are not drawn.
  int materialFor(std::size_t shaderIndex) {
    ShaderInfo& sh = shaders_[shaderIndex];
    if (sh.material != -2) return sh.material;
    const char* why = skipReason(sh.lower, sh.flags, sh.contents);
    const bool sky = why && std::strcmp(why, "sky") == 0;
    if (why && !sky) return sh.material = -1;
    Material m;
    m.name = sh.name;
    Q3Texture t;
    if (resolve_) t = resolve_(sh.name);
    const bool earlier = t.sameAsEarlier && textureByPath_.count(t.path) > 0;
    if (t.sameAsEarlier && !earlier)
      t.error = "image " + t.path + " named again before its first use (resolver bug)";
    if (sky) {  // drawn only with an image: the sky's own (unlit, both sides)
      if (t.image.empty() && !earlier) return sh.material = -1;
      m.sky = m.unlit = true;
      t.twoSided = true;
      t.alphaTest = false;
    }
    m.twoSided = t.twoSided;
    m.alphaTest = t.alphaTest;
    m.alphaCutoff = t.alphaCutoff;
    Scene& scene = map_.scene;
    if ((earlier || !t.image.empty()) && !t.path.empty() && textureByPath_.count(t.path)) {
      m.texture = textureByPath_[t.path];
    } else {
      Texture tex;
      tex.name = t.path.empty() ? sh.name : t.path;
      if (t.image.empty()) {
        ++map_.stats.missingTextures;
        scene.warnings.push_back(source_ + ": shader '" + sh.name +
                                 "': " + (t.error.empty() ? std::string("no texture") : t.error) +
                                 "; using a placeholder");
        tex.image = missingTexture();
        m.alphaTest = false;
      } else {
        tex.image = std::move(t.image);
        if (!t.path.empty()) textureByPath_[t.path] = static_cast<int>(scene.textures.size());
      }
      m.texture = static_cast<int>(scene.textures.size());
      scene.textures.push_back(std::move(tex));
    }
    scene.materials.push_back(std::move(m));
    uvScaleOf_.push_back(t.uvScale);
    return sh.material = static_cast<int>(scene.materials.size()) - 1;
  }

 private:
  std::vector<ShaderInfo> shaders_;
  const std::string& source_;
  const Q3TextureResolver& resolve_;
  Q3Map& map_;
  std::map<std::string, int> textureByPath_;
  std::vector<glm::vec2> uvScaleOf_;
};

// One dsurface_t record (the fields the loader uses).
struct BspFace {
  std::int64_t shader = 0, type = 0;
  std::int64_t firstVert = 0, numVerts = 0;
  std::int64_t firstIndex = 0, numIndexes = 0;
  std::int64_t patchW = 0, patchH = 0;
};

BspFace readFace(const char* p) {
  BspFace f;
  f.shader = readI32(p), f.type = readI32(p + 8);
  f.firstVert = readI32(p + 12), f.numVerts = readI32(p + 16);
  f.firstIndex = readI32(p + 20), f.numIndexes = readI32(p + 24);
  f.patchW = readI32(p + 96), f.patchH = readI32(p + 100);
  return f;
}

// The face's surface type and shader index.
Status checkFaceKind(const BspFace& face, const std::string& where, std::size_t shaderCount) {
  if (face.type < kPlanar || face.type > kFlare)
    return makeError(where +
                     ": expected surface type 1 (polygon), 2 (patch), 3 (mesh) or 4 "
                     "(billboard), got " +
                     std::to_string(face.type));
  if (face.shader < 0 || face.shader >= static_cast<std::int64_t>(shaderCount))
    return makeError(where + ": expected a shader (texture) index in [0, " +
                     std::to_string(shaderCount) + ") of lump 1 (shaders), got " +
                     std::to_string(face.shader));
  return {};
}

// The face's vertex and meshvert ranges, its patch grid, and that its
// vertices are finite.
Status checkFaceVertices(const BspFace& face, const std::string& where, const LumpView& verts,
                         const LumpView& indexes) {
  const std::size_t nVerts = verts.count, nIndexes = indexes.count;
  auto rangeError = [&](const char* what, std::int64_t first, std::int64_t n, std::size_t size,
                        const char* lump) {
    return makeError(where + ": " + what + " [" + std::to_string(first) + ", " +
                     std::to_string(first) + " + " + std::to_string(n) + ") outside lump " + lump +
                     " of " + std::to_string(size) + " entries");
  };
  const std::int64_t firstVert = face.firstVert, numVerts = face.numVerts;
  const std::int64_t firstIndex = face.firstIndex, numIndexes = face.numIndexes;
  const std::int64_t patchW = face.patchW, patchH = face.patchH;
  if (firstVert < 0 || numVerts < 0 || firstVert + numVerts > static_cast<std::int64_t>(nVerts))
    return rangeError("vertices", firstVert, numVerts, nVerts, "10 (vertices)");
  if (face.type != kPatch) {
    if (firstIndex < 0 || numIndexes < 0 ||
        firstIndex + numIndexes > static_cast<std::int64_t>(nIndexes))
      return rangeError("meshverts", firstIndex, numIndexes, nIndexes, "11 (meshverts)");
    if (numIndexes % 3 != 0)
      return makeError(where + ": expected a meshvert count that is a multiple of 3, got " +
                       std::to_string(numIndexes));
    for (std::int64_t k = 0; k < numIndexes; ++k) {
      const std::int64_t idx = readI32(indexes.data + 4 * (firstIndex + k));
      if (idx < 0 || idx >= numVerts)
        return makeError(where + ": meshvert " + std::to_string(firstIndex + k) +
                         " expected a vertex offset in [0, " + std::to_string(numVerts) +
                         ") (the face's vertex count), got " + std::to_string(idx));
    }
  } else {
    if (patchW < 3 || patchH < 3 || patchW % 2 == 0 || patchH % 2 == 0 || patchW > 65537 ||
        patchH > 65537)
      return makeError(where + ": patch control grid must be odd × odd and at least 3 × 3, got " +
                       std::to_string(patchW) + " × " + std::to_string(patchH));
    if (patchW * patchH != numVerts)
      return makeError(where + ": patch of " + std::to_string(patchW) + " × " +
                       std::to_string(patchH) + " control points expects that many vertices (" +
                       std::to_string(patchW * patchH) + "), got " + std::to_string(numVerts));
  }
  for (std::int64_t k = 0; k < numVerts; ++k) {
    const DrawVert v = drawVert(verts.data + kDrawVertBytes * (firstVert + k));
    if (!finite(v.xyz) || !finite(v.st))
      return makeError(where + ": vertex " + std::to_string(firstVert + k) +
                       " of lump 10 (vertices) has a non-finite position or texture coordinate");
  }
  return {};
}

// Triangles the face will add, patches subdivided `level` times per piece.
std::size_t faceTriangles(const BspFace& face, int level) {
  return face.type == kPatch ? static_cast<std::size_t>((face.patchW - 1) / 2) *
                                   static_cast<std::size_t>((face.patchH - 1) / 2) * 2u *
                                   static_cast<std::size_t>(level * level)
         : face.numIndexes > 0
             ? static_cast<std::size_t>(face.numIndexes / 3)
             : static_cast<std::size_t>(std::max<std::int64_t>(face.numVerts - 2, 0));
}

// Centre of the face's bounding box, Quake units (picks its chunk mesh).
glm::vec3 faceCentreQ3(const BspFace& face, const LumpView& verts) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::int64_t k = 0; k < face.numVerts; ++k) {
    const glm::vec3 x = drawVert(verts.data + kDrawVertBytes * (face.firstVert + k)).xyz;
    lo = glm::min(lo, x), hi = glm::max(hi, x);
  }
  return 0.5f * (lo + hi);
}

// A polygon or triangle-soup face appended to `mesh`.
void appendPolygonFace(const BspFace& face, const LumpView& verts, const LumpView& indexes,
                       glm::vec2 uvScale, Mesh& mesh, Q3Stats& stats) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  const std::int64_t firstVert = face.firstVert, numVerts = face.numVerts;
  const std::int64_t firstIndex = face.firstIndex, numIndexes = face.numIndexes;
  std::vector<DrawVert> dv(static_cast<std::size_t>(numVerts));
  for (std::int64_t k = 0; k < numVerts; ++k)
    dv[static_cast<std::size_t>(k)] = drawVert(verts.data + kDrawVertBytes * (firstVert + k));
  // Quake's triangles are clockwise seen from the front; ours are
  // counter-clockwise, so every triangle is emitted as (a, c, b).
  std::vector<std::uint32_t> tri;
  if (numIndexes > 0) {
    for (std::int64_t k = 0; k < numIndexes; ++k)
      tri.push_back(static_cast<std::uint32_t>(readI32(indexes.data + 4 * (firstIndex + k))));
  } else {  // no meshverts (old compilers): a fan, as the polygon is convex
    for (std::int64_t k = 1; k + 1 < numVerts; ++k)
      tri.insert(tri.end(), {0u, static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(k + 1)});
  }
  glm::vec3 faceNormal(0.0f);
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const glm::vec3 a = dv[tri[t]].xyz, b = dv[tri[t + 1]].xyz, c = dv[tri[t + 2]].xyz;
    faceNormal += glm::cross(c - a, b - a);  // (a, c, b): counter-clockwise front
  }
  faceNormal = safeNormalize(faceNormal, glm::vec3(0, 0, 1));
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const glm::vec3 a = dv[tri[t]].xyz, b = dv[tri[t + 1]].xyz, c = dv[tri[t + 2]].xyz;
    const glm::vec3 g = glm::cross(c - a, b - a);
    const glm::vec3 n = dv[tri[t]].normal + dv[tri[t + 1]].normal + dv[tri[t + 2]].normal;
    if (glm::length(g) > 1e-6f && finite(n) && glm::length(n) > 1e-3f && glm::dot(g, n) < 0.0f)
      ++stats.windingDisagreements;
  }
  for (const DrawVert& v : dv) {
    Vertex out;
    out.position = yUp(v.xyz) * static_cast<float>(kQ3MetresPerUnit);
    out.normal = yUp(finite(v.normal) ? safeNormalize(v.normal, faceNormal) : faceNormal);
    out.uv = v.st * uvScale;
    mesh.vertices.push_back(out);
  }
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3)
    mesh.indices.insert(mesh.indices.end(), {base + tri[t], base + tri[t + 2], base + tri[t + 1]});
}

// A Bézier patch face, each piece subdivided `level` times, appended to
// `mesh`: one grid over all pieces, so neighbouring pieces share their
// border vertices (the shared control row makes them equal anyway).
void appendPatchFace(const BspFace& face, const LumpView& verts, int level, glm::vec2 uvScale,
                     Mesh& mesh) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  const std::int64_t patchW = face.patchW, patchH = face.patchH;
  auto cp = [&](std::int64_t i, std::int64_t j) {
    return drawVert(verts.data + kDrawVertBytes * (face.firstVert + j * patchW + i));
  };
  const int piecesW = static_cast<int>((patchW - 1) / 2),
            piecesH = static_cast<int>((patchH - 1) / 2);
  const int gw = piecesW * level + 1, gh = piecesH * level + 1;
  std::vector<DrawVert> ctl(static_cast<std::size_t>(face.numVerts));
  for (std::int64_t j = 0; j < patchH; ++j)
    for (std::int64_t i = 0; i < patchW; ++i)
      ctl[static_cast<std::size_t>(j * patchW + i)] = cp(i, j);
  auto ctlAt = [&](int i, int j) -> const DrawVert& {
    return ctl[static_cast<std::size_t>(j) * static_cast<std::size_t>(patchW) +
               static_cast<std::size_t>(i)];
  };
  std::vector<PatchSample> grid(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
  auto sampleAt = [&](int gx, int gy, float nudge) {
    const int px = std::min(gx / level, piecesW - 1), py = std::min(gy / level, piecesH - 1);
    float u = static_cast<float>(gx - px * level) / static_cast<float>(level);
    float v = static_cast<float>(gy - py * level) / static_cast<float>(level);
    u += nudge * (0.5f - u), v += nudge * (0.5f - v);
    return evalPiece(ctlAt, 2 * px, 2 * py, u, v);
  };
  double orientation = 0.0;
  for (int gy = 0; gy < gh; ++gy)
    for (int gx = 0; gx < gw; ++gx) {
      PatchSample s = sampleAt(gx, gy, 0.0f);
      orientation += glm::dot(glm::cross(s.pu, s.pv), s.n);
      grid[static_cast<std::size_t>(gy) * gw + gx] = s;
    }
  // The control points' normals (from q3map) say which side is the front;
  // the surface's own derivative gives the direction.
  const float sign = orientation < 0.0 ? -1.0f : 1.0f;
  for (int gy = 0; gy < gh; ++gy)
    for (int gx = 0; gx < gw; ++gx) {
      const PatchSample& s = grid[static_cast<std::size_t>(gy) * gw + gx];
      glm::vec3 c = glm::cross(s.pu, s.pv);
      const float scale = glm::length(s.pu) * glm::length(s.pv);
      if (!(glm::length(c) > 1e-4f * scale) || scale == 0.0f) {
        // A collapsed edge (cone tip, triangle-shaped patch): the limit
        // normal, approached from inside the piece.
        const PatchSample t = sampleAt(gx, gy, 1e-3f);
        c = glm::cross(t.pu, t.pv);
        if (!(glm::length(c) > 1e-6f * glm::length(t.pu) * glm::length(t.pv)))
          c = sign * safeNormalize(s.n, glm::vec3(0, 0, 1));
      }
      Vertex out;
      out.position = yUp(s.p) * static_cast<float>(kQ3MetresPerUnit);
      out.normal = yUp(safeNormalize(sign * c, glm::vec3(0, 0, 1)));
      out.uv = s.st * uvScale;
      mesh.vertices.push_back(out);
    }
  for (int gy = 0; gy + 1 < gh; ++gy)
    for (int gx = 0; gx + 1 < gw; ++gx) {
      const std::uint32_t a = base + static_cast<std::uint32_t>(gy * gw + gx);
      const std::uint32_t b = a + 1, d = a + static_cast<std::uint32_t>(gw), c = d + 1;
      // (a, b, c) has geometric normal along pu × pv.
      if (sign > 0)
        mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
      else
        mesh.indices.insert(mesh.indices.end(), {a, c, b, a, d, c});
    }
}

}  // namespace

Result<Q3Map> parseQ3Bsp(std::string_view bytes, const std::string& source,
                         const Q3TextureResolver& resolve, const Q3Options& options) {
  HW_TRY(checkBspHeader(bytes, source));
  auto lumps = bspLumps(bytes, source);
  if (!lumps) return lumps.error();
  const LumpView& vertLump = lumps->verts;
  const LumpView& indexLump = lumps->indexes;
  const LumpView& faceLump = lumps->faces;

  Q3Map map;
  Scene& scene = map.scene;
  scene.name = source;
  {
    auto spawns = parseQ3Spawns(std::string_view(lumps->entities.data, lumps->entities.count),
                                source, options);
    if (!spawns) return spawns.error();
    map.spawns = std::move(*spawns);
  }
  Q3Materials materials(lumps->shaders, source, resolve, map);

  const int level = std::clamp(options.patchSubdivisions, 1, 64);
  const double chunk = options.chunkSizeUnits > 1.0 && std::isfinite(options.chunkSizeUnits)
                           ? options.chunkSizeUnits
                           : 512.0;
  MeshBuilder builder;
  std::size_t totalTriangles = 0;
  map.stats.faces = faceLump.count;

  for (std::size_t f = 0; f < faceLump.count; ++f) {
    const BspFace face = readFace(faceLump.data + f * kSurfaceBytes);
    const std::string where = source + ": lump 13 (faces), face " + std::to_string(f);
    HW_TRY(checkFaceKind(face, where, materials.size()));
    if (face.type == kFlare) {
      ++map.stats.skippedFaces;
      continue;
    }
    HW_TRY(checkFaceVertices(face, where, vertLump, indexLump));

    const auto shader = static_cast<std::size_t>(face.shader);
    const auto& sh = materials.shader(shader);
    if (const char* why = skipReason(sh.lower, sh.flags, sh.contents)) {
      if (std::strcmp(why, "sky") != 0 || materials.materialFor(shader) < 0) {
        ++map.stats.skippedFaces;
        continue;
      }
      ++map.stats.skyFaces;
    }
    const std::size_t faceTris = faceTriangles(face, level);
    totalTriangles += faceTris;
    if (totalTriangles > options.maxTriangles)
      return makeError(where + ": the map would have more than " +
                       std::to_string(options.maxTriangles) +
                       " triangles (Q3Options::maxTriangles); corrupt patch sizes?");
    if (faceTris == 0) continue;

    const int material = materials.materialFor(shader);
    if (material < 0) continue;
    Mesh& mesh = builder.meshFor(material, faceCentreQ3(face, vertLump), chunk);
    if (face.type != kPatch) {
      appendPolygonFace(face, vertLump, indexLump, materials.uvScale(material), mesh, map.stats);
    } else {
      ++map.stats.patches;
      appendPatchFace(face, vertLump, level, materials.uvScale(material), mesh);
    }
  }

  if (builder.meshes.empty())
    return makeError(source + ": no drawable faces (all " + std::to_string(map.stats.faces) +
                     " faces are skipped: sky, nodraw, fog, tool shaders or billboards)");
  scene.meshes = std::move(builder.meshes);
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    Mesh& m = scene.meshes[i];
    m.name = scene.materials[static_cast<std::size_t>(m.material)].name + "#" + std::to_string(i);
  }
  scene.computeBounds();
  scene.skyColour = glm::vec3(0.35f, 0.40f, 0.50f);
  return map;
}

// ---------------------------------------------------------------------------
// .pk3 files

namespace {

struct ZipDiscard {
  void operator()(zip_t* z) const { zip_discard(z); }
};

std::string zipErrorString(int code) {
  zip_error_t e;
  zip_error_init_with_code(&e, code);
  std::string s = zip_error_strerror(&e);
  zip_error_fini(&e);
  return s;
}

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

constexpr std::uint64_t kMaxEntryBytes = 1ull << 30;

class Pk3Set {
 public:
  struct Entry {
    std::size_t pk3 = 0;
    zip_uint64_t index = 0;
    std::string name;  // as stored
  };

  static Result<Pk3Set> open(const std::vector<std::string>& paths) {
    if (paths.empty())
      return makeError(
          "no .pk3 files given (fetch the OpenArena packages with `hybridwalk scenes fetch`, or "
          "point HYBRIDWALK_PK3_DIR at a folder of .pk3 files)");
    Pk3Set set;
    for (const std::string& path : paths) {
      int err = 0;
      zip_t* z = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &err);
      if (!z)
        return makeError(path + ": cannot open as a .pk3 (zip) file: " + zipErrorString(err) +
                         (err == ZIP_ER_NOZIP || err == ZIP_ER_INCONS
                              ? " (a truncated or damaged download reads like this too)"
                              : ""));
      set.zips_.emplace_back(z);
      set.paths_.push_back(path);
      const zip_int64_t n = zip_get_num_entries(z, 0);
      for (zip_int64_t i = 0; i < n; ++i) {
        const char* name = zip_get_name(z, static_cast<zip_uint64_t>(i), ZIP_FL_ENC_GUESS);
        if (!name) continue;
        Entry e{set.zips_.size() - 1, static_cast<zip_uint64_t>(i), name};
        set.index_[toLower(name)] = std::move(e);  // later pk3s override earlier ones
      }
    }
    return set;
  }

  const Entry* find(const std::string& name) const {
    auto it = index_.find(toLower(name));
    return it == index_.end() ? nullptr : &it->second;
  }
  std::string describe(const Entry& e) const { return baseName(paths_[e.pk3]) + ":" + e.name; }

  Result<std::string> read(const Entry& e) const {
    zip_t* z = zips_[e.pk3].get();
    const std::string where = paths_[e.pk3] + ": entry " + e.name;
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(z, e.index, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
      return makeError(where + ": cannot read its size: " + zip_strerror(z));
    if (st.size > kMaxEntryBytes)
      return makeError(where + ": expected at most " + std::to_string(kMaxEntryBytes) +
                       " bytes, got " + std::to_string(st.size));
    std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> f(zip_fopen_index(z, e.index, 0), zip_fclose);
    if (!f) return makeError(where + ": cannot open: " + zip_strerror(z));
    std::string out(static_cast<std::size_t>(st.size), '\0');
    std::size_t got = 0;
    for (;;) {
      char probe;
      char* dst = got < out.size() ? out.data() + got : &probe;
      const zip_uint64_t want = got < out.size() ? out.size() - got : 1;
      const zip_int64_t r = zip_fread(f.get(), dst, want);
      if (r < 0) return makeError(where + ": cannot decompress: " + zip_file_strerror(f.get()));
      if (r == 0) break;
      if (got >= out.size())
        return makeError(where + ": expected " + std::to_string(out.size()) + " bytes, got more");
      got += static_cast<std::size_t>(r);
    }
    if (got != out.size())
      return makeError(where + ": truncated: expected " + std::to_string(out.size()) +
                       " bytes, got " + std::to_string(got));
    return out;
  }

  std::vector<std::string> mapNames() const {
    std::vector<std::string> names;
    for (const auto& [lower, e] : index_) {
      if (lower.rfind("maps/", 0) != 0 || lower.size() <= 9) continue;
      if (lower.compare(lower.size() - 4, 4, ".bsp") != 0) continue;
      const std::string stem = lower.substr(5, lower.size() - 9);
      if (stem.find('/') == std::string::npos) names.push_back(stem);
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  std::vector<const Entry*> withPrefixSuffix(const std::string& prefix,
                                             const std::string& suffix) const {
    std::vector<std::pair<std::string, const Entry*>> found;
    for (const auto& [lower, e] : index_)
      if (lower.rfind(prefix, 0) == 0 && lower.size() >= prefix.size() + suffix.size() &&
          lower.compare(lower.size() - suffix.size(), suffix.size(), suffix) == 0)
        found.push_back({lower, &e});
    // The game reads shader files in pak order, then by name; later definitions win.
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
      return std::tie(a.second->pk3, a.first) < std::tie(b.second->pk3, b.first);
    });
    std::vector<const Entry*> out;
    for (const auto& f : found) out.push_back(f.second);
    return out;
  }

 private:
  std::vector<std::unique_ptr<zip_t, ZipDiscard>> zips_;
  std::vector<std::string> paths_;
  std::unordered_map<std::string, Entry> index_;
};

// What the game's shader scripts say about a shader, as far as we draw it.
struct ShaderDef {
  std::string image;   // first stage image (map/clampmap/animmap)
  std::string editor;  // qer_editorimage
  bool twoSided = false;
  bool alphaTest = false;
  float alphaCutoff = 0.5f;
  glm::vec2 uvScale{1.0f};         // the first image stage's tcMod scale
  std::string skyBox;              // skyParms far box (e.g. env/sky1), "" for none
  std::set<std::string> notDrawn;  // features we do not draw
};

// Parses one scripts/*.shader text into `defs` (later definitions replace
// earlier ones). Returns a warning for a malformed file (its remaining
// shaders are ignored), or an empty string.
std::string parseShaderScript(std::string_view text, const std::string& where,
                              std::unordered_map<std::string, ShaderDef>& defs) {
  Tokenizer tok(text);
  for (;;) {
    auto name = tok.next();
    if (!name) break;
    auto open = tok.next();
    if (!open || !isBrace(*open, '{'))
      return where + ", line " + std::to_string(name->line) + ": expected '{' after shader '" +
             std::string(name->text.substr(0, 64)) + "'; the rest of the file is ignored";
    ShaderDef def;
    bool stageHasImage = false;
    int depth = 1;
    std::string stageImage;
    bool stageAlpha = false;
    float stageCutoff = 0.5f;
    glm::vec2 stageScale(1.0f);
    int stages = 0;
    std::optional<Token> t = tok.next();
    while (t && depth > 0) {
      if (isBrace(*t, '{')) {
        ++depth;
        if (depth == 2 && ++stages == 2) def.notDrawn.insert("further stages (only the first image stage is drawn)");
        stageImage.clear(), stageAlpha = false, stageScale = glm::vec2(1.0f);
        t = tok.next();
        continue;
      }
      if (isBrace(*t, '}')) {
        if (depth == 2 && !stageHasImage && !stageImage.empty()) {
          def.image = stageImage, def.alphaTest = stageAlpha, def.alphaCutoff = stageCutoff;
          def.uvScale = stageScale;
          stageHasImage = true;
        }
        if (--depth == 0) break;  // the next token is the next shader's name
        t = tok.next();
        continue;
      }
      const std::string key = toLower(std::string(t->text));
      std::vector<std::string> args;
      t = tok.next();
      while (t && !t->newLine && !isBrace(*t, '{') && !isBrace(*t, '}')) {
        args.emplace_back(t->text);
        t = tok.next();
      }
      if (depth == 1) {
        if (key == "qer_editorimage" && !args.empty()) def.editor = args[0];
        if (key == "cull" && !args.empty()) {
          const std::string a = toLower(args[0]);
          def.twoSided = a == "none" || a == "disable" || a == "twosided";
        }
        if (key == "skyparms" && !args.empty() && args[0] != "-") def.skyBox = args[0];
        if (key == "deformvertexes") def.notDrawn.insert("deformVertexes");
      } else if (depth == 2) {
        std::string img;
        if ((key == "map" || key == "clampmap") && !args.empty()) img = args[0];
        if (key == "animmap" && args.size() >= 2) {
          img = args[1];
          def.notDrawn.insert("animMap animation (first frame drawn)");
        }
        if ((key == "map" || key == "clampmap") && !args.empty() && toLower(args[0]) == "$lightmap")
          def.notDrawn.insert("lightmaps");
        if (key == "tcmod" && !args.empty()) {
          const std::string op = toLower(args[0]);
          if (op == "scale" && args.size() >= 3) {
            const float su = std::strtof(args[1].c_str(), nullptr);
            const float sv = std::strtof(args[2].c_str(), nullptr);
            if (std::isfinite(su) && std::isfinite(sv) && std::abs(su) < 1e4f && std::abs(sv) < 1e4f)
              stageScale = glm::vec2(su, sv);
          } else {
            def.notDrawn.insert("tcMod " + op);
          }
        }
        if (key == "tcgen" && !args.empty() && toLower(args[0]) != "base" &&
            toLower(args[0]) != "texture")
          def.notDrawn.insert("tcGen " + toLower(args[0]));
        if ((key == "rgbgen" || key == "alphagen") && !args.empty() &&
            toLower(args[0]) != "identity" && toLower(args[0]) != "identitylighting")
          def.notDrawn.insert(key == "rgbgen" ? "rgbGen " + toLower(args[0]) : "alphaGen " + toLower(args[0]));
        if (!img.empty() && img[0] != '$' && img[0] != '*' && stageImage.empty()) stageImage = img;
        if (key == "alphafunc" && !args.empty()) {
          const std::string a = toLower(args[0]);
          stageAlpha = true;
          stageCutoff = a == "gt0" ? 1.0f / 255.0f : 0.5f;
        }
      }
    }
    if (depth > 0)
      return where + ": shader '" + std::string(name->text.substr(0, 64)) + "' is not closed" +
             (tok.error.empty() ? "" : " (" + tok.error + ")");
    defs[toLower(std::string(name->text))] = std::move(def);
  }
  return tok.error.empty() ? "" : where + ": " + tok.error;
}

std::string stripExtension(const std::string& name) {
  const auto dot = name.find_last_of('.');
  const auto slash = name.find_last_of('/');
  return dot != std::string::npos && (slash == std::string::npos || dot > slash)
             ? name.substr(0, dot)
             : name;
}

Result<const Pk3Set::Entry*> findMap(const Pk3Set& pk3s, const std::string& mapName,
                                     const std::vector<std::string>& paths) {
  if (mapName.empty() || mapName.find('/') != std::string::npos ||
      mapName.find('\\') != std::string::npos)
    return makeError("map name '" + mapName + "': expected a bare name such as oa_dm5");
  if (const auto* e = pk3s.find("maps/" + mapName + ".bsp")) return e;
  const auto names = pk3s.mapNames();
  std::string list;
  for (std::size_t i = 0; i < names.size() && i < 60; ++i) list += (i ? ", " : "") + names[i];
  if (names.size() > 60) list += ", …";
  std::string files;
  for (std::size_t i = 0; i < paths.size() && i < 8; ++i) files += (i ? ", " : "") + paths[i];
  if (paths.size() > 8) files += ", …";
  return makeError("map '" + mapName + "': no maps/" + mapName + ".bsp in " +
                   std::to_string(paths.size()) + " pk3 file(s) (" + files + "); " +
                   (names.empty() ? std::string("they contain no maps")
                                  : std::to_string(names.size()) + " maps available: " + list));
}

}  // namespace

Result<Q3Map> loadQ3Map(const std::string& mapName, const Q3Options& options) {
  auto pk3s = Pk3Set::open(options.pk3Paths);
  if (!pk3s) return pk3s.error();
  auto entry = findMap(*pk3s, mapName, options.pk3Paths);
  if (!entry) return entry.error();
  auto bytes = pk3s->read(**entry);
  if (!bytes) return bytes.error();

  std::vector<std::string> warnings;
  std::unordered_map<std::string, ShaderDef> defs;
  for (const Pk3Set::Entry* e : pk3s->withPrefixSuffix("scripts/", ".shader")) {
    auto text = pk3s->read(*e);
    if (!text) {
      warnings.push_back(text.error().message + "; its shaders are ignored");
      continue;
    }
    std::string w = parseShaderScript(*text, pk3s->describe(*e), defs);
    if (!w.empty()) warnings.push_back(std::move(w));
  }

  std::set<std::string> decoded;  // paths whose image an earlier call returned
  std::map<std::string, int> notDrawnCount;  // feature → shaders of this map using it
  // The game's image lookup: the name without extension, as .tga, then .jpg.
  auto findImage = [&](const std::string& name) -> const Pk3Set::Entry* {
    const std::string stem = stripExtension(name);
    for (const char* ext : {".tga", ".jpg"})
      if (const auto* e = pk3s->find(stem + ext)) return e;
    return nullptr;
  };
  Q3TextureResolver resolve = [&](const std::string& shaderName) {
    Q3Texture t;
    const Pk3Set::Entry* e = nullptr;
    std::string tried;
    auto it = defs.find(toLower(shaderName));
    if (it != defs.end()) {
      t.twoSided = it->second.twoSided;
      t.alphaTest = it->second.alphaTest;
      t.alphaCutoff = it->second.alphaCutoff;
      t.uvScale = it->second.uvScale;
      for (const std::string& f : it->second.notDrawn) ++notDrawnCount[f];
      const std::string skyUp = it->second.skyBox.empty() ? "" : it->second.skyBox + "_up";
      for (const std::string& n : {it->second.image, skyUp, shaderName, it->second.editor}) {
        if (n.empty() || e) continue;
        e = findImage(n);
        tried += (tried.empty() ? "" : ", ") + stripExtension(n) + ".tga/.jpg";
      }
    } else {
      e = findImage(shaderName);
      tried = stripExtension(shaderName) + ".tga/.jpg";
    }
    if (!e) {
      t.error = "no image found (tried " + tried + " in " +
                std::to_string(options.pk3Paths.size()) + " pk3 file(s)" +
                (it == defs.end() ? "; no shader script defines it" : "") + ")";
      t.alphaTest = false;
      return t;
    }
    t.path = pk3s->describe(*e);
    if (decoded.count(t.path)) {
      t.sameAsEarlier = true;  // the scene holds it: no second copy
      return t;
    }
    auto data = pk3s->read(*e);
    if (!data) {
      t.error = data.error().message;
      return t;
    }
    std::string downscaled;
    auto img = decodeTexture(data->data(), data->size(), t.path, &downscaled);
    data = makeError("");  // the compressed bytes are not needed any more
    if (!img) {
      t.error = img.error().message;
      return t;
    }
    if (!downscaled.empty()) warnings.push_back(downscaled);
    t.image = std::move(*img);
    decoded.insert(t.path);
    return t;
  };

  auto map = parseQ3Bsp(*bytes, pk3s->describe(**entry), resolve, options);
  if (!map) return map.error();
  if (!notDrawnCount.empty()) {
    std::string list;
    for (const auto& [f, n] : notDrawnCount)
      list += (list.empty() ? "" : ", ") + f + " (" + std::to_string(n) + ")";
    map->scene.warnings.push_back(map->scene.name + ": shader features not drawn (shaders using them): " + list);
  }
  map->scene.name = mapName;
  map->scene.warnings.insert(map->scene.warnings.begin(), warnings.begin(), warnings.end());
  return map;
}

namespace {

// Does the open segment (a, b) hit a triangle of the scene? Möller–Trumbore,
// with the meshes' bounds as a cheap reject.
bool segmentBlocked(const Scene& scene, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = b - a;
  const glm::vec3 lo = glm::min(a, b), hi = glm::max(a, b);
  for (const Mesh& m : scene.meshes) {
    if (scene.materials[static_cast<std::size_t>(m.material)].sky) continue;
    if (glm::any(glm::lessThan(m.boundsMax, lo)) || glm::any(glm::greaterThan(m.boundsMin, hi)))
      continue;
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      const glm::vec3 p0 = m.vertices[m.indices[i]].position;
      const glm::vec3 e1 = m.vertices[m.indices[i + 1]].position - p0;
      const glm::vec3 e2 = m.vertices[m.indices[i + 2]].position - p0;
      const glm::vec3 pv = glm::cross(d, e2);
      const float det = glm::dot(e1, pv);
      if (std::abs(det) < 1e-12f) continue;
      const float inv = 1.0f / det;
      const glm::vec3 tv = a - p0;
      const float u = glm::dot(tv, pv) * inv;
      if (u < 0.0f || u > 1.0f) continue;
      const glm::vec3 qv = glm::cross(tv, e1);
      const float v = glm::dot(d, qv) * inv;
      if (v < 0.0f || u + v > 1.0f) continue;
      const float t = glm::dot(e2, qv) * inv;
      if (t > 1e-3f && t < 1.0f - 1e-3f) return true;
    }
  }
  return false;
}

}  // namespace

CameraPath q3SpawnWalk(const Q3Map& map, int maxKeys) {
  if (map.spawns.empty()) return flythroughPathFor(map.scene);
  const std::size_t n = map.spawns.size();
  const TriangleGrid grid(map.scene);
  // Some spawns float above the floor (the game drops the player onto it):
  // stand each one on the first surface below its feet.
  std::vector<Q3Spawn> spawns = map.spawns;
  constexpr double kOriginAboveFeet = 24.0 * kQ3MetresPerUnit;
  for (Q3Spawn& s : spawns) {
    const std::vector<double> below = grid.hitsBelow(s.origin);
    if (below.empty()) continue;
    const double drop = (s.origin.y - kOriginAboveFeet) - below.front();
    if (drop > 0.05) {
      s.origin.y -= drop;
      s.eye.y -= drop;
    }
  }
  maxKeys = std::max(maxKeys, 2);
  std::map<std::pair<std::size_t, std::size_t>, bool> clearCache;
  auto clear = [&](std::size_t i, std::size_t j) {
    const auto key = std::minmax(i, j);
    auto it = clearCache.find(key);
    if (it != clearCache.end()) return it->second;
    const bool c =
        !segmentBlocked(map.scene, glm::vec3(spawns[i].eye), glm::vec3(spawns[j].eye));
    clearCache.emplace(key, c);
    return c;
  };
  auto chainFrom = [&](std::size_t start) {
    std::vector<std::size_t> chain{start};
    std::vector<bool> used(n, false);
    used[start] = true;
    while (chain.size() < static_cast<std::size_t>(maxKeys)) {
      const glm::dvec3 from = spawns[chain.back()].eye;
      std::vector<std::pair<double, std::size_t>> order;
      for (std::size_t j = 0; j < n; ++j)
        if (!used[j] && glm::length(spawns[j].eye - from) > 0.5)
          order.push_back({glm::length(spawns[j].eye - from), j});
      std::sort(order.begin(), order.end());
      std::optional<std::size_t> next;
      for (std::size_t k = 0; k < order.size() && k < 6 && !next; ++k)
        if (clear(chain.back(), order[k].second)) next = order[k].second;
      if (!next) break;
      used[*next] = true;
      chain.push_back(*next);
    }
    return chain;
  };
  CameraPath p;
  const double diag = glm::length(glm::dvec3(map.scene.boundsMax - map.scene.boundsMin));
  p.nearPlane = 0.05;
  p.farPlane = std::clamp(1.2 * diag, 50.0, 2000.0);
  // The longest chain; among equally long ones, the one whose first view
  // sees the least sky or void (open maps: not a start looking into the sky).
  auto firstView = [&](const std::vector<std::size_t>& c) {
    glm::dvec3 dir = c.size() > 1 ? spawns[c[1]].eye - spawns[c[0]].eye : spawns[c[0]].forward;
    dir.y = 0.0;
    if (glm::length(dir) < 1e-6) dir = spawns[c[0]].forward;
    return openViewFraction(grid, spawns[c[0]].eye, dir, p.fovYDeg, p.farPlane, 12);
  };
  std::vector<std::size_t> best;
  double bestOpen = 2.0;
  for (std::size_t s = 0; s < n && s < 16; ++s) {
    auto c = chainFrom(s);
    if (c.size() < best.size()) continue;
    const double open = firstView(c);
    if (c.size() > best.size() || open < bestOpen) {
      best = std::move(c);
      bestOpen = open;
    }
  }

  p.frames = 120;
  p.keyframeEvery = 10;
  std::vector<glm::dvec3> eyes;
  for (std::size_t i : best) eyes.push_back(spawns[i].eye);
  if (eyes.size() < 2) eyes.push_back(eyes[0] + 2.0 * spawns[best[0]].forward);
  for (std::size_t k = 0; k < eyes.size(); ++k) {
    glm::dvec3 dir = k + 1 < eyes.size() ? eyes[k + 1] - eyes[k] : eyes[k] - eyes[k - 1];
    dir.y = 0.0;  // look level, along the walk
    if (glm::length(dir) < 1e-6) dir = spawns[best[std::min(k, best.size() - 1)]].forward;
    dir = glm::normalize(dir);
    // Look down a little (up to 15°) where looking level sees mostly sky.
    glm::dvec3 look = dir;
    double lookOpen = 2.0;
    for (double deg : {0.0, 5.0, 10.0, 15.0}) {
      const double a = deg * 3.14159265358979323846 / 180.0;
      const glm::dvec3 d = std::cos(a) * dir - std::sin(a) * glm::dvec3(0, 1, 0);
      const double open = openViewFraction(grid, eyes[k], d, p.fovYDeg, p.farPlane, 12);
      if (open < lookOpen - 0.02) {
        look = d;
        lookOpen = open;
      }
      if (lookOpen < 0.4) break;
    }
    p.keys.push_back({eyes[k], eyes[k] + 2.0 * look});
  }
  return p;
}

Result<std::vector<std::string>> listQ3Maps(const std::vector<std::string>& pk3Paths) {
  auto pk3s = Pk3Set::open(pk3Paths);
  if (!pk3s) return pk3s.error();
  return pk3s->mapNames();
}

Result<std::vector<Q3Spawn>> q3Spawns(const std::string& mapName, const Q3Options& options) {
  auto pk3s = Pk3Set::open(options.pk3Paths);
  if (!pk3s) return pk3s.error();
  auto entry = findMap(*pk3s, mapName, options.pk3Paths);
  if (!entry) return entry.error();
  auto bytes = pk3s->read(**entry);
  if (!bytes) return bytes.error();
  const std::string source = pk3s->describe(**entry);
  const std::string_view b(*bytes);
  if (b.size() < kHeaderBytes || b.substr(0, 4) != "IBSP" || readI32(b.data() + 4) != kBspVersion)
    return makeError(source + ": not a Quake 3 BSP (expected 'IBSP' version " +
                     std::to_string(kBspVersion) + ")");
  auto ent = lumpOf(b, source, kLumpEntities, 1);
  if (!ent) return ent.error();
  return parseQ3Spawns(std::string_view(ent->data, ent->count), source, options);
}

Q3ShaderScriptSummary summarizeQ3ShaderScript(std::string_view text, const std::string& where) {
  std::unordered_map<std::string, ShaderDef> defs;
  Q3ShaderScriptSummary out;
  out.warning = parseShaderScript(text, where, defs);
  out.shaders = defs.size();
  return out;
}

}  // namespace hw::scenes
