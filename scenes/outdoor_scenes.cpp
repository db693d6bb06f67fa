// TORCS tracks (our AC3D parser), MORSE .blend environments (Assimp, node
// tree walked so that the SkyBox can be hidden), the grid queries and the
// camera paths built on them. See outdoor_scenes.h for the contracts.
#include "scenes/outdoor_scenes.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <fcntl.h>
#include <signal.h>
#include <stb_image.h>  // implementation compiled in core/file_io.cpp
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include "core/file_io.h"
#include "scenes/fetch.h"
#include "scenes/floor_walk.h"
#include "scenes/torcs_track.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxAcDepth = 256;  // object nesting; deeper files are refused, not recursed into
// Largest count a declared numvert/refs may reserve before its lines are read.
constexpr long long kAcReserveLimit = 1 << 16;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool hasCutout(const Image<Rgba8>& img) {
  for (const Rgba8& p : img.pixels())
    if (p.a < 128) return true;
  return false;
}

Result<Image<Rgba8>> decodeStb(const std::string& bytes, const std::string& what) {
  if (bytes.empty() || bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    return makeError("cannot decode image " + what + ": empty or too large");
  std::string downscaled;  // TORCS/MORSE textures are far below the limit; not reported
  return decodeTexture(bytes.data(), bytes.size(), what, &downscaled);
}

bool isSgi(const std::string& bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x01 &&
         static_cast<unsigned char>(bytes[1]) == 0xDA;
}

Result<Image<Rgba8>> decodeAnyImage(const std::string& bytes, const std::string& what) {
  return isSgi(bytes) ? decodeSgiImage(bytes, what) : decodeStb(bytes, what);
}

// First file found: dir/name, dir/filename(name), then a case-insensitive
// file-name match in dir; for each dir in order.
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

// Groups triangles into meshes per (material, ground cell). Vertices are
// given per batch (a surface, an Assimp mesh) by batch-local index and
// shared within a batch and mesh.
class ChunkBuilder {
 public:
  ChunkBuilder(Scene& scene, double cellSize) : scene_(scene), cell_(cellSize) {}

  void beginBatch() { remap_.clear(); }

  void addTriangle(int material, const std::vector<Vertex>& verts, std::uint32_t i0,
                   std::uint32_t i1, std::uint32_t i2) {
    const glm::vec3 c = (verts[i0].position + verts[i1].position + verts[i2].position) / 3.0f;
    int cx = 0, cz = 0;
    if (cell_ > 0) {
      cx = static_cast<int>(std::floor(std::clamp(c.x / cell_, -1e6, 1e6)));
      cz = static_cast<int>(std::floor(std::clamp(c.z / cell_, -1e6, 1e6)));
    }
    const auto key = std::make_tuple(material, cx, cz);
    auto it = meshOf_.find(key);
    if (it == meshOf_.end()) {
      Mesh m;
      m.material = material;
      m.name = scene_.materials[static_cast<std::size_t>(material)].name + "@" +
               std::to_string(cx) + "," + std::to_string(cz);
      scene_.meshes.push_back(std::move(m));
      it = meshOf_.emplace(key, scene_.meshes.size() - 1).first;
    }
    Mesh& mesh = scene_.meshes[it->second];
    for (std::uint32_t i : {i0, i1, i2}) {
      const std::uint64_t k = (static_cast<std::uint64_t>(it->second) << 32) | i;
      auto [r, inserted] = remap_.try_emplace(k, static_cast<std::uint32_t>(mesh.vertices.size()));
      if (inserted) mesh.vertices.push_back(verts[i]);
      mesh.indices.push_back(r->second);
    }
  }

 private:
  Scene& scene_;
  double cell_;
  std::map<std::tuple<int, int, int>, std::size_t> meshOf_;
  std::unordered_map<std::uint64_t, std::uint32_t> remap_;
};

bool degenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float e =
      std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
  // sin(smallest angle) below ~1e-6: zero area, or a needle no raster shows.
  return !(glm::length(n) > 1e-6f * e) || !std::isfinite(e);
}

// ------------------------------------------------------------------ AC3D

struct AcMaterial {
  glm::vec4 rgba{1.0f};
};

struct AcTransform {
  glm::mat3 rot{1.0f};
  glm::vec3 loc{0.0f};
};

class AcParser {
 public:
  AcParser(const std::string& text, std::string source, std::vector<fs::path> textureDirs,
           const Ac3dOptions& options)
      : text_(text),
        source_(std::move(source)),
        dirs_(std::move(textureDirs)),
        options_(options),
        builder_(out_.scene, options.chunkSizeMetres) {}

  Result<Ac3dModel> run() {
    std::string_view line;
    if (!next(&line) || line.substr(0, 4) != "AC3D")
      return fail("expected the header 'AC3Db' (not an AC3D file)", line);
    while (next(&line)) {
      const std::string_view kw = keyword(line);
      if (kw == "MATERIAL") {
        HW_TRY(material(line));
      } else if (kw == "OBJECT") {
        HW_TRY(object(line, AcTransform{}, 0));
      } else {
        return fail("expected MATERIAL or OBJECT at top level", line);
      }
    }
    if (out_.scene.meshes.empty())
      return makeError(source_ + ": contains no triangles (" + std::to_string(out_.stats.objects) +
                       " objects, " + std::to_string(out_.stats.surfaces) + " surfaces)");
    out_.scene.computeBounds();
    return std::move(out_);
  }

 private:
  // Next non-blank line (comments '#' skipped), CR stripped.
  bool next(std::string_view* line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      std::string_view l(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++lineNo_;
      while (!l.empty() && (l.back() == '\r' || std::isspace(static_cast<unsigned char>(l.back()))))
        l.remove_suffix(1);
      while (!l.empty() && std::isspace(static_cast<unsigned char>(l.front()))) l.remove_prefix(1);
      if (l.empty() || l.front() == '#') continue;
      *line = l;
      return true;
    }
    *line = {};
    return false;
  }

  static std::string_view keyword(std::string_view line) {
    const std::size_t sp = line.find_first_of(" \t");
    return sp == std::string_view::npos ? line : line.substr(0, sp);
  }
  static std::string_view rest(std::string_view line) {
    const std::size_t sp = line.find_first_of(" \t");
    if (sp == std::string_view::npos) return {};
    line.remove_prefix(sp);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front())))
      line.remove_prefix(1);
    return line;
  }

  Error fail(const std::string& what, std::string_view got) const {
    std::string g(got.substr(0, 80));
    return makeError(source_ + ":" + std::to_string(lineNo_) + ": " + what + ", got '" + g + "'");
  }
  Error eof(const std::string& what) const {
    return makeError(source_ + ":" + std::to_string(lineNo_) + ": file ends early: expected " +
                     what);
  }

  // Reads up to `n` numbers from `s`; returns how many were read. Stops at
  // the first token that is not a number.
  static int numbers(std::string_view s, double* out, int n) {
    int k = 0;
    const char* p = s.data();
    const char* end = s.data() + s.size();
    while (k < n) {
      while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (p == end) break;
      double v = 0;
      auto [q, ec] = std::from_chars(p, end, v);
      if (ec != std::errc() || !std::isfinite(v)) break;
      out[k++] = v;
      p = q;
    }
    return k;
  }
  static bool integer(std::string_view s, long long* v) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    int base = 10;
    if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
      base = 16;
      s.remove_prefix(2);
    }
    auto [q, ec] = std::from_chars(s.data(), s.data() + s.size(), *v, base);
    return ec == std::errc() && q != s.data();
  }
  static std::string quoted(std::string_view s) {
    if (!s.empty() && s.front() == '"') {
      s.remove_prefix(1);
      const std::size_t q = s.find('"');
      return std::string(q == std::string_view::npos ? s : s.substr(0, q));
    }
    return std::string(keyword(s));
  }

  Status material(std::string_view line) {
    // MATERIAL "name" rgb r g b amb … emis … spec … shi n trans t
    AcMaterial m;
    const std::size_t rgb = line.find(" rgb ");
    double c[3] = {1, 1, 1};
    if (rgb == std::string_view::npos || numbers(line.substr(rgb + 5), c, 3) != 3)
      return fail("expected MATERIAL \"name\" rgb R G B ...", line);
    double trans = 0;
    if (const std::size_t t = line.find(" trans "); t != std::string_view::npos)
      numbers(line.substr(t + 7), &trans, 1);
    m.rgba = glm::vec4(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]),
                       static_cast<float>(1.0 - std::clamp(trans, 0.0, 1.0)));
    acMaterials_.push_back(m);
    return {};
  }

  int textureIndex(const std::string& name) {
    if (auto it = textureByName_.find(name); it != textureByName_.end()) return it->second;
    Texture t;
    t.name = name;
    Result<Image<Rgba8>> img = makeError("");
    if (auto p = findTexture(dirs_, name)) {
      auto bytes = readFile(p->string());
      img = bytes ? decodeAnyImage(*bytes, p->string()) : Result<Image<Rgba8>>(bytes.error());
    } else {
      std::string where;
      for (const fs::path& d : dirs_) where += (where.empty() ? "" : ", ") + d.string();
      img = makeError(source_ + ": texture '" + name + "' not found (looked in " + where + ")");
    }
    if (img.ok() && !img->empty()) {
      t.image = std::move(*img);
    } else {
      ++out_.stats.missingTextures;
      out_.scene.warnings.push_back(
          (img.ok() ? source_ + ": texture '" + name + "' is empty" : img.error().message) +
          "; using a checker");
      t.image = missingTexture();
    }
    const int i = static_cast<int>(out_.scene.textures.size());
    out_.scene.textures.push_back(std::move(t));
    textureByName_.emplace(name, i);
    return i;
  }

  int materialIndex(int acMat, const std::string& texture, bool twoSided) {
    const auto key = std::make_tuple(acMat, texture, twoSided);
    if (auto it = materialByKey_.find(key); it != materialByKey_.end()) return it->second;
    Material m;
    const glm::vec4 rgba = acMaterials_[static_cast<std::size_t>(acMat)].rgba;
    m.name = (texture.empty() ? "mat" + std::to_string(acMat) : fs::path(texture).stem().string()) +
             (twoSided ? "+2s" : "");
    m.twoSided = twoSided;
    m.baseColour = rgba;
    if (!texture.empty()) {
      m.texture = textureIndex(texture);
      // TORCS lights textured track surfaces to about the texture's own
      // colour (emission 0.4 + ambient + diffuse); the AC grey would darken it.
      m.baseColour = glm::vec4(1.0f, 1.0f, 1.0f, rgba.a);
      const auto& img = out_.scene.textures[static_cast<std::size_t>(m.texture)].image;
      if (hasCutout(img)) {
        m.alphaTest = true;
        const std::string l = lower(texture);
        if (l.find("tree") != std::string::npos || l.find("trans-") != std::string::npos ||
            l.find("arbor") != std::string::npos)
          m.alphaCutoff = options_.foliageAlphaCutoff;
      }
    }
    const int i = static_cast<int>(out_.scene.materials.size());
    out_.scene.materials.push_back(m);
    out_.materialTextureNames.push_back(texture);
    materialByKey_.emplace(key, i);
    return i;
  }

  Status object(std::string_view header, const AcTransform& parent, int depth) {
    if (depth > kMaxAcDepth)
      return fail("objects nested deeper than " + std::to_string(kMaxAcDepth), header);
    ++out_.stats.objects;
    std::string baseTexture;
    bool sawBase = false;
    int layers = 0;
    double texrep[2] = {1, 1}, texoff[2] = {0, 0};
    AcTransform local;
    std::vector<glm::vec3> positions, normals;
    bool haveNormals = true;
    struct Pending {  // surfaces wait for `kids`, as loc/rot may follow them
      int flags;
      int mat;
      std::vector<std::array<double, 3>> refs;  // vertex index, u, v
    };
    std::vector<Pending> surfaces;
    std::string_view line;
    long long kids = -1;
    while (kids < 0) {
      if (!next(&line)) return eof("'kids N' to end the OBJECT started earlier");
      const std::string_view kw = keyword(line), arg = rest(line);
      long long n = 0;
      if (kw == "name" || kw == "url" || kw == "crease" || kw == "subdiv" || kw == "hidden" ||
          kw == "locked" || kw == "folded") {
        continue;
      } else if (kw == "data") {
        if (!integer(arg, &n) || n < 0 ||
            static_cast<std::size_t>(n) > text_.size() - std::min(pos_, text_.size()))
          return fail("expected 'data N' with N bytes following", line);
        pos_ += static_cast<std::size_t>(n);  // the data bytes, then their newline
        if (pos_ < text_.size() && text_[pos_] == '\r') ++pos_;
        if (pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
      } else if (kw == "texture") {
        // TORCS: `texture "X" base|tiled|skids|shad`; only the base layer
        // (or a plain `texture "X"`) is the surface colour.
        ++layers;
        std::string_view a = arg;
        if (a.empty()) return fail("expected 'texture \"NAME\" [base|tiled|skids|shad]'", line);
        std::string name = quoted(a);
        std::string_view tail =
            a.front() == '"' ? a.substr(std::min(a.size(), name.size() + 2)) : rest(a);
        while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.front())))
          tail.remove_prefix(1);
        const std::string_view layer = keyword(tail);
        if (layer.empty() || layer == "base") {
          baseTexture = name == "empty_texture_no_mapping" ? "" : name;
          sawBase = true;
        }
      } else if (kw == "texrep" || kw == "texoff") {
        double* v = kw == "texrep" ? texrep : texoff;
        if (numbers(arg, v, 2) != 2) return fail("expected '" + std::string(kw) + " U V'", line);
      } else if (kw == "rot") {
        double r[9];
        if (numbers(arg, r, 9) != 9) return fail("expected 'rot' with 9 numbers", line);
        local.rot = glm::mat3(glm::vec3(r[0], r[1], r[2]), glm::vec3(r[3], r[4], r[5]),
                              glm::vec3(r[6], r[7], r[8]));
      } else if (kw == "loc") {
        double l[3];
        if (numbers(arg, l, 3) != 3) return fail("expected 'loc X Y Z'", line);
        local.loc = glm::vec3(l[0], l[1], l[2]);
      } else if (kw == "numvert") {
        if (!integer(arg, &n) || n < 0 || n > 50'000'000) return fail("expected 'numvert N'", line);
        // Grown as lines arrive: a declared count allocates nothing by
        // itself (an 84-byte file declaring 50M vertices took 1.2 GB).
        positions.clear();
        normals.clear();
        positions.reserve(static_cast<std::size_t>(std::min<long long>(n, kAcReserveLimit)));
        normals.reserve(positions.capacity());
        for (long long i = 0; i < n; ++i) {
          if (!next(&line)) return eof(std::to_string(n) + " vertex lines after numvert");
          double v[6];
          const int k = numbers(line, v, 6);
          if (k < 3) return fail("expected a vertex 'X Y Z [NX NY NZ]'", line);
          positions.push_back(glm::vec3(v[0], v[1], v[2]));
          if (k == 6)
            normals.push_back(glm::vec3(v[3], v[4], v[5]));
          else {
            normals.push_back(glm::vec3(0.0f));
            haveNormals = false;
          }
        }
      } else if (kw == "numsurf") {
        if (!integer(arg, &n) || n < 0 || n > 50'000'000) return fail("expected 'numsurf N'", line);
        for (long long s = 0; s < n; ++s) {
          if (!next(&line)) return eof("SURF record");
          long long flags = 0;
          if (keyword(line) != "SURF" || !integer(rest(line), &flags))
            return fail("expected 'SURF FLAGS'", line);
          // Material 0 unless a 'mat' line follows: there must be one.
          if (acMaterials_.empty())
            return fail("expected a MATERIAL line before the first SURF (a surface uses "
                        "material 0 unless it says 'mat N')",
                        line);
          Pending p{static_cast<int>(flags), 0, {}};
          bool gotRefs = false;
          while (!gotRefs) {
            if (!next(&line)) return eof("'mat N' / 'refs N' of a SURF");
            const std::string_view skw = keyword(line);
            long long v = 0;
            if (skw == "mat") {
              if (!integer(rest(line), &v) || v < 0 ||
                  static_cast<std::size_t>(v) >= acMaterials_.size())
                return fail("expected 'mat I' with I < " + std::to_string(acMaterials_.size()) +
                                " (the MATERIALs so far)",
                            line);
              p.mat = static_cast<int>(v);
            } else if (skw == "refs") {
              if (!integer(rest(line), &v) || v < 0 || v > 10'000'000)
                return fail("expected 'refs N'", line);
              p.refs.clear();
              p.refs.reserve(static_cast<std::size_t>(std::min<long long>(v, kAcReserveLimit)));
              for (long long ri = 0; ri < v; ++ri) {
                auto& r = p.refs.emplace_back();
                if (!next(&line)) return eof("a 'INDEX U V' line of refs");
                double q[3] = {0, 0, 0};
                if (numbers(line, q, 3) < 1 || q[0] < 0 ||
                    q[0] >= static_cast<double>(positions.size()) || q[0] != std::floor(q[0]))
                  return fail("expected 'INDEX U V' with INDEX < numvert " +
                                  std::to_string(positions.size()),
                              line);
                r = {q[0], q[1], q[2]};
              }
              gotRefs = true;
            } else {
              return fail("expected 'mat' or 'refs' in a SURF", line);
            }
          }
          surfaces.push_back(std::move(p));
        }
      } else if (kw == "kids") {
        if (!integer(arg, &n) || n < 0 || n > 10'000'000) return fail("expected 'kids N'", line);
        kids = n;
      } else {
        return fail("unknown OBJECT keyword '" + std::string(kw) + "'", line);
      }
    }
    (void)sawBase;
    if (layers > 1) ++out_.stats.multiLayerObjects;

    AcTransform world;
    world.rot = parent.rot * local.rot;
    world.loc = parent.rot * local.loc + parent.loc;
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(world.rot));

    std::vector<Vertex> verts;
    std::vector<std::uint32_t> tri;
    for (const Pending& s : surfaces) {
      ++out_.stats.surfaces;
      const int type = s.flags & 0x0F;
      const bool twoSided = (s.flags & 0x20) != 0;
      if (twoSided) ++out_.stats.twoSidedSurfaces;
      if (type == 1 || type == 2) {
        ++out_.stats.lineSurfaces;
        continue;
      }
      if (s.refs.size() < 3) continue;
      verts.resize(s.refs.size());
      for (std::size_t i = 0; i < s.refs.size(); ++i) {
        const auto vi = static_cast<std::size_t>(s.refs[i][0]);
        Vertex& v = verts[i];
        v.position = world.rot * positions[vi] + world.loc;
        v.normal = haveNormals ? normalMatrix * normals[vi] : glm::vec3(0.0f);
        const double u = s.refs[i][1] * texrep[0] + texoff[0];
        const double t = s.refs[i][2] * texrep[1] + texoff[1];
        v.uv = glm::vec2(static_cast<float>(u),
                         static_cast<float>(1.0 - t));  // AC: v = 0 at the bottom
      }
      tri.clear();
      const std::size_t n = s.refs.size();
      auto add = [&](std::size_t a, std::size_t b, std::size_t c) {
        const bool sameIndex = s.refs[a][0] == s.refs[b][0] || s.refs[b][0] == s.refs[c][0] ||
                               s.refs[a][0] == s.refs[c][0];
        if (sameIndex || degenerate(verts[a].position, verts[b].position, verts[c].position)) {
          ++out_.stats.degenerateTriangles;
          return;
        }
        tri.insert(tri.end(), {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                               static_cast<std::uint32_t>(c)});
      };
      if (type == 4) {  // TORCS triangle strip, GL order
        for (std::size_t i = 0; i + 2 < n; ++i)
          (i % 2 == 0) ? add(i, i + 1, i + 2) : add(i + 1, i, i + 2);
      } else {  // polygon: a fan, as plib draws it
        for (std::size_t i = 1; i + 1 < n; ++i) add(0, i, i + 1);
      }
      if (tri.empty()) continue;
      // Missing or zero normals: from the surface's own triangles.
      std::vector<glm::vec3> acc(n, glm::vec3(0.0f));
      for (std::size_t k = 0; k < tri.size(); k += 3) {
        const glm::vec3 fn = glm::cross(verts[tri[k + 1]].position - verts[tri[k]].position,
                                        verts[tri[k + 2]].position - verts[tri[k]].position);
        for (int j = 0; j < 3; ++j) acc[tri[k + static_cast<std::size_t>(j)]] += fn;
      }
      for (std::size_t i = 0; i < n; ++i) {
        const float len = glm::length(verts[i].normal);
        if (len > 1e-6f && std::isfinite(len)) {
          verts[i].normal /= len;
        } else {
          const float al = glm::length(acc[i]);
          verts[i].normal = al > 0 && std::isfinite(al) ? acc[i] / al : glm::vec3(0, 1, 0);
        }
      }
      const int material = materialIndex(s.mat, baseTexture, twoSided);
      builder_.beginBatch();
      for (std::size_t k = 0; k < tri.size(); k += 3)
        builder_.addTriangle(material, verts, tri[k], tri[k + 1], tri[k + 2]);
    }

    for (long long k = 0; k < kids; ++k) {
      if (!next(&line)) {
        // TORCS' own loader stops quietly here ("bad hack for buggy .acc
        // format"): trackgen writes kid counts larger than what follows.
        out_.scene.warnings.push_back(source_ + ": an OBJECT declares " + std::to_string(kids) +
                                      " kids, the file ends after " + std::to_string(k));
        break;
      }
      // TORCS' loader accepts MATERIAL lines among kids; so do we.
      if (keyword(line) == "MATERIAL") {
        HW_TRY(material(line));
        --k;
        continue;
      }
      if (keyword(line) != "OBJECT") return fail("expected a kid 'OBJECT TYPE'", line);
      HW_TRY(object(line, world, depth + 1));
    }
    return {};
  }

  const std::string& text_;
  std::string source_;
  std::vector<fs::path> dirs_;
  Ac3dOptions options_;
  Ac3dModel out_;
  ChunkBuilder builder_;
  std::size_t pos_ = 0;
  std::size_t lineNo_ = 0;
  std::vector<AcMaterial> acMaterials_;
  std::map<std::string, int> textureByName_;
  std::map<std::tuple<int, std::string, bool>, int> materialByKey_;
};

// ------------------------------------------------------------------ Blender

struct BlendLoader {
  const aiScene* ai;
  std::string path;
  fs::path folder;
  BlendOptions options;
  Scene scene;
  ChunkBuilder builder;
  std::vector<int> materialOf;  // Assimp material → ours

  BlendLoader(const aiScene* s, std::string p, const BlendOptions& o)
      : ai(s),
        path(std::move(p)),
        folder(fs::path(path).parent_path()),
        options(o),
        builder(scene, o.chunkSizeMetres) {
    if (folder.empty()) folder = ".";
  }

  void materials() {
    bool warnedProcedural = false;
    for (unsigned i = 0; i < ai->mNumMaterials; ++i) {
      const aiMaterial& am = *ai->mMaterials[i];
      Material m;
      aiString name;
      if (am.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
      aiColor4D c(0.8f, 0.8f, 0.8f, 1.0f);
      am.Get(AI_MATKEY_COLOR_DIFFUSE, c);
      m.baseColour = glm::vec4(c.r, c.g, c.b, 1.0f);
      m.twoSided = true;
      aiString tex;
      if (am.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == AI_SUCCESS) {
        const std::string ref = tex.C_Str();
        Result<Image<Rgba8>> img = makeError("");
        bool procedural = false;
        if (ref.rfind("Procedural", 0) == 0) {
          procedural = true;
        } else if (const aiTexture* e = ai->GetEmbeddedTexture(ref.c_str())) {
          if (e->mHeight == 0) {
            img = decodeAnyImage(std::string(reinterpret_cast<const char*>(e->pcData), e->mWidth),
                                 path + " (embedded " + ref + ")");
          } else {
            Image<Rgba8> raw(static_cast<int>(e->mWidth), static_cast<int>(e->mHeight));
            for (std::size_t k = 0; k < raw.size(); ++k)
              raw.data()[k] = Rgba8{e->pcData[k].r, e->pcData[k].g, e->pcData[k].b, e->pcData[k].a};
            img = std::move(raw);
          }
        } else if (auto p = findTexture({folder}, ref)) {
          auto bytes = readFile(p->string());
          img = bytes ? decodeAnyImage(*bytes, p->string()) : Result<Image<Rgba8>>(bytes.error());
        } else {
          img = makeError(path + ": texture '" + ref + "' not found in " + folder.string());
        }
        if (procedural) {
          if (!warnedProcedural)
            scene.warnings.push_back(path +
                                     ": Blender procedural textures cannot be evaluated; their "
                                     "materials use the diffuse colour (first: " +
                                     m.name + ")");
          warnedProcedural = true;
        } else if (img.ok() && !img->empty()) {
          m.texture = static_cast<int>(scene.textures.size());
          m.alphaTest = hasCutout(*img);
          scene.textures.push_back(Texture{ref, std::move(*img)});
          m.baseColour = glm::vec4(1.0f);
        } else {
          scene.warnings.push_back(
              (img.ok() ? path + ": texture '" + ref + "' is empty" : img.error().message) +
              "; material '" + m.name + "' uses its diffuse colour");
        }
      }
      materialOf.push_back(static_cast<int>(scene.materials.size()));
      scene.materials.push_back(m);
    }
    if (scene.materials.empty()) scene.materials.push_back(Material{"default", glm::vec4(0.8f)});
  }

  glm::vec3 toYUp(const aiVector3D& v) const {
    return options.zUp ? glm::vec3(v.x, v.z, -v.y) : glm::vec3(v.x, v.y, v.z);
  }

  void node(const aiNode& n, const aiMatrix4x4& parent, int depth) {
    if (depth > 512) return;
    const std::string name = n.mName.C_Str();
    for (const std::string& h : options.hiddenNodes)
      if (h == name) return;
    bool ownMeshes = true;
    for (const std::string& h : options.hiddenNodePrefixes)
      if (name.rfind(h, 0) == 0) ownMeshes = false;
    const aiMatrix4x4 m = parent * n.mTransformation;
    aiMatrix3x3 nm(m);
    nm.Inverse().Transpose();
    std::vector<Vertex> verts;
    for (unsigned k = 0; ownMeshes && k < n.mNumMeshes; ++k) {
      const aiMesh& mesh = *ai->mMeshes[n.mMeshes[k]];
      if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      verts.resize(mesh.mNumVertices);
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        verts[v].position = toYUp(m * mesh.mVertices[v]);
        glm::vec3 nn(0, 1, 0);
        if (mesh.mNormals) {
          nn = toYUp(nm * mesh.mNormals[v]);
          const float len = glm::length(nn);
          nn = len > 0 && std::isfinite(len) ? nn / len : glm::vec3(0, 1, 0);
        }
        verts[v].normal = nn;
        verts[v].uv = mesh.mTextureCoords[0]
                          ? glm::vec2(mesh.mTextureCoords[0][v].x, mesh.mTextureCoords[0][v].y)
                          : glm::vec2(0.0f);
      }
      const int mat = mesh.mMaterialIndex < materialOf.size() ? materialOf[mesh.mMaterialIndex] : 0;
      builder.beginBatch();
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;
        const unsigned a = face.mIndices[0], b = face.mIndices[1], c = face.mIndices[2];
        if (a >= verts.size() || b >= verts.size() || c >= verts.size() || a == b || b == c ||
            a == c || degenerate(verts[a].position, verts[b].position, verts[c].position))
          continue;
        builder.addTriangle(mat, verts, a, b, c);
      }
    }
    for (unsigned k = 0; k < n.mNumChildren; ++k) node(*n.mChildren[k], m, depth + 1);
  }
};

// ------------------------------------------------------------------ paths helpers

double polylineLength(const std::vector<glm::dvec3>& p, bool closed) {
  double len = 0;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) len += glm::length(p[i + 1] - p[i]);
  if (closed && p.size() > 1) len += glm::length(p.front() - p.back());
  return len;
}

// Point at arc length s of a closed polyline (s wraps).
glm::dvec3 pointAtClosed(const std::vector<glm::dvec3>& p, const std::vector<double>& cum,
                         double total, double s) {
  s = std::fmod(s, total);
  if (s < 0) s += total;
  const auto it = std::upper_bound(cum.begin(), cum.end(), s);
  const std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - cum.begin() - 1));
  const glm::dvec3& a = p[i];
  const glm::dvec3& b = p[(i + 1) % p.size()];
  const double seg = (i + 1 < cum.size() ? cum[i + 1] : total) - cum[i];
  const double t = seg > 0 ? (s - cum[i]) / seg : 0.0;
  return a + (b - a) * t;
}

}  // namespace

// ================================================================== public

Result<Image<Rgba8>> decodeSgiImage(const std::string& b, const std::string& what) {
  auto u8 = [&](std::size_t o) { return static_cast<unsigned>(static_cast<unsigned char>(b[o])); };
  auto u16 = [&](std::size_t o) { return (u8(o) << 8) | u8(o + 1); };
  auto u32 = [&](std::size_t o) { return (u16(o) << 16) | u16(o + 2); };
  if (b.size() < 512 || !isSgi(b))
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

Result<Ac3dModel> parseAc3d(const std::string& text, const std::string& source,
                            const std::string& folder, const Ac3dOptions& options) {
  std::vector<fs::path> dirs{folder.empty() ? fs::path(".") : fs::path(folder)};
  for (const std::string& d : options.textureDirs) dirs.emplace_back(d);
  try {
    AcParser p(text, source, dirs, options);
    return p.run();
  } catch (const std::exception& e) {
    return makeError(source + ": cannot read AC3D: " + e.what());
  }
}

Result<Ac3dModel> loadAc3dFile(const std::string& path, const Ac3dOptions& options) {
  auto text = readFile(path);
  if (!text) return text.error();
  auto m = parseAc3d(*text, path, fs::path(path).parent_path().string(), options);
  if (m) m->scene.name = fs::path(path).stem().string();
  return m;
}

Result<Ac3dModel> loadTorcsTrack(const std::string& accPath) {
  Ac3dOptions o;
  // tracks/CATEGORY/NAME/NAME.acc → the install root holds data/textures.
  const fs::path root = fs::path(accPath).parent_path().parent_path().parent_path().parent_path();
  o.textureDirs = {(root / "data" / "textures").string(), (root / "data" / "img").string()};
  return loadAc3dFile(accPath, o);
}

Result<std::string> findTorcsTrack(const std::string& root, const std::string& name) {
  std::error_code ec;
  std::vector<std::string> found;
  if (fs::is_directory(root, ec)) {
    fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const fs::path& p = it->path();
      if (p.extension() != ".acc" || p.stem() != p.parent_path().filename()) continue;
      if (p.parent_path().parent_path().parent_path().filename() != "tracks") continue;
      if (p.stem() == name) return p.string();
      found.push_back(p.stem().string());
    }
  }
  std::sort(found.begin(), found.end());
  std::string list;
  for (const auto& f : found) list += (list.empty() ? "" : ", ") + f;
  return makeError("TORCS track '" + name + "': no tracks/*/" + name + "/" + name + ".acc under " +
                   root +
                   (found.empty() ? " (no TORCS tracks there: run `hybridwalk scenes fetch "
                                    "--outdoor` to fetch torcs-data)"
                                  : " (tracks found: " + list + ")"));
}

namespace {

constexpr unsigned kBlendFlags = aiProcess_Triangulate | aiProcess_GenSmoothNormals |
                                 aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                                 aiProcess_FlipUVs | aiProcess_ValidateDataStructure;

const aiScene* readBlend(Assimp::Importer& importer, const std::string& path,
                         unsigned flags = kBlendFlags) {
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  return importer.ReadFile(path, flags);
}

// Assimp 5's Blender importer follows the file's pointers and block sizes
// without checking them all: it segfaults on some real files (the MORSE
// environments human_tut/tutorial_scene and sandbox) and on damaged ones. A
// crash cannot be caught in the process, so the import is first tried in a
// forked child; this process imports the file only when the child came
// through (whether or not Assimp accepted the file: its own error message is
// then the one to show). The child only reads and validates (no
// triangulation, normals or vertex joining: those run on validated data):
// tum_kitchen (266k triangles) loads in 3.8–4.3 s instead of 2.4–3.2 s
// (5.1 s with a full second import; all on a loaded machine).
Status tryBlendImportInChild(const std::string& path) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return {};  // no child: import here, as without the guard
  if (pid == 0) {
    // The parent's SIGINT/SIGTERM handler would remove the parent's
    // temporaries; the child has none of its own. It dies with the parent,
    // leaves no core file and says nothing (sanitizer reports included).
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    const rlimit noCore{0, 0};
    ::setrlimit(RLIMIT_CORE, &noCore);
    const int devNull = ::open("/dev/null", O_WRONLY);
    if (devNull >= 0) {
      ::dup2(devNull, 1);
      ::dup2(devNull, 2);
    }
    int code = 0;
    try {
      Assimp::Importer importer;
      code = readBlend(importer, path, aiProcess_ValidateDataStructure) ? 0 : 3;
    } catch (...) {
      code = 3;
    }
    ::_exit(code);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return {};
  const char* how = nullptr;
  std::string detail;
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    detail = sig == SIGSEGV ? "SIGSEGV" : sig == SIGBUS ? "SIGBUS" : sig == SIGABRT ? "SIGABRT"
             : sig == SIGKILL ? "SIGKILL (out of memory?)" : "signal " + std::to_string(sig);
    how = "crashed";
  } else if (WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 3) {
    detail = "exit status " + std::to_string(WEXITSTATUS(status));  // e.g. a sanitizer's report
    how = "failed";
  }
  if (!how) return {};
  return makeError(path + ": Assimp's Blender importer " + how + " reading this file (" + detail +
                   " in a child process that tries each .blend first); not loaded (expected a "
                   ".blend that Assimp 5 imports: re-save it from Blender 2.7x, or export it "
                   "as glTF or OBJ)");
}

}  // namespace

Result<Scene> loadBlendFile(const std::string& path, const BlendOptions& options) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return makeError(path + ": no such file");
  HW_TRY(tryBlendImportInChild(path));
  try {
    Assimp::Importer importer;
    const aiScene* ai = readBlend(importer, path);
    if (!ai) return makeError(path + ": Assimp cannot read it: " + importer.GetErrorString());
    if (!ai->mRootNode) return makeError(path + ": Assimp returned no node tree");
    BlendLoader l(ai, path, options);
    l.scene.name = fs::path(path).stem().string();
    l.materials();
    l.node(*ai->mRootNode, aiMatrix4x4(), 0);
    if (l.scene.meshes.empty()) return makeError(path + ": no triangles outside the hidden nodes");
    l.scene.computeBounds();
    return std::move(l.scene);
  } catch (const std::exception& e) {
    return makeError(path + ": cannot read .blend: " + e.what());
  } catch (...) {
    return makeError(path + ": cannot read .blend: unknown error");
  }
}

std::optional<Result<std::string>> outdoorSpecFile(const std::string& spec,
                                                   const std::string& cacheDir) {
  const std::string l = lower(spec.substr(0, std::min<std::size_t>(spec.size(), 6)));
  const fs::path root = fs::path(cacheDir) / "root";
  if (l.rfind("torcs:", 0) == 0) {
    const std::string name = spec.substr(6);
    if (name.empty())
      return Result<std::string>(
          makeError("scene 'torcs:': expected a track name, e.g. torcs:forza"));
    return findTorcsTrack((root / "usr" / "share" / "games" / "torcs").string(), name);
  }
  if (l.rfind("morse:", 0) == 0) {
    std::string rel = spec.substr(6);
    if (fs::path(rel).extension() != ".blend") rel += ".blend";
    const fs::path p = root / "usr" / "share" / "morse" / "data" / "environments" / rel;
    std::error_code ec;
    if (rel.find("..") != std::string::npos || !fs::is_regular_file(p, ec))
      return Result<std::string>(makeError(
          "scene '" + spec + "': no " + p.string() +
          " (expected morse:ENV/FILE, e.g. morse:land-1/trees; run `hybridwalk scenes fetch "
          "--outdoor` to fetch morse-simulator-data)"));
    return Result<std::string>(p.string());
  }
  return std::nullopt;
}

std::optional<Result<Scene>> loadOutdoorFile(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".acc") {
    auto m = loadTorcsTrack(path);
    if (!m) return Result<Scene>(m.error());
    return Result<Scene>(std::move(m->scene));
  }
  if (ext == ".blend") return loadBlendFile(path);
  return std::nullopt;
}

namespace {

// The file an outdoor spec or path names, and whether it is ours.
std::optional<Result<std::string>> outdoorFileOf(const std::string& spec) {
  std::error_code ec;
  if (!spec.empty() && fs::is_regular_file(spec, ec)) {
    const std::string ext = lower(fs::path(spec).extension().string());
    if (ext == ".acc" || ext == ".blend") return Result<std::string>(spec);
    return std::nullopt;
  }
  return outdoorSpecFile(spec, defaultSceneCacheDir());
}

}  // namespace

std::optional<Result<Scene>> loadOutdoorSpec(const std::string& spec) {
  auto file = outdoorFileOf(spec);
  if (!file) return std::nullopt;
  if (!*file) return Result<Scene>(file->error());
  return loadOutdoorFile(**file);
}

std::optional<Result<CameraPath>> outdoorDefaultPath(const std::string& spec,
                                                     const DefaultPathOptions& options,
                                                     std::vector<std::string>* notes) {
  auto file = outdoorFileOf(spec);
  if (!file) return std::nullopt;
  if (!*file) return Result<CameraPath>(file->error());
  if (lower(fs::path(**file).extension().string()) == ".acc") {
    DrivePathOptions o;
    o.metresPerFrame = options.metresPerFrame;
    if (options.eyeHeight > 0) o.eyeHeightMetres = options.eyeHeight;
    return torcsDefaultPath(**file, o, notes);
  }
  auto scene = loadBlendFile(**file);
  if (!scene) return Result<CameraPath>(scene.error());
  // On foot over the environment's floor (indoors under its roof); the
  // circle below where no floor is found.
  FloorWalkOptions fw;
  fw.eyeHeight = options.eyeHeight > 0 ? options.eyeHeight : 1.7;
  fw.frames = 240;
  auto floor = floorWalkPath(*scene, fw);
  if (floor) return floor;
  if (notes) notes->push_back(floor.error().message + "; walking a circle over the terrain instead");
  const TriangleGrid grid(*scene);
  const glm::dvec3 lo(scene->boundsMin), hi(scene->boundsMax), c = 0.5 * (lo + hi);
  const double r = 0.25 * std::min(hi.x - lo.x, hi.z - lo.z);
  std::vector<glm::dvec2> circle;
  for (int k = 0; k <= 24; ++k) {
    const double t = 2.0 * 3.14159265358979323846 * k / 24;
    circle.push_back({c.x + r * std::cos(t), c.z + r * std::sin(t)});
  }
  TerrainWalkOptions walk;
  if (options.eyeHeight > 0) walk.eyeHeightMetres = options.eyeHeight;
  return terrainWalkPath(grid, circle, walk);
}

// ------------------------------------------------------------------ queries

double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c) {
  // Ericson, Real-Time Collision Detection, ClosestPtPointTriangle.
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(ap);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return glm::length(ap);  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return glm::length(p - (a + ab * v + ac * w));
}

TriangleGrid::TriangleGrid(const Scene& scene, double cellSize) : cellSize_(cellSize) {
  HW_CHECK(cellSize > 0);
  for (const Mesh& m : scene.meshes) {
    if (m.material >= 0 && static_cast<std::size_t>(m.material) < scene.materials.size() &&
        scene.materials[static_cast<std::size_t>(m.material)].sky)
      continue;
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
      tris_.push_back({glm::dvec3(m.vertices[m.indices[i]].position),
                       glm::dvec3(m.vertices[m.indices[i + 1]].position),
                       glm::dvec3(m.vertices[m.indices[i + 2]].position)});
  }
  if (tris_.empty()) return;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const Tri& t : tris_)
    for (const glm::dvec3& v : {t.a, t.b, t.c}) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  // Keep the grid under ~8M cells whatever the scene's extent.
  for (;;) {
    const glm::dvec3 d = glm::floor((hi - lo) / cellSize_) + 1.0;
    if (d.x * d.y * d.z <= 8e6) {
      dims_ = glm::ivec3(d);
      break;
    }
    cellSize_ *= 1.5;
  }
  origin_ = lo;
  cells_.resize(static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z);
  for (std::size_t i = 0; i < tris_.size(); ++i) {
    const Tri& t = tris_[i];
    const glm::ivec3 a = cellOf(glm::min(t.a, glm::min(t.b, t.c)));
    const glm::ivec3 b = cellOf(glm::max(t.a, glm::max(t.b, t.c)));
    for (int z = a.z; z <= b.z; ++z)
      for (int y = a.y; y <= b.y; ++y)
        for (int x = a.x; x <= b.x; ++x)
          cells_[(static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x].push_back(
              static_cast<std::uint32_t>(i));
  }
}

glm::ivec3 TriangleGrid::cellOf(const glm::dvec3& p) const {
  const glm::dvec3 c = glm::floor((p - origin_) / cellSize_);
  return glm::clamp(glm::ivec3(glm::clamp(c, glm::dvec3(-1.0), glm::dvec3(1e7))), glm::ivec3(0),
                    dims_ - 1);
}

std::vector<double> TriangleGrid::hitsBelow(const glm::dvec3& from) const {
  std::vector<double> hits;
  if (tris_.empty()) return hits;
  const glm::dvec3 rel = (from - origin_) / cellSize_;
  if (rel.x < 0 || rel.z < 0 || rel.x >= dims_.x || rel.z >= dims_.z) return hits;
  const glm::ivec3 top = cellOf(from);
  std::vector<std::uint32_t> seen;
  for (int y = top.y; y >= 0; --y)
    for (std::uint32_t i :
         cells_[(static_cast<std::size_t>(top.z) * dims_.y + y) * dims_.x + top.x]) {
      if (std::find(seen.begin(), seen.end(), i) != seen.end()) continue;
      seen.push_back(i);
      const Tri& t = tris_[i];
      // 2D barycentrics in XZ.
      const double d = (t.b.z - t.c.z) * (t.a.x - t.c.x) + (t.c.x - t.b.x) * (t.a.z - t.c.z);
      if (std::abs(d) < 1e-12) continue;
      const double l1 =
          ((t.b.z - t.c.z) * (from.x - t.c.x) + (t.c.x - t.b.x) * (from.z - t.c.z)) / d;
      const double l2 =
          ((t.c.z - t.a.z) * (from.x - t.c.x) + (t.a.x - t.c.x) * (from.z - t.c.z)) / d;
      const double l3 = 1 - l1 - l2;
      // A point on a shared edge (spawns and floors on the same grid) must
      // not fall through the crack between two triangles.
      constexpr double kEdge = -1e-7;
      if (l1 < kEdge || l2 < kEdge || l3 < kEdge) continue;
      const double h = l1 * t.a.y + l2 * t.b.y + l3 * t.c.y;
      if (h <= from.y) hits.push_back(h);
    }
  std::sort(hits.begin(), hits.end(), std::greater<>());
  return hits;
}

double TriangleGrid::distanceToNearest(const glm::dvec3& p, double maxDistance) const {
  double best = maxDistance;
  if (tris_.empty()) return best;
  const glm::ivec3 a = cellOf(p - glm::dvec3(maxDistance)), b = cellOf(p + glm::dvec3(maxDistance));
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y)
      for (int x = a.x; x <= b.x; ++x)
        for (std::uint32_t i : cells_[(static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x]) {
          const Tri& t = tris_[i];
          best = std::min(best, pointTriangleDistance(p, t.a, t.b, t.c));
        }
  return best;
}

bool TriangleGrid::segmentClear(const glm::dvec3& a, const glm::dvec3& b, double clearance) const {
  const double len = glm::length(b - a);
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * clearance))));
  for (int i = 0; i <= n; ++i)
    if (distanceToNearest(a + (b - a) * (static_cast<double>(i) / n), clearance) < clearance)
      return false;
  return true;
}

std::optional<double> TriangleGrid::rayHit(const glm::dvec3& origin, const glm::dvec3& dir,
                                           double maxDistance) const {
  if (tris_.empty()) return std::nullopt;
  // March through the cells the ray crosses (Amanatides & Woo 1987), testing
  // their triangles (Möller & Trumbore 1997); the nearest hit in a cell is
  // final once it lies before the cell's exit.
  const glm::dvec3 hiB = origin_ + glm::dvec3(dims_) * cellSize_;
  double t0 = 0.0, t1 = maxDistance;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir[k]) < 1e-12) {
      if (origin[k] < origin_[k] || origin[k] > hiB[k]) return std::nullopt;
      continue;
    }
    double a = (origin_[k] - origin[k]) / dir[k], b = (hiB[k] - origin[k]) / dir[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return std::nullopt;
  glm::ivec3 c = cellOf(origin + dir * t0);
  glm::ivec3 stepI(0);
  glm::dvec3 tMax(std::numeric_limits<double>::infinity()), tDelta(tMax);
  for (int k = 0; k < 3; ++k) {
    if (dir[k] > 0) {
      stepI[k] = 1;
      tMax[k] = (origin_[k] + (c[k] + 1) * cellSize_ - origin[k]) / dir[k];
      tDelta[k] = cellSize_ / dir[k];
    } else if (dir[k] < 0) {
      stepI[k] = -1;
      tMax[k] = (origin_[k] + c[k] * cellSize_ - origin[k]) / dir[k];
      tDelta[k] = -cellSize_ / dir[k];
    }
  }
  double best = std::numeric_limits<double>::infinity();
  for (int guard = 0; guard < dims_.x + dims_.y + dims_.z + 3; ++guard) {
    for (std::uint32_t i : cells_[(static_cast<std::size_t>(c.z) * dims_.y + c.y) * dims_.x + c.x]) {
      const Tri& t = tris_[i];
      const glm::dvec3 e1 = t.b - t.a, e2 = t.c - t.a, p = glm::cross(dir, e2);
      const double det = glm::dot(e1, p);
      if (std::abs(det) < 1e-14) continue;
      const glm::dvec3 s = origin - t.a;
      const double u = glm::dot(s, p) / det;
      if (u < 0 || u > 1) continue;
      const glm::dvec3 q = glm::cross(s, e1);
      const double v = glm::dot(dir, q) / det;
      if (v < 0 || u + v > 1) continue;
      const double tt = glm::dot(e2, q) / det;
      if (tt > 1e-9 && tt < best) best = tt;
    }
    const double exit = std::min({tMax.x, tMax.y, tMax.z});
    if (best <= exit) break;
    if (exit > t1) break;
    const int k = tMax.x == exit ? 0 : tMax.y == exit ? 1 : 2;
    c[k] += stepI[k];
    if (c[k] < 0 || c[k] >= dims_[k]) break;
    tMax[k] += tDelta[k];
  }
  if (best <= maxDistance) return best;
  return std::nullopt;
}

double openViewFraction(const TriangleGrid& grid, const glm::dvec3& eye, const glm::dvec3& forward,
                        double fovYDeg, double maxDistance, int n) {
  const glm::dvec3 w = glm::normalize(forward);
  glm::dvec3 u = glm::cross(w, glm::dvec3(0, 1, 0));
  if (glm::length(u) < 1e-9) u = glm::dvec3(1, 0, 0);
  u = glm::normalize(u);
  const glm::dvec3 v = glm::cross(u, w);
  const double h = std::tan(0.5 * fovYDeg * 3.14159265358979323846 / 180.0);
  int open = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (2.0 * (i + 0.5) / n - 1.0) * h, y = (1.0 - 2.0 * (j + 0.5) / n) * h;
      if (!grid.rayHit(eye, glm::normalize(w + x * u + y * v), maxDistance)) ++open;
    }
  return static_cast<double>(open) / (n * n);
}

EyeCheck checkEye(const TriangleGrid& grid, const glm::dvec3& eye, double maxClearance) {
  EyeCheck c;
  const std::vector<double> hits = grid.hitsBelow(eye);
  if (!hits.empty()) c.floorDrop = eye.y - hits.front();
  c.clearance = grid.distanceToNearest(eye, maxClearance);
  return c;
}

// ------------------------------------------------------------------ paths

Result<std::vector<glm::dvec3>> roadCentreline(const Ac3dModel& track,
                                               const DrivePathOptions& options, bool* closed) {
  if (closed) *closed = false;
  const Scene& s = track.scene;
  std::vector<bool> isRoad(s.materials.size(), false);
  for (std::size_t m = 0; m < s.materials.size() && m < track.materialTextureNames.size(); ++m) {
    const std::string stem = lower(fs::path(track.materialTextureNames[m]).stem().string());
    for (const std::string& r : options.roadTextureStems) {
      const std::string lr = lower(r);
      if (stem.rfind(lr, 0) == 0) isRoad[m] = true;
    }
  }
  // Uniform samples on the road, about four per m², fixed seed.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<glm::dvec3> pts;
  for (const Mesh& m : s.meshes) {
    if (!isRoad[static_cast<std::size_t>(m.material)]) continue;
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      const glm::dvec3 a(m.vertices[m.indices[i]].position),
          b(m.vertices[m.indices[i + 1]].position), c(m.vertices[m.indices[i + 2]].position);
      const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
      const int n = std::max(1, static_cast<int>(std::lround(4.0 * area)));
      for (int k = 0; k < n; ++k) {
        double u = uni(rng), v = uni(rng);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        pts.push_back(a + (b - a) * u + (c - a) * v);
      }
    }
  }
  if (pts.size() < 100)
    return makeError(
        s.name + ": no road found (materials with base texture " +
        (options.roadTextureStems.empty() ? std::string("?") : options.roadTextureStems[0]) +
        "*); cannot trace a centreline");
  constexpr double kCell = 4.0;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
  auto key = [](int x, int z) { return (static_cast<std::int64_t>(x) << 32) ^ (z & 0xffffffffLL); };
  for (std::size_t i = 0; i < pts.size(); ++i)
    grid[key(static_cast<int>(std::floor(pts[i].x / kCell)),
             static_cast<int>(std::floor(pts[i].z / kCell)))]
        .push_back(static_cast<std::uint32_t>(i));
  auto near = [&](const glm::dvec3& q, double r, auto&& fn) {
    const int x0 = static_cast<int>(std::floor((q.x - r) / kCell)),
              x1 = static_cast<int>(std::floor((q.x + r) / kCell));
    const int z0 = static_cast<int>(std::floor((q.z - r) / kCell)),
              z1 = static_cast<int>(std::floor((q.z + r) / kCell));
    for (int z = z0; z <= z1; ++z)
      for (int x = x0; x <= x1; ++x)
        if (auto it = grid.find(key(x, z)); it != grid.end())
          for (std::uint32_t i : it->second) {
            const glm::dvec2 d(pts[i].x - q.x, pts[i].z - q.z);
            if (glm::dot(d, d) <= r * r) fn(pts[i]);
          }
  };
  // Cross-section of the road through q perpendicular to dir: the
  // contiguous cluster of samples (gaps < 2 m) nearest q; nullopt if none within 6 m.
  constexpr double kHalfWidthMax = 20.0;
  constexpr double kMaxRoadWidth = 22.0;
  const double kMaxShift = 0.35 * std::max(0.5, options.stepMetres);
  auto section = [&](const glm::dvec3& q, const glm::dvec2& dir) -> std::optional<glm::dvec3> {
    const glm::dvec2 side(-dir.y, dir.x);
    std::vector<std::pair<double, double>> lat;  // lateral offset, height
    near(q, kHalfWidthMax, [&](const glm::dvec3& p) {
      const glm::dvec2 d(p.x - q.x, p.z - q.z);
      if (std::abs(glm::dot(d, dir)) < 1.5 && std::abs(p.y - q.y) < 3.0)
        lat.push_back({glm::dot(d, side), p.y});
    });
    if (lat.size() < 3) return std::nullopt;
    std::sort(lat.begin(), lat.end());
    std::size_t best = 0;
    for (std::size_t i = 1; i < lat.size(); ++i)
      if (std::abs(lat[i].first) < std::abs(lat[best].first)) best = i;
    std::size_t lo = best, hi = best;
    while (lo > 0 && lat[lo].first - lat[lo - 1].first < 2.0) --lo;
    while (hi + 1 < lat.size() && lat[hi + 1].first - lat[hi].first < 2.0) ++hi;
    if (std::abs(lat[best].first) > 6.0) return std::nullopt;
    double mid = 0.5 * (lat[lo].first + lat[hi].first);
    // Wider than a road (a paddock or car park beside it): keep going
    // straight rather than drift into it.
    if (lat[hi].first - lat[lo].first > kMaxRoadWidth) {
      mid = 0.0;
      lo = hi = best;
    }
    // At most ~20° of heading change per step: no jumping onto a road
    // running alongside.
    mid = std::clamp(mid, -kMaxShift, kMaxShift);
    double y = 0;
    for (std::size_t i = lo; i <= hi; ++i) y += lat[i].second;
    y /= static_cast<double>(hi - lo + 1);
    return glm::dvec3(q.x + side.x * mid, y, q.z + side.y * mid);
  };

  // Start: the road sample nearest to the samples' mean; direction: the
  // principal axis of the road around it.
  glm::dvec3 mean(0.0);
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  glm::dvec3 start = pts[0];
  for (const auto& p : pts)
    if (glm::length(glm::dvec2(p.x - mean.x, p.z - mean.z)) <
        glm::length(glm::dvec2(start.x - mean.x, start.z - mean.z)))
      start = p;
  double cxx = 0, cxz = 0, czz = 0;
  near(start, 25.0, [&](const glm::dvec3& p) {
    const double dx = p.x - start.x, dz = p.z - start.z;
    cxx += dx * dx, cxz += dx * dz, czz += dz * dz;
  });
  const double ang = 0.5 * std::atan2(2 * cxz, cxx - czz);
  glm::dvec2 dir(std::cos(ang), std::sin(ang));
  if (auto c = section(start, dir)) start = *c;

  std::vector<glm::dvec3> line{start};
  glm::dvec3 p = start;
  const double step = std::max(0.5, options.stepMetres);
  const std::size_t maxSteps = static_cast<std::size_t>(200'000.0 / step);
  for (std::size_t k = 0; k < maxSteps; ++k) {
    // Gaps (a start line or pit entry in another texture) are bridged by
    // looking up to kMaxGap steps straight ahead.
    constexpr int kMaxGap = 8;
    glm::dvec3 q = p;
    std::optional<glm::dvec3> c;
    for (int g = 1; g <= kMaxGap && !c; ++g) {
      q = glm::dvec3(p.x + dir.x * step * g, p.y, p.z + dir.y * step * g);
      c = section(q, dir);
    }
    if (!c) {
      if (static_cast<double>(line.size() - 1) * step >= options.traceMetres) return line;
      return makeError(s.name + ": the road ends " +
                       std::to_string(static_cast<int>(static_cast<double>(line.size()) * step)) +
                       " m along the centreline trace (at x=" + std::to_string(q.x) +
                       ", z=" + std::to_string(q.z) + "), before the " +
                       std::to_string(static_cast<int>(options.traceMetres)) + " m asked for");
    }
    glm::dvec2 nd(c->x - p.x, c->z - p.z);
    if (glm::length(nd) < 1e-6) return makeError(s.name + ": centreline trace stalled");
    dir = glm::normalize(nd);
    p = *c;
    if (line.size() > 20 && glm::length(glm::dvec2(p.x - start.x, p.z - start.z)) < 0.75 * step) {
      if (closed) *closed = true;
      return line;
    }
    line.push_back(p);
    if (static_cast<double>(line.size() - 1) * step >= options.traceMetres) return line;
  }
  return makeError(s.name + ": the centreline trace did not return to its start after " +
                   std::to_string(maxSteps) + " steps");
}

Result<CameraPath> drivePath(const Ac3dModel& track, const DrivePathOptions& options) {
  DrivePathOptions o = options;
  o.traceMetres =
      options.startMetres + options.lengthMetres + options.lookAheadMetres + 2 * options.stepMetres;
  bool closed = false;
  auto lineR = roadCentreline(track, o, &closed);
  if (!lineR) return lineR.error();
  std::vector<glm::dvec3> line = std::move(*lineR);
  if (options.reverse) {
    if (!closed)
      return makeError(track.scene.name +
                       ": cannot drive in reverse: the centreline did not close");
    std::reverse(line.begin(), line.end());
  }
  // Light smoothing of the traced points (ends kept on open traces).
  {
    const std::size_t n = line.size();
    std::vector<glm::dvec3> sm(line);
    for (std::size_t i = 0; i < n; ++i) {
      if (!closed && (i == 0 || i + 1 == n)) continue;
      sm[i] = 0.25 * line[(i + n - 1) % n] + 0.5 * line[i] + 0.25 * line[(i + 1) % n];
    }
    line = std::move(sm);
  }
  std::vector<double> cum(line.size(), 0.0);
  for (std::size_t i = 1; i < line.size(); ++i)
    cum[i] = cum[i - 1] + glm::length(line[i] - line[i - 1]);
  const double total = polylineLength(line, closed);
  const double length = std::clamp(options.lengthMetres, 1.0, total);
  const glm::dvec3 up(0, options.eyeHeightMetres, 0);
  CameraPath path;
  path.nearPlane = 0.5;
  path.farPlane = 1000.0;
  path.frames = options.frames;
  path.keyframeEvery = options.keyframeEvery;
  const int keys = std::max(2, static_cast<int>(std::ceil(length / options.stepMetres)) + 1);
  for (int k = 0; k < keys; ++k) {
    const double sArc = options.startMetres + length * k / (keys - 1);
    path.keys.push_back({pointAtClosed(line, cum, total, sArc) + up,
                         pointAtClosed(line, cum, total, sArc + options.lookAheadMetres) + up});
  }
  return path;
}

Result<CameraPath> terrainWalkPath(const TriangleGrid& grid,
                                   const std::vector<glm::dvec2>& waypointsXZ,
                                   const TerrainWalkOptions& options) {
  if (waypointsXZ.size() < 2) return makeError("terrain walk: need at least 2 waypoints");
  std::vector<glm::dvec2> pts;
  for (std::size_t i = 0; i + 1 < waypointsXZ.size(); ++i) {
    const glm::dvec2 a = waypointsXZ[i], b = waypointsXZ[i + 1];
    const int n =
        std::max(1, static_cast<int>(std::ceil(glm::length(b - a) / options.keySpacingMetres)));
    for (int k = 0; k < n; ++k) pts.push_back(a + (b - a) * (static_cast<double>(k) / n));
  }
  pts.push_back(waypointsXZ.back());
  auto ground = [&](const glm::dvec2& xz) -> Result<double> {
    const auto hits = grid.hitsBelow(glm::dvec3(xz.x, 1e6, xz.y));
    if (hits.empty())
      return makeError("terrain walk: no ground below x=" + std::to_string(xz.x) +
                       ", z=" + std::to_string(xz.y));
    return hits.back();
  };
  CameraPath path;
  path.nearPlane = 0.1;
  path.farPlane = 1000.0;
  path.frames = options.frames;
  path.keyframeEvery = options.keyframeEvery;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto g = ground(pts[i]);
    if (!g) return g.error();
    glm::dvec2 d = i + 1 < pts.size() ? pts[i + 1] - pts[i] : pts[i] - pts[i - 1];
    d = glm::normalize(d);
    const glm::dvec3 eye(pts[i].x, *g + options.eyeHeightMetres, pts[i].y);
    path.keys.push_back({eye, eye + glm::dvec3(d.x, 0.0, d.y) * options.lookAheadMetres});
  }
  // Look along the way: the average of the directions in and out of a key.
  for (std::size_t i = 1; i + 1 < path.keys.size(); ++i) {
    glm::dvec3 din = path.keys[i].eye - path.keys[i - 1].eye;
    glm::dvec3 dout = path.keys[i + 1].eye - path.keys[i].eye;
    din.y = dout.y = 0;
    glm::dvec3 d = glm::normalize(glm::normalize(din) + glm::normalize(dout));
    if (!std::isfinite(d.x)) d = glm::normalize(dout);
    path.keys[i].lookAt = path.keys[i].eye + d * options.lookAheadMetres;
  }
  return path;
}

}  // namespace hw::scenes
