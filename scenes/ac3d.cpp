// AC3D text → Scene: objects flattened, surfaces as fans/strips, grouped
// per (material, ground cell). See ac3d.h for the contract.
#include "scenes/ac3d.h"

#include <algorithm>
#include <array>
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
#include <sstream>
#include <string_view>

#include <glm/glm.hpp>

#include "core/file_io.h"
#include "scenes/model_common.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;
using namespace detail;  // the readers' shared helpers (model_common.h)

constexpr int kMaxAcDepth = 256;  // object nesting; deeper files are refused, not recursed into
// Largest count a declared numvert/refs may reserve before its lines are read.
constexpr long long kAcReserveLimit = 1 << 16;

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

  // An OBJECT's records up to its `kids` line. Surfaces wait for `kids`, as
  // loc/rot may follow them.
  struct AcSurface {
    int flags;
    int mat;
    std::vector<std::array<double, 3>> refs;  // vertex index, u, v
  };
  struct AcObject {
    std::string baseTexture;
    bool sawBase = false;
    int layers = 0;
    double texrep[2] = {1, 1}, texoff[2] = {0, 0};
    AcTransform local;
    std::vector<glm::vec3> positions, normals;
    bool haveNormals = true;
    std::vector<AcSurface> surfaces;
    long long kids = -1;
  };

  Status object(std::string_view header, const AcTransform& parent, int depth) {
    if (depth > kMaxAcDepth)
      return fail("objects nested deeper than " + std::to_string(kMaxAcDepth), header);
    ++out_.stats.objects;
    AcObject o;
    while (o.kids < 0) HW_TRY(objectRecord(o));
    if (o.layers > 1) ++out_.stats.multiLayerObjects;

    AcTransform world;
    world.rot = parent.rot * o.local.rot;
    world.loc = parent.rot * o.local.loc + parent.loc;
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(world.rot));
    std::vector<Vertex> verts;
    std::vector<std::uint32_t> tri;
    for (const AcSurface& s : o.surfaces) emitSurface(s, o, world, normalMatrix, verts, tri);
    return kidObjects(o.kids, world, depth);
  }

  // One record of an OBJECT (a line, or a numvert/numsurf block).
  Status objectRecord(AcObject& o) {
    std::string_view line;
    if (!next(&line)) return eof("'kids N' to end the OBJECT started earlier");
    const std::string_view kw = keyword(line), arg = rest(line);
    long long n = 0;
    if (kw == "name" || kw == "url" || kw == "crease" || kw == "subdiv" || kw == "hidden" ||
        kw == "locked" || kw == "folded") {
      return {};
    } else if (kw == "data") {
      if (!integer(arg, &n) || n < 0 ||
          static_cast<std::size_t>(n) > text_.size() - std::min(pos_, text_.size()))
        return fail("expected 'data N' with N bytes following", line);
      pos_ += static_cast<std::size_t>(n);  // the data bytes, then their newline
      if (pos_ < text_.size() && text_[pos_] == '\r') ++pos_;
      if (pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
    } else if (kw == "texture") {
      return objectTexture(line, arg, o);
    } else if (kw == "texrep" || kw == "texoff") {
      double* v = kw == "texrep" ? o.texrep : o.texoff;
      if (numbers(arg, v, 2) != 2) return fail("expected '" + std::string(kw) + " U V'", line);
    } else if (kw == "rot") {
      double r[9];
      if (numbers(arg, r, 9) != 9) return fail("expected 'rot' with 9 numbers", line);
      o.local.rot = glm::mat3(glm::vec3(r[0], r[1], r[2]), glm::vec3(r[3], r[4], r[5]),
                              glm::vec3(r[6], r[7], r[8]));
    } else if (kw == "loc") {
      double l[3];
      if (numbers(arg, l, 3) != 3) return fail("expected 'loc X Y Z'", line);
      o.local.loc = glm::vec3(l[0], l[1], l[2]);
    } else if (kw == "numvert") {
      if (!integer(arg, &n) || n < 0 || n > 50'000'000) return fail("expected 'numvert N'", line);
      return objectVertices(n, o);
    } else if (kw == "numsurf") {
      if (!integer(arg, &n) || n < 0 || n > 50'000'000) return fail("expected 'numsurf N'", line);
      for (long long s = 0; s < n; ++s) HW_TRY(objectSurface(o));
    } else if (kw == "kids") {
      if (!integer(arg, &n) || n < 0 || n > 10'000'000) return fail("expected 'kids N'", line);
      o.kids = n;
    } else {
      return fail("unknown OBJECT keyword '" + std::string(kw) + "'", line);
    }
    return {};
  }

  // TORCS: `texture "X" base|tiled|skids|shad`; only the base layer (or a
  // plain `texture "X"`) is the surface colour.
  Status objectTexture(std::string_view line, std::string_view arg, AcObject& o) {
    ++o.layers;
    std::string_view a = arg;
    if (a.empty()) return fail("expected 'texture \"NAME\" [base|tiled|skids|shad]'", line);
    std::string name = quoted(a);
    std::string_view tail =
        a.front() == '"' ? a.substr(std::min(a.size(), name.size() + 2)) : rest(a);
    while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.front())))
      tail.remove_prefix(1);
    const std::string_view layer = keyword(tail);
    if (layer.empty() || layer == "base") {
      o.baseTexture = name == "empty_texture_no_mapping" ? "" : name;
      o.sawBase = true;
    }
    return {};
  }

  // The `n` vertex lines after `numvert n`.
  Status objectVertices(long long n, AcObject& o) {
    // Grown as lines arrive: a declared count allocates nothing by
    // itself (an 84-byte file declaring 50M vertices took 1.2 GB).
    o.positions.clear();
    o.normals.clear();
    o.positions.reserve(static_cast<std::size_t>(std::min<long long>(n, kAcReserveLimit)));
    o.normals.reserve(o.positions.capacity());
    std::string_view line;
    for (long long i = 0; i < n; ++i) {
      if (!next(&line)) return eof(std::to_string(n) + " vertex lines after numvert");
      double v[6];
      const int k = numbers(line, v, 6);
      if (k < 3) return fail("expected a vertex 'X Y Z [NX NY NZ]'", line);
      o.positions.push_back(glm::vec3(v[0], v[1], v[2]));
      if (k == 6)
        o.normals.push_back(glm::vec3(v[3], v[4], v[5]));
      else {
        o.normals.push_back(glm::vec3(0.0f));
        o.haveNormals = false;
      }
    }
    return {};
  }

  // One SURF record: its flags, then 'mat I' lines and its 'refs N' block.
  Status objectSurface(AcObject& o) {
    std::string_view line;
    if (!next(&line)) return eof("SURF record");
    long long flags = 0;
    if (keyword(line) != "SURF" || !integer(rest(line), &flags))
      return fail("expected 'SURF FLAGS'", line);
    // Material 0 unless a 'mat' line follows: there must be one.
    if (acMaterials_.empty())
      return fail(
          "expected a MATERIAL line before the first SURF (a surface uses "
          "material 0 unless it says 'mat N')",
          line);
    AcSurface p{static_cast<int>(flags), 0, {}};
    bool gotRefs = false;
    while (!gotRefs) {
      if (!next(&line)) return eof("'mat N' / 'refs N' of a SURF");
      const std::string_view skw = keyword(line);
      long long v = 0;
      if (skw == "mat") {
        if (!integer(rest(line), &v) || v < 0 || static_cast<std::size_t>(v) >= acMaterials_.size())
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
              q[0] >= static_cast<double>(o.positions.size()) || q[0] != std::floor(q[0]))
            return fail(
                "expected 'INDEX U V' with INDEX < numvert " + std::to_string(o.positions.size()),
                line);
          r = {q[0], q[1], q[2]};
        }
        gotRefs = true;
      } else {
        return fail("expected 'mat' or 'refs' in a SURF", line);
      }
    }
    o.surfaces.push_back(std::move(p));
    return {};
  }

  // A surface's triangles (a fan, or a TORCS strip) added to the scene in
  // `world` space; `verts` and `tri` are scratch.
  void emitSurface(const AcSurface& s, const AcObject& o, const AcTransform& world,
                   const glm::mat3& normalMatrix, std::vector<Vertex>& verts,
                   std::vector<std::uint32_t>& tri) {
    ++out_.stats.surfaces;
    const int type = s.flags & 0x0F;
    const bool twoSided = (s.flags & 0x20) != 0;
    if (twoSided) ++out_.stats.twoSidedSurfaces;
    if (type == 1 || type == 2) {
      ++out_.stats.lineSurfaces;
      return;
    }
    if (s.refs.size() < 3) return;
    verts.resize(s.refs.size());
    for (std::size_t i = 0; i < s.refs.size(); ++i) {
      const auto vi = static_cast<std::size_t>(s.refs[i][0]);
      Vertex& v = verts[i];
      v.position = world.rot * o.positions[vi] + world.loc;
      v.normal = o.haveNormals ? normalMatrix * o.normals[vi] : glm::vec3(0.0f);
      const double u = s.refs[i][1] * o.texrep[0] + o.texoff[0];
      const double t = s.refs[i][2] * o.texrep[1] + o.texoff[1];
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
    if (tri.empty()) return;
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
    const int material = materialIndex(s.mat, o.baseTexture, twoSided);
    builder_.beginBatch();
    for (std::size_t k = 0; k < tri.size(); k += 3)
      builder_.addTriangle(material, verts, tri[k], tri[k + 1], tri[k + 2]);
  }

  // The `kids` OBJECTs after an OBJECT's `kids` line, placed in `world`.
  Status kidObjects(long long kids, const AcTransform& world, int depth) {
    std::string_view line;
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

}  // namespace

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

}  // namespace hw::scenes
