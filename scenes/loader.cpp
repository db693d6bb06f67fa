// Assimp-based scene loading (the only place Assimp is included) and the
// scene/camera-path spec strings of the command line.
#include "scenes/loader.h"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <stb_image.h>  // implementation compiled in core/file_io.cpp

#include <algorithm>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <sys/stat.h>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string_view>

#include "core/file_io.h"
#include "core/json_guard.h"
#include "core/memory_budget.h"
#include "core/safe_io.h"
#include "scenes/fetch.h"
#include "scenes/floor_walk.h"
#include "scenes/obj_prescan.h"
#include "scenes/outdoor_scenes.h"
#include "scenes/procedural.h"
#include "scenes/q3bsp.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kDefaultTargetTriangles = 100'000;

bool gExternalRefsAllowed = false;

// Whether `file` lies in the folder tree `root` (both made absolute and
// canonical as far as they exist, so "../" and symlinks out are seen).
bool insideTree(const fs::path& root, const fs::path& file) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(fs::absolute(file, ec), ec);
  if (ec) return false;
  const fs::path rel = c.lexically_relative(root);
  return !rel.empty() && *rel.begin() != ".." && !rel.is_absolute();
}

// Assimp's file access for one model: files outside the model's folder tree
// (unless allowed) and anything that is not a regular file (a FIFO would
// block the reader) are reported missing, and the first such request is kept
// for the error message.
class ConfinedIOSystem : public Assimp::DefaultIOSystem {
 public:
  ConfinedIOSystem(fs::path root, bool allowExternal)
      : root_(std::move(root)), allowExternal_(allowExternal) {}
  bool Exists(const char* file) const override {
    const std::string f = resolve(file);
    return allowed(f.c_str()) && DefaultIOSystem::Exists(f.c_str());
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    const std::string f = resolve(file);
    if (!allowed(f.c_str())) return nullptr;
    return DefaultIOSystem::Open(f.c_str(), mode);
  }
  const std::string& refused() const { return refused_; }

 private:
  // Some importers (LWS, Ogre) pass a referenced name as written, which the
  // default file system would look up in the working directory; others (OBJ)
  // pass the model's folder joined to it. A relative name is taken as given
  // only when that lands inside the model's folder tree, else beside the
  // model, so the working directory never decides what loads.
  std::string resolve(const char* file) const {
    std::error_code ec;
    const fs::path p(file);
    if (p.is_absolute()) return file;
    if (fs::exists(p, ec) && insideTree(root_, p)) return file;
    const fs::path beside = root_ / p;
    return fs::exists(beside, ec) ? beside.string() : std::string(file);
  }
  bool allowed(const char* file) const {
    struct stat st {};
    if (::stat(file, &st) == 0 && !S_ISREG(st.st_mode)) {
      if (refused_.empty())
        refused_ = "'" + std::string(file) + "', which is " + fileKindName(st.st_mode) +
                   " (expected a regular file)";
      return false;
    }
    if (allowExternal_ || insideTree(root_, file)) return true;
    if (refused_.empty())
      refused_ = "'" + std::string(file) + "', outside the model's folder " + root_.string() +
                 " (refused; pass --allow-external-refs to permit)";
    return false;
  }
  fs::path root_;
  bool allowExternal_;
  mutable std::string refused_;
};

// Every bufferView lies inside its buffer's declared byteLength, computed
// without wrapping: Assimp adds offset and length in 64 bits, so an offset of
// 2^64 − 4 passed its check and read before the buffer ("1 triangles", exit 0).
Status checkGltfJson(std::string_view text, const std::string& path) {
  HW_TRY(checkJsonNesting(text, path));
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return {};  // not JSON: Assimp's reader says what is wrong
  if (!j.is_object()) return {};
  // glTF 1.0: objects keyed by name where 2.0 has arrays, and no version 2.
  const nlohmann::json* version =
      j.contains("asset") && j["asset"].is_object() && j["asset"].contains("version")
          ? &j["asset"]["version"]
          : nullptr;
  const bool v1 = version ? version->is_string() && version->get<std::string>().rfind("1", 0) == 0
                          : j.contains("bufferViews") && j["bufferViews"].is_object();
  if (v1)
    return makeError(path + ": glTF 1.0 is not supported (expected glTF 2.0, asset.version \"2.0\"; "
                            "convert it, e.g. with Blender or gltf-pipeline)");
  if (!j.contains("bufferViews")) return {};
  const nlohmann::json& views = j["bufferViews"];
  const nlohmann::json* buffers = j.contains("buffers") ? &j["buffers"] : nullptr;
  if (!views.is_array()) return makeError(path + ": bufferViews: expected an array");
  auto count = [](const nlohmann::json& v, std::uint64_t* out) {
    if (!v.is_number_unsigned()) return false;
    *out = v.get<std::uint64_t>();
    return true;
  };
  for (std::size_t i = 0; i < views.size(); ++i) {
    const nlohmann::json& v = views[i];
    const std::string where = path + ": bufferViews[" + std::to_string(i) + "]";
    std::uint64_t buffer = 0, offset = 0, length = 0, bufferLength = 0;
    if (!v.is_object() || !v.contains("buffer") || !count(v["buffer"], &buffer) ||
        !v.contains("byteLength") || !count(v["byteLength"], &length) ||
        (v.contains("byteOffset") && !count(v["byteOffset"], &offset)))
      return makeError(where +
                       ": expected {buffer, byteLength, byteOffset} as non-negative integers");
    if (!buffers || !buffers->is_array() || buffer >= buffers->size() ||
        !(*buffers)[buffer].is_object() || !(*buffers)[buffer].contains("byteLength") ||
        !count((*buffers)[buffer]["byteLength"], &bufferLength))
      return makeError(where + ": buffer " + std::to_string(buffer) +
                       " does not exist or has no byteLength");
    if (offset > bufferLength || length > bufferLength - offset)
      return makeError(where + ": byteOffset " + std::to_string(offset) + " + byteLength " +
                       std::to_string(length) + " lies outside buffer " + std::to_string(buffer) +
                       " of " + std::to_string(bufferLength) + " bytes");
  }
  return {};
}

// glTF JSON nests far less than kMaxJsonDepth; Assimp's reader recurses per
// level, so deeper text would overflow the stack. .glb: the header's lengths
// must fit in the file before anything is allocated from them.
Status prescanGltf(const std::string& path, const std::string& ext) {
  auto bytes = readFile(path, 1ull << 30);
  if (!bytes) return bytes.error();
  if (ext == ".gltf") return checkGltfJson(*bytes, path);
  const std::string& b = *bytes;
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  if (b.size() < 20 || b.compare(0, 4, "glTF") != 0)
    return makeError(path + ": not a binary glTF file (expected the magic 'glTF' and a 20-byte "
                            "header, got " + std::to_string(b.size()) + " bytes)");
  if (u32(4) == 1)
    return makeError(path + ": glTF 1.0 is not supported (binary glTF version 1; expected "
                            "version 2, glTF 2.0)");
  const std::uint64_t total = u32(8), chunk0 = u32(12);
  if (total > b.size())
    return makeError(path + ": header declares " + std::to_string(total) +
                     " bytes, the file has " + std::to_string(b.size()) + " (truncated or damaged)");
  if (chunk0 > b.size() - 20)
    return makeError(path + ": first chunk declares " + std::to_string(chunk0) +
                     " bytes, only " + std::to_string(b.size() - 20) +
                     " follow the header (truncated or damaged)");
  std::size_t at = 20 + static_cast<std::size_t>(chunk0);
  while (at + 8 <= b.size()) {  // later chunks (BIN)
    const std::uint64_t len = u32(at);
    if (len > b.size() - at - 8)
      return makeError(path + ": chunk at byte " + std::to_string(at) + " declares " +
                       std::to_string(len) + " bytes, only " + std::to_string(b.size() - at - 8) +
                       " remain (truncated or damaged)");
    at += 8 + static_cast<std::size_t>(len);
  }
  if (u32(16) == 0x4E4F534Au)  // "JSON"
    return checkGltfJson(std::string_view(b).substr(20, chunk0), path);
  return {};
}

Result<Image<Rgba8>> decodeImage(const unsigned char* bytes, std::size_t size,
                                 const std::string& what, std::string* warning) {
  return decodeTexture(bytes, size, what, warning);
}

Result<Image<Rgba8>> embeddedImage(const aiTexture& t, const std::string& what,
                                   std::string* warning) {
  if (t.mHeight == 0)  // compressed (PNG/JPG… bytes), mWidth = byte count
    return decodeImage(reinterpret_cast<const unsigned char*>(t.pcData), t.mWidth, what, warning);
  Image<Rgba8> img(static_cast<int>(t.mWidth), static_cast<int>(t.mHeight));
  for (std::size_t i = 0; i < img.size(); ++i) {
    const aiTexel& s = t.pcData[i];
    img.data()[i] = Rgba8{s.r, s.g, s.b, s.a};
  }
  return img;
}

// Finds an external texture named in a model file: as written (relative to
// the model's folder), with '\' as '/', then by file name alone, then by a
// case-insensitive match in the model's folder.
std::optional<fs::path> resolveTexturePath(const fs::path& folder, std::string name) {
  std::replace(name.begin(), name.end(), '\\', '/');
  std::error_code ec;
  const fs::path p(name);
  for (const fs::path& c : {p.is_absolute() ? p : folder / p, folder / p.filename()})
    if (fs::is_regular_file(c, ec)) return c;
  std::string lower = p.filename().string();
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    std::string f = entry.path().filename().string();
    std::transform(f.begin(), f.end(), f.begin(),
                   [](unsigned char ch) { return std::tolower(ch); });
    if (f == lower && entry.is_regular_file(ec)) return entry.path();
  }
  return std::nullopt;
}

bool hasTransparency(const Image<Rgba8>& img) {
  std::size_t n = 0;
  for (const Rgba8& p : img.pixels()) n += p.a < 128;
  return n > 0;
}

struct TextureCache {
  Scene* scene;
  const aiScene* ai;
  fs::path folder;
  std::string file;
  std::map<std::string, int> byName;
  fs::path confinedTo;  // non-empty: textures must lie in this folder tree
  std::string refused;  // the first texture refused for lying outside it

  // Texture index for a material's texture reference; never fails (uses a
  // placeholder and records a warning).
  int get(const std::string& ref) {
    if (auto it = byName.find(ref); it != byName.end()) return it->second;
    Result<Image<Rgba8>> img = makeError("");
    std::string warning;  // set when the texture was downscaled
    const aiTexture* emb = nullptr;
    if (!ref.empty() && ref[0] == '*') {
      char* end = nullptr;
      const long i = std::strtol(ref.c_str() + 1, &end, 10);
      if (end && *end == 0 && i >= 0 && static_cast<unsigned long>(i) < ai->mNumTextures)
        emb = ai->mTextures[i];
    } else {
      emb = ai->GetEmbeddedTexture(ref.c_str());
    }
    if (emb) {
      img = embeddedImage(*emb, file + " (embedded texture " + ref + ")", &warning);
    } else if (ref.empty() || ref[0] == '*') {
      img = makeError(file + ": embedded texture " + ref + " does not exist");
    } else if (auto path = resolveTexturePath(folder, ref)) {
      if (!confinedTo.empty() && !insideTree(confinedTo, *path)) {
        img = makeError(file + ": texture '" + ref + "' lies outside the model's folder " +
                        confinedTo.string() + " (refused; pass --allow-external-refs to permit)");
        if (refused.empty())
          refused = "texture '" + ref + "', outside the model's folder " + confinedTo.string() +
                    " (refused; pass --allow-external-refs to permit)";
      } else {
        img = readTexture(path->string(), &warning);  // stb: PNG, JPG, TGA, BMP, …
      }
    } else {
      img = makeError(file + ": texture '" + ref + "' not found next to the model (in " +
                      folder.string() + ")");
    }
    if (!warning.empty()) scene->warnings.push_back(warning);
    Texture t;
    t.name = ref;
    if (img.ok() && !img->empty()) {
      t.image = std::move(*img);
    } else {
      scene->warnings.push_back(
          (img.ok() ? file + ": texture '" + ref + "' is empty" : img.error().message) +
          "; using a placeholder");
      t.image = missingTexture();
    }
    const int index = static_cast<int>(scene->textures.size());
    scene->textures.push_back(std::move(t));
    byName.emplace(ref, index);
    return index;
  }
};

Material convertMaterial(const aiMaterial& m, TextureCache& cache) {
  Material out;
  aiString name;
  if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) out.name = name.C_Str();
  aiColor4D c(1, 1, 1, 1);
  if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS ||
      m.Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS)
    out.baseColour = glm::vec4(c.r, c.g, c.b, c.a);
  float opacity = 1.0f;
  if (m.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS)
    out.baseColour.a = std::clamp(opacity, 0.0f, 1.0f);
  int twoSided = 0;
  if (m.Get(AI_MATKEY_TWOSIDED, twoSided) == AI_SUCCESS) out.twoSided = twoSided != 0;

  aiString tex;
  bool haveTex = m.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS;
  if (!haveTex) haveTex = m.GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS;
  if (haveTex) {
    out.texture = cache.get(tex.C_Str());
    // A textured diffuse colour of pure black (some exporters) would hide the texture.
    if (out.baseColour.r == 0 && out.baseColour.g == 0 && out.baseColour.b == 0)
      out.baseColour = glm::vec4(1, 1, 1, out.baseColour.a);
  }

  aiString alphaMode;
  const bool gltfMode = m.Get(AI_MATKEY_GLTF_ALPHAMODE, alphaMode) == AI_SUCCESS;
  if (gltfMode && std::strcmp(alphaMode.C_Str(), "OPAQUE") != 0) {
    out.alphaTest = true;
    float cutoff = 0.5f;
    if (m.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS) out.alphaCutoff = cutoff;
  } else if (!gltfMode && out.texture >= 0) {
    out.alphaTest =
        hasTransparency(cache.scene->textures[static_cast<std::size_t>(out.texture)].image);
  }
  return out;
}

// Splits `mesh` into spatially compact meshes of at most maxTris triangles
// (median cuts on triangle centroids along the longest axis).
void splitMesh(Mesh&& mesh, std::size_t maxTris, std::vector<Mesh>& out) {
  const std::size_t nt = mesh.triangleCount();
  if (maxTris == 0 || nt <= maxTris) {
    out.push_back(std::move(mesh));
    return;
  }
  std::vector<glm::vec3> centre(nt);
  for (std::size_t t = 0; t < nt; ++t)
    centre[t] = (mesh.vertices[mesh.indices[3 * t]].position +
                 mesh.vertices[mesh.indices[3 * t + 1]].position +
                 mesh.vertices[mesh.indices[3 * t + 2]].position) /
                3.0f;
  std::vector<std::uint32_t> tris(nt);
  std::iota(tris.begin(), tris.end(), 0u);
  std::vector<std::pair<std::size_t, std::size_t>> leaves;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, nt}};
  while (!stack.empty()) {
    auto [b, e] = stack.back();
    stack.pop_back();
    if (e - b <= maxTris) {
      leaves.push_back({b, e});
      continue;
    }
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t k = b; k < e; ++k) {
      lo = glm::min(lo, centre[tris[k]]);
      hi = glm::max(hi, centre[tris[k]]);
    }
    const glm::vec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const std::size_t mid = b + (e - b) / 2;
    std::nth_element(
        tris.begin() + static_cast<std::ptrdiff_t>(b),
        tris.begin() + static_cast<std::ptrdiff_t>(mid),
        tris.begin() + static_cast<std::ptrdiff_t>(e),
        [&](std::uint32_t x, std::uint32_t y) { return centre[x][axis] < centre[y][axis]; });
    stack.push_back({mid, e});
    stack.push_back({b, mid});
  }
  std::vector<std::uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
  for (std::size_t li = 0; li < leaves.size(); ++li) {
    Mesh part;
    part.name = mesh.name + "." + std::to_string(li);
    part.material = mesh.material;
    for (std::size_t k = leaves[li].first; k < leaves[li].second; ++k)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = mesh.indices[3 * tris[k] + static_cast<std::size_t>(c)];
        if (remap[v] == UINT32_MAX) {
          remap[v] = static_cast<std::uint32_t>(part.vertices.size());
          part.vertices.push_back(mesh.vertices[v]);
        }
        part.indices.push_back(remap[v]);
      }
    for (std::size_t k = leaves[li].first; k < leaves[li].second; ++k)
      for (int c = 0; c < 3; ++c)
        remap[mesh.indices[3 * tris[k] + static_cast<std::size_t>(c)]] = UINT32_MAX;
    out.push_back(std::move(part));
  }
}

// Reads "UpAxis"/"UpAxisSign" metadata; returns +2/−2 for ±Z up, 0 otherwise.
int metadataUpAxis(const aiScene& s) {
  if (!s.mMetaData) return 0;
  int axis = 1, sign = 1;
  if (!s.mMetaData->Get("UpAxis", axis)) return 0;
  s.mMetaData->Get("UpAxisSign", sign);
  return axis == 2 ? (sign < 0 ? -2 : 2) : 0;
}

std::string toLower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// "100k", "1M", "250000", "1.5M" → count; nullopt when malformed.
std::optional<double> parseCount(const std::string& s) {
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str()) return std::nullopt;
  std::string suffix(end);
  if (suffix == "k" || suffix == "K")
    v *= 1e3;
  else if (suffix == "m" || suffix == "M")
    v *= 1e6;
  else if (!suffix.empty())
    return std::nullopt;
  if (!std::isfinite(v)) return std::nullopt;
  return v;
}

struct BuiltinSpec {
  bool indoor;
  std::size_t triangles;
};

const char* const kBuiltinHelp =
    "built-in scenes: indoor, outdoor, indoor:N, outdoor:N (N = target triangles, e.g. 100k, 1M; "
    "default 100k); q3:MAP, torcs:TRACK, morse:ENV/FILE after `hybridwalk scenes fetch "
    "[--outdoor]`; `hybridwalk scenes list` names them all";

// nullopt: not a built-in name; error: a built-in name with a bad count.
Result<std::optional<BuiltinSpec>> parseBuiltin(const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string name = toLower(spec.substr(0, colon));
  if (name != "indoor" && name != "outdoor") return std::optional<BuiltinSpec>();
  BuiltinSpec b{name == "indoor", kDefaultTargetTriangles};
  if (colon != std::string::npos) {
    const std::string n = spec.substr(colon + 1);
    const auto v = parseCount(n);
    if (!v || *v < 1e3 || *v > 5e7)
      return makeError("scene '" + spec +
                       "': expected a triangle count in [1000, 50M] after ':' (e.g. " + name +
                       ":1M), got '" + n + "'");
    b.triangles = static_cast<std::size_t>(std::llround(*v));
  }
  return std::optional<BuiltinSpec>(b);
}

// Assimp 5.2's PLY reader can loop forever on a truncated body, so PLY files
// are walked here first: header, then every element record (ASCII tokens or
// binary bytes). Returns an error naming the file for a bad/truncated file.
Status checkPly(const std::string& path) {
  auto bytes = readFile(path);
  if (!bytes) return bytes.error();
  const std::string& b = *bytes;
  const std::size_t headerEnd = b.find("end_header");
  if (b.compare(0, 3, "ply") != 0 || headerEnd == std::string::npos)
    return makeError(
        path +
        ": not a PLY file (expected a header starting with 'ply' and ending with 'end_header')");
  std::size_t body = b.find('\n', headerEnd);
  if (body == std::string::npos)
    return makeError(path + ": truncated PLY header (no line after end_header)");
  ++body;

  struct Prop {
    int size = 0;       // bytes of a scalar, or of the list's items
    int countSize = 0;  // > 0: a list with a count of this many bytes
  };
  struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Prop> props;
  };
  auto typeSize = [](const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
      return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
  };
  std::istringstream header(b.substr(0, headerEnd));
  std::string line, format;
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
    } else if (word == "element") {
      Element e;
      if (!(ls >> e.name >> e.count))
        return makeError(path + ": bad PLY header line '" + line + "'");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty())
        return makeError(path + ": PLY property before any element: '" + line + "'");
      std::string t;
      ls >> t;
      Prop p;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it;
        p.countSize = typeSize(ct);
        p.size = typeSize(it);
        if (p.countSize == 0 || p.size == 0)
          return makeError(path + ": bad PLY list property '" + line + "'");
      } else {
        p.size = typeSize(t);
        if (p.size == 0) return makeError(path + ": unknown PLY property type in '" + line + "'");
      }
      elements.back().props.push_back(p);
    }
  }
  const bool ascii = format == "ascii";
  const bool little = format == "binary_little_endian", big = format == "binary_big_endian";
  if (!ascii && !little && !big)
    return makeError(path + ": unknown PLY format '" + format +
                     "' (expected ascii, binary_little_endian or binary_big_endian)");

  std::size_t pos = body;
  auto truncated = [&](const Element& e, std::uint64_t i) {
    return makeError(path + ": truncated PLY file: element '" + e.name + "' declares " +
                     std::to_string(e.count) + " records, the file ends in record " +
                     std::to_string(i));
  };
  if (ascii) {
    auto nextToken = [&](std::string_view* tok) {
      while (pos < b.size() && std::isspace(static_cast<unsigned char>(b[pos]))) ++pos;
      const std::size_t start = pos;
      while (pos < b.size() && !std::isspace(static_cast<unsigned char>(b[pos]))) ++pos;
      *tok = std::string_view(b).substr(start, pos - start);
      return pos > start;
    };
    std::string_view tok;
    for (const Element& e : elements)
      for (std::uint64_t i = 0; i < e.count; ++i)
        for (const Prop& p : e.props) {
          if (!nextToken(&tok)) return truncated(e, i);
          if (p.countSize == 0) continue;
          const double n = std::strtod(std::string(tok).c_str(), nullptr);
          if (!(n >= 0 && n < 1e9))
            return makeError(path + ": bad PLY list length '" + std::string(tok) + "'");
          for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(n); ++k)
            if (!nextToken(&tok)) return truncated(e, i);
        }
    return {};
  }
  for (const Element& e : elements)
    for (std::uint64_t i = 0; i < e.count; ++i)
      for (const Prop& p : e.props) {
        if (p.countSize == 0) {
          if (b.size() - pos < static_cast<std::size_t>(p.size)) return truncated(e, i);
          pos += static_cast<std::size_t>(p.size);
          continue;
        }
        if (b.size() - pos < static_cast<std::size_t>(p.countSize)) return truncated(e, i);
        std::uint64_t n = 0;
        for (int k = 0; k < p.countSize; ++k) {
          const auto byte = static_cast<unsigned char>(
              b[pos + static_cast<std::size_t>(little ? p.countSize - 1 - k : k)]);
          n = (n << 8) | byte;
        }
        pos += static_cast<std::size_t>(p.countSize);
        if (n > (b.size() - pos) / static_cast<std::size_t>(p.size)) return truncated(e, i);
        pos += static_cast<std::size_t>(n) * static_cast<std::size_t>(p.size);
      }
  return {};
}

}  // namespace

void setExternalRefsAllowed(bool allowed) { gExternalRefsAllowed = allowed; }
bool externalRefsAllowed() { return gExternalRefsAllowed; }

Result<Scene> loadSceneFile(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (path.empty()) return makeError("scene file: empty path");
  if (!fs::exists(path, ec)) return makeError(path + ": no such file");
  if (fs::is_directory(path, ec))
    return makeError(path + ": is a directory, expected a model file");
  auto sizeOrError = regularFileSize(path);  // devices and FIFOs are refused here
  if (!sizeOrError) return sizeOrError.error();
  if (*sizeOrError == 0) return makeError(path + ": file is empty");

  try {
    Assimp::Importer importer;
    const std::string ext = toLower(fs::path(path).extension().string());
    if (ext.empty() || !importer.IsExtensionSupported(ext)) {
      return makeError(
          path + ": unsupported format '" + (ext.empty() ? std::string("(no extension)") : ext) +
          "' (expected a model format Assimp reads, e.g. .obj, .gltf, .glb, .ply, .dae, .fbx, "
          ".3ds, .ac, .pk3)");
    }
    if (ext == ".ply") HW_TRY(checkPly(path));
    if (ext == ".gltf" || ext == ".glb") HW_TRY(prescanGltf(path, ext));
    // Assimp's OBJ import needs far more than the file's size: charge its
    // peak (counted from the text) before it starts, give it back after.
    std::uint64_t importCharge = 0;
    std::vector<std::string> objWarnings;
    if (ext == ".obj") {
      auto counts = countObjElements(path);
      if (!counts) return counts.error();
      // Assimp skips a material library it cannot open without a word.
      for (const std::string& lib : counts->mtllibs) {
        const fs::path p = fs::path(lib).is_absolute() ? fs::path(lib) : fs::path(path).parent_path() / lib;
        if (fs::equivalent(p, path, ec))
          return makeError(path + ": mtllib '" + lib + "' names the model itself (expected a .mtl file)");
        if (!fs::exists(p, ec))
          objWarnings.push_back(path + ": mtllib '" + lib + "' not found (looked for " + p.string() +
                                "); its materials are drawn in the default grey");
      }
      importCharge = objImportBytes(*counts);
      HW_TRY(chargeMemory(importCharge,
                          path + ": importing " + std::to_string(counts->faces) + " faces (" +
                              std::to_string(counts->references) + " vertex references) needs about",
                          "--max-memory raises it"));
    }
    struct Release {
      std::uint64_t bytes;
      ~Release() { releaseMemory(bytes); }
    } releaseImport{importCharge};
    fs::path root = fs::weakly_canonical(fs::absolute(path, ec), ec).parent_path();
    auto* io = new ConfinedIOSystem(root, options.allowExternalRefs);
    importer.SetIOHandler(io);  // the importer owns it
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_GenSmoothNormals |
                           aiProcess_PreTransformVertices | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType | aiProcess_FlipUVs |
                           aiProcess_ValidateDataStructure;
    const aiScene* ai = importer.ReadFile(path, flags);
    if (!io->refused().empty())
      return makeError(path + ": the model references " + io->refused());
    if (!ai) {
      const std::string why = importer.GetErrorString();
      if (why.find("No meshes remaining") != std::string::npos)
        return makeError(path + ": contains no triangle meshes (only points or lines, which are "
                                "not drawn; expected faces)");
      if (why.find("mNumMeshes is 0") != std::string::npos)
        return makeError(path + ": contains no meshes (or is not a valid " + ext + " file)");
      return makeError(path + ": cannot read model: " + why);
    }
    if (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
      return makeError(path +
                       ": incomplete or corrupt model (Assimp flagged the scene incomplete)");

    Scene scene;
    scene.name = fs::path(path).stem().string();
    scene.warnings = objWarnings;
    TextureCache cache{&scene, ai, fs::path(path).parent_path(), path, {},
                       options.allowExternalRefs ? fs::path() : root, {}};
    if (cache.folder.empty()) cache.folder = ".";
    for (unsigned i = 0; i < ai->mNumMaterials; ++i)
      scene.materials.push_back(convertMaterial(*ai->mMaterials[i], cache));
    if (!cache.refused.empty()) return makeError(path + ": the model references " + cache.refused);
    if (scene.materials.empty())
      scene.materials.push_back(Material{"default", glm::vec4(0.8f), -1});

    int up = options.zUp ? 2 : metadataUpAxis(*ai);
    auto toYUp = [up](const aiVector3D& v) {
      if (up == 2) return glm::vec3(v.x, v.z, -v.y);
      if (up == -2) return glm::vec3(v.x, -v.z, v.y);
      return glm::vec3(v.x, v.y, v.z);
    };

    std::size_t repeatedFaces = 0, facesRead = 0;
    for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
      const aiMesh& m = *ai->mMeshes[mi];
      if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || m.mNumVertices == 0) continue;
      Mesh mesh;
      mesh.name = m.mName.length ? m.mName.C_Str() : "mesh" + std::to_string(mi);
      mesh.material =
          m.mMaterialIndex < scene.materials.size() ? static_cast<int>(m.mMaterialIndex) : 0;
      mesh.vertices.resize(m.mNumVertices);
      for (unsigned v = 0; v < m.mNumVertices; ++v) {
        Vertex& out = mesh.vertices[v];
        out.position = toYUp(m.mVertices[v]);
        // Assimp's FindInvalidData would drop such a mesh silently ("No meshes
        // remaining"); say what is wrong instead.
        if (!std::isfinite(out.position.x) || !std::isfinite(out.position.y) ||
            !std::isfinite(out.position.z))
          return makeError(path + ": mesh '" + std::string(m.mName.C_Str()) + "' vertex " +
                           std::to_string(v) + " has a non-finite position (expected finite "
                           "coordinates, got NaN or Inf)");
        if (m.mNormals) {
          glm::vec3 n = toYUp(m.mNormals[v]);
          const float len = glm::length(n);
          out.normal = std::isfinite(len) && len > 0 ? n / len : glm::vec3(0, 1, 0);
        }
        if (m.mTextureCoords[0])
          out.uv = glm::vec2(m.mTextureCoords[0][v].x, m.mTextureCoords[0][v].y);
      }
      mesh.indices.reserve(static_cast<std::size_t>(m.mNumFaces) * 3);
      for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3) continue;
        for (int k = 0; k < 3; ++k) mesh.indices.push_back(face.mIndices[k]);
      }
      if (mesh.indices.empty()) continue;
      repeatedFaces += dropRepeatedTriangles(mesh);
      facesRead += m.mNumFaces;
      splitMesh(std::move(mesh), options.maxTrianglesPerMesh, scene.meshes);
    }
    if (scene.meshes.empty()) return makeError(path + ": contains no triangle meshes");
    if (repeatedFaces > 0)
      scene.warnings.push_back(path + ": " + std::to_string(repeatedFaces) + " of " +
                               std::to_string(facesRead) +
                               " faces repeat an earlier face of their mesh (the same corners); "
                               "each is drawn once");
    scene.computeBounds();
    return scene;
  } catch (const std::bad_alloc&) {
    return makeError(path + ": out of memory while reading the model (" +
                     formatBytes(memoryCharged()) + " charged to the " +
                     formatBytes(memoryBudget()) + " budget); --max-memory lowers the budget so "
                     "such a model is refused before it is read");
  } catch (const std::exception& e) {
    return makeError(path + ": cannot read model: " + e.what());
  } catch (...) {
    return makeError(path + ": cannot read model: unknown error");
  }
}

namespace {

// "q3:MAP": an OpenArena/Quake 3 map from the pk3s of the scene cache
// (`hybridwalk scenes fetch`) and of $HYBRIDWALK_PK3_DIR (scenes/fetch.h).
std::optional<std::string> q3MapName(const std::string& spec) {
  if (spec.size() > 3 && toLower(spec.substr(0, 3)) == "q3:") return spec.substr(3);
  return std::nullopt;
}

Result<Q3Map> loadQ3Spec(const std::string& mapName) {
  Q3Options o;
  o.pk3Paths = defaultPk3Paths();
  if (const std::string why = pk3SearchProblems(); o.pk3Paths.empty() && !why.empty())
    return makeError("scene 'q3:" + mapName + "': " + why + " (expected a folder holding .pk3 files)");
  if (o.pk3Paths.empty())
    return makeError("scene 'q3:" + mapName + "': no .pk3 files in " + defaultSceneCacheDir() +
                     "/root or $HYBRIDWALK_PK3_DIR (run `hybridwalk scenes fetch` first)");
  return loadQ3Map(mapName, o);
}

}  // namespace

namespace {
Result<Scene> loadSceneUnscoped(const std::string& spec) {
  std::error_code ec;
  if (auto outdoor = loadOutdoorSpec(spec)) return std::move(*outdoor);  // .acc, .blend, torcs:, morse:
  if (!spec.empty() && fs::exists(spec, ec)) return loadSceneFile(spec);
  if (auto q3 = q3MapName(spec)) {
    auto map = loadQ3Spec(*q3);
    if (!map) return map.error();
    return std::move(map->scene);
  }
  auto builtin = parseBuiltin(spec);
  if (!builtin) return builtin.error();
  if (*builtin) {
    const BuiltinSpec b = **builtin;
    return b.indoor ? makeIndoorScene(b.triangles) : makeOutdoorScene(b.triangles);
  }
  return makeError("scene '" + spec + "': no such file and not a built-in scene (" + kBuiltinHelp +
                   ")");
}
}  // namespace

Result<Scene> loadScene(const std::string& spec) {
  MemoryScope scope;  // what the load charges is held by the scene, or given back
  try {
    auto s = loadSceneUnscoped(spec);
    if (!scope.refused().empty()) return makeError(scope.refused());
    if (!s) return s;
    // The meshes, once loaded: the renderer uploads a copy of them.
    std::uint64_t meshBytes = 0;
    for (const Mesh& m : s->meshes)
      meshBytes += m.vertices.size() * sizeof(Vertex) + m.indices.size() * sizeof(m.indices[0]);
    HW_TRY(chargeMemory(meshBytes, "scene " + spec + ": meshes of " +
                                       std::to_string(s->triangleCount()) + " triangles",
                        "--max-memory raises it"));
    s->memory = scope.keep();
    return s;
  } catch (const std::bad_alloc&) {
    return makeError("scene '" + spec + "': out of memory while loading (" +
                     formatBytes(memoryCharged()) + " charged to the " +
                     formatBytes(memoryBudget()) + " memory budget; --max-memory)");
  }
}

Result<CameraPath> defaultPathFor(const std::string& spec) {
  return defaultPathFor(spec, DefaultPathOptions{}, nullptr);
}

Result<CameraPath> defaultPathFor(const std::string& spec, const DefaultPathOptions& options,
                                  std::vector<std::string>* notes) {
  std::error_code ec;
  if (auto outdoor = outdoorDefaultPath(spec, options, notes)) return std::move(*outdoor);
  if (auto q3 = q3MapName(spec); q3 && !fs::exists(spec, ec)) {
    auto map = loadQ3Spec(*q3);
    if (!map) return map.error();
    return q3SpawnWalk(*map);
  }
  if (spec.empty() || !fs::exists(spec, ec)) {
    auto builtin = parseBuiltin(spec);
    if (!builtin) return builtin.error();
    if (*builtin) return (*builtin)->indoor ? defaultIndoorPath() : defaultOutdoorPath();
    return makeError("scene '" + spec + "': no such file and not a built-in scene (" +
                     kBuiltinHelp + ")");
  }
  auto scene = loadSceneFile(spec);
  if (!scene) return scene.error();
  FloorWalkOptions walk;
  walk.eyeHeight = options.eyeHeight;
  auto floor = floorWalkPath(*scene, walk);
  if (floor) return framedDefaultPath(*scene, std::move(*floor), notes);
  if (notes) notes->push_back(floor.error().message + "; the default path orbits the bounds instead");
  return framedDefaultPath(*scene, flythroughPathFor(*scene), notes);
}

}  // namespace hw::scenes
