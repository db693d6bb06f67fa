// Procedural indoor/outdoor scenes. The triangle-count knob is a single
// tessellation density (cells per metre) solved by bisection on an exact
// count-only pass, so the look is the same at every count.
#include "scenes/procedural.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "core/check.h"

namespace hw::scenes {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kTexSize = 256;

// ---------------------------------------------------------------------------
// Deterministic randomness and tileable noise for the textures.

// Uniform doubles from std::mt19937 (whose output sequence the standard fixes;
// std::uniform_real_distribution is implementation-defined).
struct Rng {
  explicit Rng(std::uint32_t seed) : g(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (g() / 4294967296.0); }
  std::mt19937 g;
};

std::uint32_t hash3(int x, int y, std::uint32_t seed) {
  std::uint32_t h = static_cast<std::uint32_t>(x) * 374761393u +
                    static_cast<std::uint32_t>(y) * 668265263u + seed * 2246822519u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return h ^ (h >> 16);
}
double hashUnit(int x, int y, std::uint32_t seed) { return hash3(x, y, seed) / 4294967296.0; }

// Value noise on a lattice that wraps every `period` cells (so textures tile).
// (x, y) in lattice units.
double valueNoise(double x, double y, int period, std::uint32_t seed) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  double fx = x - x0, fy = y - y0;
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  auto w = [&](int v) { return ((v % period) + period) % period; };
  const double a = hashUnit(w(x0), w(y0), seed), b = hashUnit(w(x0 + 1), w(y0), seed);
  const double c = hashUnit(w(x0), w(y0 + 1), seed), d = hashUnit(w(x0 + 1), w(y0 + 1), seed);
  return (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy;
}

// Fractal noise in [0, 1] at texture coordinates (u, v) in [0, 1), tiling.
double fbm(double u, double v, int basePeriod, int octaves, std::uint32_t seed) {
  double sum = 0, amp = 1, norm = 0;
  int period = basePeriod;
  for (int o = 0; o < octaves; ++o) {
    sum += amp *
           valueNoise(u * period, v * period, period, seed + static_cast<std::uint32_t>(o) * 101u);
    norm += amp;
    amp *= 0.5;
    period *= 2;
  }
  return sum / norm;
}

std::uint8_t toByte(double v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0, 255.0) + 0.5); }
Rgba8 rgb(double r, double g, double b, double a = 255) {
  return Rgba8{toByte(r), toByte(g), toByte(b), toByte(a)};
}
Rgba8 scaled(const glm::dvec3& c, double k) { return rgb(c.r * k, c.g * k, c.b * k); }

Texture makeTexture(const std::string& name, const std::function<Rgba8(int, int)>& f) {
  Texture t;
  t.name = name;
  t.image.resize(kTexSize, kTexSize);
  for (int y = 0; y < kTexSize; ++y)
    for (int x = 0; x < kTexSize; ++x) t.image(x, y) = f(x, y);
  return t;
}

double uOf(int x) { return (x + 0.5) / kTexSize; }

// ---------------------------------------------------------------------------
// Textures. Each is 256×256, tiles seamlessly, row 0 = top.

// 1 m × 1 m of stretcher-bond brick: 8 courses of 4 bricks, 3 px mortar.
Texture brickTexture() {
  return makeTexture("brick", [](int x, int y) {
    const int row = y / 32;
    const int xs = (x + (row % 2) * 32) % kTexSize;
    const int col = xs / 64;
    const int lx = xs % 64, ly = y % 32;
    const double n = fbm(uOf(x), uOf(y), 16, 3, 7);
    if (lx < 3 || ly < 3) return scaled({190, 184, 172}, 0.85 + 0.2 * n);
    const double k = (0.8 + 0.35 * hashUnit(col, row, 11)) * (0.85 + 0.3 * n);
    return scaled({158, 66, 48}, k);
  });
}

Texture plasterTexture() {
  return makeTexture("plaster", [](int x, int y) {
    return scaled({236, 232, 224}, 0.93 + 0.07 * fbm(uOf(x), uOf(y), 8, 4, 21));
  });
}

// 8 × 8 squares (a 2 m texture gives 25 cm squares).
Texture checkerTexture() {
  return makeTexture("checker", [](int x, int y) {
    const bool dark = ((x / 32) + (y / 32)) % 2 == 1;
    const double n = 0.9 + 0.1 * fbm(uOf(x), uOf(y), 16, 3, 31);
    return dark ? scaled({58, 60, 70}, n) : scaled({226, 220, 204}, n);
  });
}

// 4 × 4 ceramic tiles with grout.
Texture tileTexture() {
  return makeTexture("tile", [](int x, int y) {
    if (x % 64 < 2 || y % 64 < 2) return rgb(120, 118, 112);
    const double k =
        0.92 + 0.08 * hashUnit(x / 64, y / 64, 41) + 0.04 * fbm(uOf(x), uOf(y), 8, 2, 43);
    return scaled({196, 204, 212}, k);
  });
}

// Planks along v: 8 planks of 32 px with staggered end joints and grain.
Texture woodTexture() {
  return makeTexture("wood", [](int x, int y) {
    const int plank = x / 32;
    const int joint = static_cast<int>(hashUnit(plank, 0, 51) * kTexSize);
    if (x % 32 == 0 || (y == joint)) return rgb(60, 38, 22);
    const double n = fbm(uOf(x) * 1.0, uOf(y), 4, 3, 53 + static_cast<std::uint32_t>(plank));
    const double grain = 0.5 + 0.5 * std::sin(2 * kPi * (uOf(x) * 32 + n * 4));
    const double k = (0.75 + 0.25 * grain) * (0.85 + 0.3 * hashUnit(plank, 1, 57));
    return scaled({168, 112, 66}, k);
  });
}

// Crate side: grain with a darker frame.
Texture crateTexture() {
  return makeTexture("crate", [](int x, int y) {
    const bool frame = x < 20 || x >= kTexSize - 20 || y < 20 || y >= kTexSize - 20;
    const double n = fbm(uOf(x), uOf(y), 4, 3, 61);
    const double grain = 0.5 + 0.5 * std::sin(2 * kPi * (uOf(y) * 12 + n * 3));
    const double k = (0.7 + 0.3 * grain) * (frame ? 0.7 : 1.0);
    return scaled({184, 140, 84}, k);
  });
}

Texture marbleTexture() {
  return makeTexture("marble", [](int x, int y) {
    const double n = fbm(uOf(x), uOf(y), 4, 5, 71);
    const double vein = std::pow(std::abs(std::sin(2 * kPi * (uOf(x) * 2 + n * 3))), 0.3);
    return scaled({232, 230, 226}, 0.7 + 0.3 * vein);
  });
}

Texture grassTexture() {
  return makeTexture("grass", [](int x, int y) {
    const double n = fbm(uOf(x), uOf(y), 8, 5, 81);
    const double m = fbm(uOf(x), uOf(y), 2, 2, 83);
    return rgb((62 + 40 * m) * (0.7 + 0.5 * n), (112 + 20 * m) * (0.7 + 0.5 * n),
               38 * (0.7 + 0.5 * n));
  });
}

Texture barkTexture() {
  return makeTexture("bark", [](int x, int y) {
    const double n =
        valueNoise(uOf(x) * 32, uOf(y) * 4, 32, 91) * 0.6 + fbm(uOf(x), uOf(y), 16, 3, 93) * 0.4;
    return scaled({92, 66, 46}, 0.55 + 0.6 * n);
  });
}

// Leaf clusters: opaque where the noise is high, fully transparent elsewhere.
Texture leavesTexture() {
  return makeTexture("leaves", [](int x, int y) {
    const double n = fbm(uOf(x), uOf(y), 16, 3, 101);
    if (n < 0.47) return Rgba8{40, 80, 30, 0};
    const double k = 0.7 + 0.6 * fbm(uOf(x), uOf(y), 32, 2, 103);
    return rgb(52 * k, 104 * k, 36 * k, 255);
  });
}

Texture needlesTexture() {
  return makeTexture("needles", [](int x, int y) {
    const double n =
        valueNoise(uOf(x) * 64, uOf(y) * 16, 64, 111) * 0.5 + fbm(uOf(x), uOf(y), 8, 3, 113) * 0.5;
    return scaled({34, 76, 44}, 0.6 + 0.6 * n);
  });
}

// One 3 m × 3 m facade bay: wall around a framed window.
Texture facadeTexture() {
  return makeTexture("facade", [](int x, int y) {
    const double n = fbm(uOf(x), uOf(y), 8, 3, 121);
    const int wx0 = 56, wx1 = 200, wy0 = 48, wy1 = 192;
    const bool inFrame = x >= wx0 - 6 && x < wx1 + 6 && y >= wy0 - 6 && y < wy1 + 10;
    const bool inGlass = x >= wx0 && x < wx1 && y >= wy0 && y < wy1;
    if (inGlass) {
      if (x >= 126 && x < 130) return rgb(200, 200, 196);  // mullion
      const double t = (y - wy0) / double(wy1 - wy0);
      const double refl = (x - wx0 + (wy1 - y)) % 90 < 30 ? 1.15 : 1.0;
      return scaled(glm::dvec3(96, 128, 160) * (1 - t) + glm::dvec3(40, 58, 86) * t, refl);
    }
    if (inFrame) return scaled({214, 214, 208}, 0.95 + 0.05 * n);
    return scaled({204, 192, 170}, 0.85 + 0.2 * n);
  });
}

Texture roofTexture() {
  return makeTexture("roof", [](int x, int y) {
    return scaled({112, 110, 104}, 0.75 + 0.4 * fbm(uOf(x), uOf(y), 32, 3, 131));
  });
}

Texture concreteTexture() {
  return makeTexture("concrete", [](int x, int y) {
    return scaled({150, 148, 142}, 0.8 + 0.3 * fbm(uOf(x), uOf(y), 8, 4, 141));
  });
}

Material material(const std::string& name, int texture, glm::vec4 colour = glm::vec4(1.0f)) {
  Material m;
  m.name = name;
  m.texture = texture;
  m.baseColour = colour;
  return m;
}

// ---------------------------------------------------------------------------
// Geometry builder: emits "pieces" (small one-material meshes with local
// indices) or, in count-only mode, just counts their triangles exactly.

// World-anchored planar texture projection: uv = (dot(P−origin, tu), dot(P−origin, tv)) / scale.
struct UvMap {
  glm::dvec3 origin{0.0};
  glm::dvec3 tu{1, 0, 0};
  glm::dvec3 tv{0, 0, 1};
  double scale = 1.0;
  glm::vec2 at(const glm::dvec3& p) const {
    const glm::dvec3 d = p - origin;
    return glm::vec2(glm::dot(d, tu) / scale, glm::dot(d, tv) / scale);
  }
};

struct Hole {  // in a rectangle's (a, b) coordinates
  double a0, a1, b0, b1;
};

struct ProfilePoint {  // surface-of-revolution profile: radius, height, normal, texture v
  double r, y, nr, ny, v;
};

struct Piece {
  int material;
  std::size_t v0, vn, i0, in;
  glm::vec3 centre;
};

class Builder {
 public:
  // `tileMetres`: largest tile a flat surface is cut into, which keeps pieces
  // small enough to chunk (and sets the triangle floor at low densities).
  Builder(double cellsPerMetre, double tileMetres, bool countOnly)
      : density_(cellsPerMetre), tile_(tileMetres), countOnly_(countOnly) {}

  int cells(double length) const {
    return std::max(1, static_cast<int>(std::ceil(length * density_ - 1e-6)));
  }
  int segments(double radius, int minSegments) const {
    return std::max(minSegments, static_cast<int>(std::ceil(2 * kPi * radius * density_ - 1e-6)));
  }
  std::size_t triangles() const { return triangles_; }
  bool countOnly() const { return countOnly_; }

  // nu × nv quads over P(a, b) = origin + a·eu + b·ev, a, b ∈ [0, 1]; faces
  // wound so that their geometric normal points along `normal`.
  void grid(int mat, const glm::dvec3& origin, const glm::dvec3& eu, const glm::dvec3& ev, int nu,
            int nv, const glm::dvec3& normal, const UvMap& uv) {
    triangles_ += 2 * static_cast<std::size_t>(nu) * nv;
    if (countOnly_) return;
    begin(mat);
    const glm::vec3 n(glm::normalize(normal));
    for (int j = 0; j <= nv; ++j)
      for (int i = 0; i <= nu; ++i) {
        const glm::dvec3 p = origin + eu * (double(i) / nu) + ev * (double(j) / nv);
        verts_.push_back(Vertex{glm::vec3(p), n, uv.at(p)});
      }
    const bool ccw = glm::dot(glm::cross(eu, ev), normal) > 0;
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const auto p00 = static_cast<std::uint32_t>(j * (nu + 1) + i);
        const std::uint32_t p10 = p00 + 1, p01 = p00 + static_cast<std::uint32_t>(nu + 1),
                            p11 = p01 + 1;
        if (ccw)
          tris({p00, p10, p11, p00, p11, p01});
        else
          tris({p00, p11, p10, p00, p01, p11});
      }
    end();
  }

  // Rectangle origin + a·dirU + b·dirV, a ∈ [0, lenU], b ∈ [0, lenV], minus
  // `holes`, cut at the holes' edges and into tiles ≤ tileMetres. Cells that
  // share an edge get the same subdivision along it (no T-junctions).
  void rect(int mat, const glm::dvec3& origin, const glm::dvec3& dirU, double lenU,
            const glm::dvec3& dirV, double lenV, const glm::dvec3& normal, const UvMap& uv,
            const std::vector<Hole>& holes = {}) {
    std::vector<double> bu{0.0, lenU}, bv{0.0, lenV};
    for (const Hole& h : holes) {
      bu.insert(bu.end(), {h.a0, h.a1});
      bv.insert(bv.end(), {h.b0, h.b1});
    }
    bu = breaks(bu, lenU, tile_);
    bv = breaks(bv, lenV, tile_);
    for (std::size_t j = 0; j + 1 < bv.size(); ++j) {
      const double b0 = bv[j], b1 = bv[j + 1];
      for (std::size_t i = 0; i + 1 < bu.size(); ++i) {
        const double a0 = bu[i], a1 = bu[i + 1];
        const double ac = 0.5 * (a0 + a1), bc = 0.5 * (b0 + b1);
        const bool hole = std::any_of(holes.begin(), holes.end(), [&](const Hole& h) {
          return ac > h.a0 && ac < h.a1 && bc > h.b0 && bc < h.b1;
        });
        if (hole) continue;
        grid(mat, origin + dirU * a0 + dirV * b0, dirU * (a1 - a0), dirV * (b1 - b0),
             cells(a1 - a0), cells(b1 - b0), normal, uv);
      }
    }
  }

  // Axis-aligned box; `faces` bit k set = emit face k (+X, −X, +Y, −Y, +Z, −Z).
  // Sides are textured with v down the world Y axis, top/bottom with (x, z).
  void box(int mat, const glm::dvec3& lo, const glm::dvec3& hi, double texScale,
           unsigned faces = 0x3f, const glm::dvec3& uvOrigin = glm::dvec3(0.0)) {
    const glm::dvec3 d = hi - lo;
    const glm::dvec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
    auto side = [&](const glm::dvec3& dirU) { return UvMap{uvOrigin, dirU, -Y, texScale}; };
    const UvMap flat{uvOrigin, X, Z, texScale};
    if (faces & 1u) rect(mat, {hi.x, lo.y, hi.z}, -Z, d.z, Y, d.y, X, side(-Z));
    if (faces & 2u) rect(mat, {lo.x, lo.y, lo.z}, Z, d.z, Y, d.y, -X, side(Z));
    if (faces & 4u) rect(mat, {lo.x, hi.y, lo.z}, X, d.x, Z, d.z, Y, flat);
    if (faces & 8u) rect(mat, {lo.x, lo.y, lo.z}, X, d.x, Z, d.z, -Y, flat);
    if (faces & 16u) rect(mat, {lo.x, lo.y, hi.z}, X, d.x, Y, d.y, Z, side(X));
    if (faces & 32u) rect(mat, {hi.x, lo.y, lo.z}, -X, d.x, Y, d.y, -Z, side(-X));
  }

  // Surface of revolution about the vertical axis through `base`, profile
  // ordered so that the outside is on the left going up (bottom pole → top
  // pole for a sphere); a profile point with r = 0 is a pole.
  void lathe(int mat, const glm::dvec3& base, const std::vector<ProfilePoint>& profile, int segs,
             double uRepeat) {
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
      const bool pole0 = profile[i].r == 0, pole1 = profile[i + 1].r == 0;
      if (!(pole0 && pole1))
        triangles_ += static_cast<std::size_t>(segs) * (pole0 || pole1 ? 1 : 2);
    }
    if (countOnly_) return;
    begin(mat);
    for (const ProfilePoint& p : profile)
      for (int j = 0; j <= segs; ++j) {
        const double t = 2 * kPi * j / segs;
        const double c = std::cos(t), s = std::sin(t);
        const glm::dvec3 pos = base + glm::dvec3(p.r * c, p.y, p.r * s);
        const glm::vec3 n(glm::normalize(glm::dvec3(p.nr * c, p.ny, p.nr * s)));
        verts_.push_back(
            Vertex{glm::vec3(pos), n, glm::vec2(float(uRepeat * j / segs), float(p.v))});
      }
    const auto ring = static_cast<std::uint32_t>(segs + 1);
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
      const bool pole0 = profile[i].r == 0, pole1 = profile[i + 1].r == 0;
      if (pole0 && pole1) continue;
      for (int j = 0; j < segs; ++j) {
        const auto a = static_cast<std::uint32_t>(i) * ring + static_cast<std::uint32_t>(j);
        const std::uint32_t b = a + ring, c = b + 1, d = a + 1;
        if (!pole1) tris({a, b, c});
        if (!pole0) tris({a, c, d});
      }
    }
    end();
  }

  // One tile of a heightfield over the global lattice x = x0 + gi·step,
  // z = z0 + gj·step, cells [gi0, gi0+n) × [gj0, gj0+n); shared edges are
  // bit-identical between tiles.
  template <class HeightFn, class GradFn>
  void heightTile(int mat, double x0, double z0, double step, int gi0, int gj0, int n,
                  const HeightFn& height, const GradFn& grad, double texScale) {
    triangles_ += 2 * static_cast<std::size_t>(n) * n;
    if (countOnly_) return;
    begin(mat);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double x = x0 + (gi0 + i) * step, z = z0 + (gj0 + j) * step;
        const glm::dvec2 g = grad(x, z);
        verts_.push_back(Vertex{glm::vec3(glm::dvec3(x, height(x, z), z)),
                                glm::vec3(glm::normalize(glm::dvec3(-g.x, 1.0, -g.y))),
                                glm::vec2(float(x / texScale), float(z / texScale))});
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto p00 = static_cast<std::uint32_t>(j * (n + 1) + i);
        const std::uint32_t p10 = p00 + 1, p01 = p00 + static_cast<std::uint32_t>(n + 1),
                            p11 = p01 + 1;
        tris({p00, p11, p10, p00, p01, p11});  // +x × +z points down, so reverse
      }
    end();
  }

  std::vector<Vertex>& vertices() { return verts_; }
  std::vector<std::uint32_t>& indices() { return idx_; }
  const std::vector<Piece>& pieces() const { return pieces_; }

 private:
  static std::vector<double> breaks(std::vector<double> b, double len, double tile) {
    for (double& x : b) x = std::clamp(x, 0.0, len);
    std::sort(b.begin(), b.end());
    std::vector<double> out;
    for (double x : b)
      if (out.empty() || x - out.back() > 1e-9) out.push_back(x);
    std::vector<double> tiled{out.front()};
    for (std::size_t i = 1; i < out.size(); ++i) {
      const double span = out[i] - out[i - 1];
      const int k = std::max(1, static_cast<int>(std::ceil(span / tile - 1e-9)));
      for (int s = 1; s < k; ++s) tiled.push_back(out[i - 1] + span * s / k);
      tiled.push_back(out[i]);
    }
    return tiled;
  }
  void begin(int mat) { current_ = Piece{mat, verts_.size(), 0, idx_.size(), 0, glm::vec3(0.0f)}; }
  void tris(std::initializer_list<std::uint32_t> ids) { idx_.insert(idx_.end(), ids); }
  void end() {
    current_.vn = verts_.size() - current_.v0;
    current_.in = idx_.size() - current_.i0;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (std::size_t k = current_.v0; k < verts_.size(); ++k) {
      lo = glm::min(lo, verts_[k].position);
      hi = glm::max(hi, verts_[k].position);
    }
    current_.centre = 0.5f * (lo + hi);
    pieces_.push_back(current_);
  }

  double density_;
  double tile_;
  bool countOnly_;
  std::size_t triangles_ = 0;
  std::vector<Vertex> verts_;
  std::vector<std::uint32_t> idx_;
  std::vector<Piece> pieces_;
  Piece current_{};
};

using Generator = std::function<void(Builder&)>;

// Density (cells per metre) whose triangle count is closest to `target`.
double solveDensity(const Generator& gen, double tileMetres, std::size_t target) {
  auto count = [&](double s) {
    Builder b(s, tileMetres, true);
    gen(b);
    return b.triangles();
  };
  double lo = 1e-3, hi = 1e3;
  for (int it = 0; it < 60; ++it) {
    const double mid = std::sqrt(lo * hi);
    if (count(mid) >= target)
      hi = mid;
    else
      lo = mid;
  }
  const auto dist = [&](double s) {
    const double c = static_cast<double>(count(s));
    return std::abs(c - static_cast<double>(target));
  };
  return dist(lo) < dist(hi) ? lo : hi;
}

// Splits one material's pieces into spatially compact groups of at most
// `maxTris` triangles (median cuts along the longest axis of the centres).
void splitPieces(const std::vector<Piece>& pieces, std::vector<int> ids, std::size_t maxTris,
                 std::vector<std::vector<int>>& groups) {
  std::size_t total = 0;
  for (int id : ids) total += pieces[static_cast<std::size_t>(id)].in / 3;
  if (total <= maxTris || ids.size() <= 1) {
    groups.push_back(std::move(ids));
    return;
  }
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (int id : ids) {
    lo = glm::min(lo, pieces[static_cast<std::size_t>(id)].centre);
    hi = glm::max(hi, pieces[static_cast<std::size_t>(id)].centre);
  }
  const glm::vec3 ext = hi - lo;
  const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  std::stable_sort(ids.begin(), ids.end(), [&](int a, int b) {
    return pieces[static_cast<std::size_t>(a)].centre[axis] <
           pieces[static_cast<std::size_t>(b)].centre[axis];
  });
  std::size_t acc = 0, cut = 1;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    acc += pieces[static_cast<std::size_t>(ids[k])].in / 3;
    if (2 * acc >= total) {
      cut = std::clamp<std::size_t>(k + 1, 1, ids.size() - 1);
      break;
    }
  }
  splitPieces(pieces, std::vector<int>(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(cut)),
              maxTris, groups);
  splitPieces(pieces, std::vector<int>(ids.begin() + static_cast<std::ptrdiff_t>(cut), ids.end()),
              maxTris, groups);
}

// Solves the density for `target`, generates, and chunks into meshes.
Scene buildScene(const std::string& name, const Generator& gen, double tileMetres,
                 std::size_t target, std::vector<Material> materials,
                 std::vector<Texture> textures) {
  target = std::clamp<std::size_t>(target, 5'000, 50'000'000);
  const double density = solveDensity(gen, tileMetres, target);
  Builder counter(density, tileMetres, true);
  gen(counter);
  Builder b(density, tileMetres, false);
  b.vertices().reserve(counter.triangles() * 6 / 10 + 1024);
  b.indices().reserve(counter.triangles() * 3);
  gen(b);
  HW_CHECK_EQ(b.indices().size(), counter.triangles() * 3);

  // Chunks of ~target/200 triangles (at least 1'500, at most 20'000).
  const std::size_t maxTris = std::clamp<std::size_t>(target / 200, 1'500, 20'000);
  Scene scene;
  scene.name = name;
  std::vector<std::vector<int>> byMaterial(materials.size());
  for (std::size_t i = 0; i < b.pieces().size(); ++i)
    byMaterial[static_cast<std::size_t>(b.pieces()[i].material)].push_back(static_cast<int>(i));
  for (std::size_t m = 0; m < byMaterial.size(); ++m) {
    if (byMaterial[m].empty()) continue;
    std::vector<std::vector<int>> groups;
    splitPieces(b.pieces(), byMaterial[m], maxTris, groups);
    for (std::size_t g = 0; g < groups.size(); ++g) {
      Mesh mesh;
      mesh.name = materials[m].name + "." + std::to_string(g);
      mesh.material = static_cast<int>(m);
      std::size_t nv = 0, ni = 0;
      for (int id : groups[g]) {
        nv += b.pieces()[static_cast<std::size_t>(id)].vn;
        ni += b.pieces()[static_cast<std::size_t>(id)].in;
      }
      mesh.vertices.reserve(nv);
      mesh.indices.reserve(ni);
      for (int id : groups[g]) {
        const Piece& p = b.pieces()[static_cast<std::size_t>(id)];
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.insert(mesh.vertices.end(),
                             b.vertices().begin() + static_cast<std::ptrdiff_t>(p.v0),
                             b.vertices().begin() + static_cast<std::ptrdiff_t>(p.v0 + p.vn));
        for (std::size_t k = p.i0; k < p.i0 + p.in; ++k)
          mesh.indices.push_back(base + b.indices()[k]);
      }
      scene.meshes.push_back(std::move(mesh));
    }
  }
  scene.materials = std::move(materials);
  scene.textures = std::move(textures);
  scene.computeBounds();
  return scene;
}

// Vertical cylinder side (no caps), bottom centre `base`.
void cylinder(Builder& b, int mat, const glm::dvec3& base, double r, double h, double texScale,
              bool capTop) {
  const int segs = b.segments(r, 6);
  const int rows = b.cells(h);
  std::vector<ProfilePoint> prof;
  for (int i = 0; i <= rows; ++i) {
    const double y = h * i / rows;
    prof.push_back({r, y, 1, 0, (h - y) / texScale});
  }
  b.lathe(mat, base, prof, segs, std::max(1.0, std::round(2 * kPi * r / texScale)));
  if (capTop) {
    std::vector<ProfilePoint> cap;
    const int rings = b.cells(r);
    for (int i = 0; i <= rings; ++i)
      cap.push_back({r * (rings - i) / rings, h, 0, 1, r * i / rings / texScale});
    b.lathe(mat, base, cap, segs, 1.0);
  }
}

void sphere(Builder& b, int mat, const glm::dvec3& centre, double r, double uRepeat,
            double vRepeat) {
  const int segs = b.segments(r, 8);
  const int rings = std::max(4, segs / 2);
  std::vector<ProfilePoint> prof;
  for (int i = 0; i <= rings; ++i) {
    const double phi = -0.5 * kPi + kPi * i / rings;
    const double c = i == 0 || i == rings ? 0.0 : std::cos(phi);
    prof.push_back({r * c, r * std::sin(phi), c, std::sin(phi), vRepeat * (rings - i) / rings});
  }
  b.lathe(mat, centre, prof, segs, uRepeat);
}

// Cone side from radius r at `base` to the apex h above, with its base disc.
void cone(Builder& b, int mat, const glm::dvec3& base, double r, double h, double texScale) {
  const int segs = b.segments(r, 6);
  const int rows = b.cells(std::hypot(r, h));
  const double slant = std::hypot(r, h);
  std::vector<ProfilePoint> prof;
  for (int i = 0; i <= rows; ++i) {
    const double t = double(i) / rows;
    prof.push_back({r * (1 - t), h * t, h / slant, r / slant, slant * (1 - t) / texScale});
  }
  b.lathe(mat, base, prof, segs, std::max(1.0, std::round(2 * kPi * r / texScale)));
  std::vector<ProfilePoint> disc;
  const int rings = b.cells(r);
  for (int i = 0; i <= rings; ++i)
    disc.push_back({r * i / rings, 0, 0, -1, r * i / rings / texScale});
  b.lathe(mat, base, disc, segs, 1.0);
}

// ---------------------------------------------------------------------------
// Indoor scene.

namespace indoor {

constexpr double kCeiling = 3.0;
constexpr double kWall = 0.2;  // wall thickness
constexpr double kDoorW = 1.2, kDoorH = 2.2;

enum Mat {
  kBrick,
  kPlaster,
  kChecker,
  kWoodFloor,
  kTile,
  kCheckerBlue,
  kWood,
  kCrate,
  kMarble,
  kRed,
  kSteel,
  kMatCount
};

struct Opening {
  double c;    // centre along the wall
  double w;    // width
  double top;  // height of the opening's top (≥ kCeiling: full height)
};
struct Wall {
  bool alongX;  // runs along x at z = at (else along z at x = at)
  double at, from, to;
  std::vector<Opening> openings;
};
struct Region {
  double x0, x1, z0, z1;
  int floorMat;
};

const std::vector<Region>& regions() {
  static const std::vector<Region> r = {
      {0, 24, -1.5, 1.5, kTile},          // corridor
      {0, 12, 1.5, 12, kChecker},         // NW room
      {12, 24, 1.5, 12, kWoodFloor},      // NE room
      {0, 12, -12, -1.5, kTile},          // SW room
      {12, 24, -12, -1.5, kCheckerBlue},  // SE room
      {24, 33, -6, 6, kChecker},          // hall
  };
  return r;
}

const std::vector<Wall>& walls() {
  static const std::vector<Wall> w = {
      {true, 1.5, 0, 24, {{6, kDoorW, kDoorH}, {18, kDoorW, kDoorH}}},
      {true, -1.5, 0, 24, {{6, kDoorW, kDoorH}, {18, kDoorW, kDoorH}}},
      {true, 12, 0, 24, {}},
      {true, -12, 0, 24, {}},
      {false, 0, -12, 12, {}},
      {false, 12, 1.5, 12, {{6.6, kDoorW, kDoorH}}},
      {false, 12, -12, -1.5, {{-8, kDoorW, kDoorH}}},
      {false, 24, -12, 12, {{0, 3.0, kCeiling}}},  // corridor opens into the hall
      {true, 6, 24, 33, {}},
      {true, -6, 24, 33, {}},
      {false, 33, -6, 6, {}},
  };
  return w;
}

void addWall(Builder& b, const Wall& w) {
  const double h = kWall / 2;
  const double from = w.from - h, len = w.to - w.from + kWall;
  // Local frame: a along the wall, b up, the two long faces at ±h.
  const glm::dvec3 along = w.alongX ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
  const glm::dvec3 across = w.alongX ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 up(0, 1, 0);
  const glm::dvec3 start = along * from + across * w.at;
  std::vector<Hole> holes;
  for (const Opening& o : w.openings)
    holes.push_back({o.c - o.w / 2 - from, o.c + o.w / 2 - from, 0.0, std::min(o.top, kCeiling)});
  const UvMap uvAlong{glm::dvec3(0.0), along, -up, 1.0};
  // Both long faces, wound by their normals.
  b.rect(kBrick, start + across * h, along, len, up, kCeiling, across, uvAlong, holes);
  b.rect(kBrick, start - across * h, along, len, up, kCeiling, -across, uvAlong, holes);
  // End caps.
  const UvMap uvAcross{glm::dvec3(0.0), across, -up, 1.0};
  b.rect(kBrick, start - across * h, across, kWall, up, kCeiling, -along, uvAcross);
  b.rect(kBrick, start + along * len - across * h, across, kWall, up, kCeiling, along, uvAcross);
  // Door jambs and lintel undersides.
  for (const Hole& o : holes) {
    const double top = o.b1;
    b.rect(kBrick, start + along * o.a0 - across * h, across, kWall, up, top, along, uvAcross);
    b.rect(kBrick, start + along * o.a1 - across * h, across, kWall, up, top, -along, uvAcross);
    if (top < kCeiling)
      b.rect(kBrick, start + along * o.a0 - across * h + up * top, along, o.a1 - o.a0, across,
             kWall, -up, UvMap{glm::dvec3(0.0), along, across, 1.0});
  }
}

void table(Builder& b, double cx, double cz, double w, double d) {
  const double top = 0.75, t = 0.05, leg = 0.06, inset = 0.08;
  b.box(kWood, {cx - w / 2, top - t, cz - d / 2}, {cx + w / 2, top, cz + d / 2}, 1.0);
  for (int sx : {-1, 1})
    for (int sz : {-1, 1}) {
      const double lx = cx + sx * (w / 2 - inset), lz = cz + sz * (d / 2 - inset);
      b.box(kWood, {lx - leg / 2, 0, lz - leg / 2}, {lx + leg / 2, top - t, lz + leg / 2}, 1.0,
            0x3f & ~8u);
    }
}

void crate(Builder& b, double cx, double y0, double cz, double s) {
  b.box(kCrate, {cx - s / 2, y0, cz - s / 2}, {cx + s / 2, y0 + s, cz + s / 2}, s, 0x3f & ~8u,
        glm::dvec3(cx - s / 2, y0 + s, cz - s / 2));
}

void column(Builder& b, double cx, double cz, double r) {
  b.box(kMarble, {cx - r - 0.1, 0, cz - r - 0.1}, {cx + r + 0.1, 0.2, cz + r + 0.1}, 1.0,
        0x3f & ~8u);
  cylinder(b, kMarble, {cx, 0.2, cz}, r, kCeiling - 0.2, 1.0, false);
}

void generate(Builder& b) {
  for (const Region& r : regions()) {
    const UvMap floorUv{glm::dvec3(0.0), {1, 0, 0}, {0, 0, 1}, r.floorMat == kTile ? 1.0 : 2.0};
    b.rect(r.floorMat, {r.x0, 0, r.z0}, {1, 0, 0}, r.x1 - r.x0, {0, 0, 1}, r.z1 - r.z0, {0, 1, 0},
           floorUv);
    b.rect(kPlaster, {r.x0, kCeiling, r.z0}, {1, 0, 0}, r.x1 - r.x0, {0, 0, 1}, r.z1 - r.z0,
           {0, -1, 0}, UvMap{glm::dvec3(0.0), {1, 0, 0}, {0, 0, 1}, 2.0});
  }
  for (const Wall& w : walls()) addWall(b, w);

  // SW room (the walk starts here).
  table(b, 9, -8, 1.6, 0.9);
  sphere(b, kRed, {9, 0.75 + 0.22, -8}, 0.22, 1, 1);
  crate(b, 1.0, 0, -3.0, 0.8);
  crate(b, 1.1, 0, -11.0, 1.0);
  crate(b, 1.1, 1.0, -11.0, 0.6);
  crate(b, 10.8, 0, -2.5, 0.7);
  column(b, 9.5, -4.0, 0.25);
  // NW room.
  table(b, 4, 7, 1.8, 0.9);
  table(b, 8, 7, 1.8, 0.9);
  crate(b, 11.0, 0, 11.0, 1.0);
  crate(b, 1.0, 0, 10.0, 0.8);
  sphere(b, kSteel, {6, 0.6, 10.5}, 0.6, 2, 1);
  // NE room.
  for (double x : {16.0, 20.0})
    for (double z : {5.0, 9.0}) column(b, x, z, 0.3);
  crate(b, 23.0, 0, 2.6, 0.9);
  sphere(b, kRed, {18, 0.5, 7}, 0.5, 2, 1);
  // SE room.
  table(b, 15, -8, 1.6, 0.9);
  table(b, 21, -8, 1.6, 0.9);
  crate(b, 13.0, 0, -3.0, 0.8);
  crate(b, 22.6, 0, -2.6, 0.7);
  sphere(b, kSteel, {21, 0.75 + 0.3, -8}, 0.3, 2, 1);
  // Corridor.
  crate(b, 12.0, 0, -1.05, 0.5);
  crate(b, 3.0, 0, 1.0, 0.6);
  // Hall.
  for (double x : {27.0, 30.5})
    for (double z : {-3.5, 3.5}) column(b, x, z, 0.3);
  b.box(kMarble, {31.7, 0, -0.3}, {32.3, 1.0, 0.3}, 1.0, 0x3f & ~8u);
  sphere(b, kSteel, {32, 1.35, 0}, 0.35, 2, 1);
  table(b, 28.5, 5.0, 1.6, 0.8);
  crate(b, 32.2, 0, -5.3, 0.9);
}

}  // namespace indoor

// ---------------------------------------------------------------------------
// Outdoor scene.

namespace outdoor {

constexpr double kHalf = 160.0;  // terrain spans [−160, 160]² m
constexpr int kTiles = 16;       // terrain tiles per side (20 m each)
constexpr double kEyeAbove = 4.0;

enum Mat {
  kGrass,
  kFacadeA,
  kFacadeB,
  kFacadeC,
  kConcrete,
  kRoof,
  kBark,
  kLeaves,
  kNeedles,
  kMatCount
};

glm::dvec2 terrainGrad(double x, double z) {
  const double s1 = std::sin(0.021 * x + 0.3), c1 = std::cos(0.021 * x + 0.3);
  const double s2 = std::sin(0.017 * z + 1.1), c2 = std::cos(0.017 * z + 1.1);
  const double c3 = std::cos(0.045 * x + 0.037 * z + 2.0);
  const double s4 = std::sin(0.06 * z - 0.03 * x + 0.5);
  return {6.0 * 0.021 * c1 * c2 + 3.0 * 0.045 * c3 + 1.5 * 0.03 * s4,
          -6.0 * 0.017 * s1 * s2 + 3.0 * 0.037 * c3 - 1.5 * 0.06 * s4};
}

// The lane the default path drives along (kept free of buildings and trees).
glm::dvec2 lane(double t) { return {-90.0 + 180.0 * t, 35.0 * std::sin(1.5 * kPi * t)}; }

double laneDistance(const glm::dvec2& p) {
  double best = 1e30;
  constexpr int kN = 400;
  for (int i = 0; i < kN; ++i) {
    const glm::dvec2 a = lane(-0.1 + 1.2 * i / kN), c = lane(-0.1 + 1.2 * (i + 1) / kN);
    const glm::dvec2 ab = c - a;
    const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    best = std::min(best, glm::length(p - (a + t * ab)));
  }
  return best;
}

struct Building {
  double x0, z0, x1, z1, base, ref, top;
  int facade;
};
struct Tree {
  double x, z, ground;
  bool conifer;
  double scale;
};
struct Layout {
  std::vector<Building> buildings;
  std::vector<Tree> trees;
};

const Layout& layout() {
  static const Layout l = [] {
    Layout out;
    Rng rng(20240611u);
    for (int attempt = 0; attempt < 4000 && out.buildings.size() < 32; ++attempt) {
      const double w = 3.0 * std::floor(rng.uniform(3, 7.99)),
                   d = 3.0 * std::floor(rng.uniform(3, 7.99));
      const double cx = rng.uniform(-kHalf + 20, kHalf - 20),
                   cz = rng.uniform(-kHalf + 20, kHalf - 20);
      const int floors = static_cast<int>(rng.uniform(2, 9.99));
      const int facade = static_cast<int>(rng.uniform(0, 2.99));
      const Building cand{cx - w / 2, cz - d / 2, cx + w / 2, cz + d / 2, 0, 0, 0, facade};
      // Keep the lane clear: the nearest footprint point must be ≥ 14 m away.
      bool ok = true;
      for (double u : {0.0, 0.25, 0.5, 0.75, 1.0})
        for (double v : {0.0, 0.25, 0.5, 0.75, 1.0})
          if (laneDistance({cand.x0 + u * w, cand.z0 + v * d}) < 14.0) ok = false;
      for (const Building& o : out.buildings)
        if (cand.x0 < o.x1 + 8 && o.x0 < cand.x1 + 8 && cand.z0 < o.z1 + 8 && o.z0 < cand.z1 + 8)
          ok = false;
      if (!ok) continue;
      double lo = 1e30, hi = -1e30;
      for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j) {
          const double hgt = outdoorTerrainHeight(cand.x0 + w * i / 6, cand.z0 + d * j / 6);
          lo = std::min(lo, hgt);
          hi = std::max(hi, hgt);
        }
      Building bld = cand;
      bld.base = lo - 1.0;
      bld.ref = hi + 0.5;
      bld.top = bld.ref + 3.0 * floors;
      out.buildings.push_back(bld);
    }
    for (int attempt = 0; attempt < 20000 && out.trees.size() < 130; ++attempt) {
      const double x = rng.uniform(-kHalf + 6, kHalf - 6), z = rng.uniform(-kHalf + 6, kHalf - 6);
      const bool conifer = rng.uniform(0, 1) < 0.45;
      const double scale = rng.uniform(0.8, 1.25);
      bool ok = laneDistance({x, z}) > 4.5 * scale + 3.0;
      for (const Building& bd : out.buildings)
        if (x > bd.x0 - 5 && x < bd.x1 + 5 && z > bd.z0 - 5 && z < bd.z1 + 5) ok = false;
      for (const Tree& t : out.trees)
        if (std::hypot(t.x - x, t.z - z) < 5.0) ok = false;
      if (!ok) continue;
      out.trees.push_back({x, z, outdoorTerrainHeight(x, z), conifer, scale});
    }
    return out;
  }();
  return l;
}

void generate(Builder& b) {
  const int n = b.cells(2 * kHalf / kTiles);
  const double step = 2 * kHalf / (kTiles * n);
  for (int tj = 0; tj < kTiles; ++tj)
    for (int ti = 0; ti < kTiles; ++ti)
      b.heightTile(kGrass, -kHalf, -kHalf, step, ti * n, tj * n, n, outdoorTerrainHeight,
                   terrainGrad, 4.0);

  for (const Building& bd : layout().buildings) {
    const int facade = kFacadeA + bd.facade;
    // Foundation band (concrete) from below ground to the first floor line.
    b.box(kConcrete, {bd.x0, bd.base, bd.z0}, {bd.x1, bd.ref, bd.z1}, 2.0, 1u | 2u | 16u | 32u);
    // Facades: one 3 m × 3 m window bay per texture repeat, aligned to the
    // floor lines (v = 0 at each floor's top) and to each face's corner.
    const glm::dvec3 lo(bd.x0, bd.ref, bd.z0), hi(bd.x1, bd.top, bd.z1);
    const glm::dvec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
    const double w = bd.x1 - bd.x0, d = bd.z1 - bd.z0, h = bd.top - bd.ref;
    auto uv = [&](const glm::dvec3& corner, const glm::dvec3& dirU) {
      return UvMap{glm::dvec3(corner.x, bd.top, corner.z), dirU, -Y, 3.0};
    };
    b.rect(facade, {hi.x, lo.y, hi.z}, -Z, d, Y, h, X, uv({hi.x, 0, hi.z}, -Z));
    b.rect(facade, {lo.x, lo.y, lo.z}, Z, d, Y, h, -X, uv({lo.x, 0, lo.z}, Z));
    b.rect(facade, {lo.x, lo.y, hi.z}, X, w, Y, h, Z, uv({lo.x, 0, hi.z}, X));
    b.rect(facade, {hi.x, lo.y, lo.z}, -X, w, Y, h, -Z, uv({hi.x, 0, lo.z}, -X));
    b.rect(kRoof, {lo.x, hi.y, lo.z}, X, w, Z, d, Y, UvMap{glm::dvec3(0.0), X, Z, 4.0});
  }

  for (const Tree& t : layout().trees) {
    const glm::dvec3 g(t.x, t.ground - 0.3, t.z);
    if (t.conifer) {
      cylinder(b, kBark, g, 0.25 * t.scale, 2.6 * t.scale, 1.0, false);
      cone(b, kNeedles, g + glm::dvec3(0, 2.0 * t.scale, 0), 2.3 * t.scale, 7.5 * t.scale, 2.0);
    } else {
      cylinder(b, kBark, g, 0.3 * t.scale, 4.0 * t.scale, 1.0, false);
      sphere(b, kLeaves, g + glm::dvec3(0, 5.6 * t.scale, 0), 3.0 * t.scale, 6, 3);
    }
  }
}

}  // namespace outdoor

}  // namespace

double outdoorTerrainHeight(double x, double z) {
  return 6.0 * std::sin(0.021 * x + 0.3) * std::cos(0.017 * z + 1.1) +
         3.0 * std::sin(0.045 * x + 0.037 * z + 2.0) + 1.5 * std::cos(0.06 * z - 0.03 * x + 0.5);
}

Scene makeIndoorScene(std::size_t targetTriangles) {
  using namespace indoor;
  std::vector<Texture> tex = {brickTexture(), plasterTexture(), checkerTexture(), woodTexture(),
                              tileTexture(),  crateTexture(),   marbleTexture()};
  enum { tBrick, tPlaster, tChecker, tWood, tTile, tCrate, tMarble };
  std::vector<Material> mats(kMatCount);
  mats[kBrick] = material("brick_wall", tBrick);
  mats[kPlaster] = material("plaster_ceiling", tPlaster);
  mats[kChecker] = material("checker_floor", tChecker);
  mats[kWoodFloor] = material("wood_floor", tWood, glm::vec4(0.9f, 0.85f, 0.8f, 1.0f));
  mats[kTile] = material("tile_floor", tTile);
  mats[kCheckerBlue] =
      material("checker_floor_blue", tChecker, glm::vec4(0.75f, 0.85f, 1.0f, 1.0f));
  mats[kWood] = material("wood", tWood);
  mats[kCrate] = material("crate", tCrate);
  mats[kMarble] = material("marble", tMarble);
  mats[kRed] = material("red_paint", -1, glm::vec4(0.8f, 0.12f, 0.1f, 1.0f));
  mats[kSteel] = material("steel", -1, glm::vec4(0.6f, 0.62f, 0.66f, 1.0f));
  Scene s = buildScene("indoor", generate, 1.5, targetTriangles, std::move(mats), std::move(tex));
  s.skyColour = glm::vec3(0.0f);
  return s;
}

Scene makeOutdoorScene(std::size_t targetTriangles) {
  using namespace outdoor;
  std::vector<Texture> tex = {grassTexture(), facadeTexture(), concreteTexture(), roofTexture(),
                              barkTexture(),  leavesTexture(), needlesTexture()};
  enum { tGrass, tFacade, tConcrete, tRoof, tBark, tLeaves, tNeedles };
  std::vector<Material> mats(kMatCount);
  mats[kGrass] = material("grass", tGrass);
  mats[kFacadeA] = material("facade_sand", tFacade);
  mats[kFacadeB] = material("facade_grey", tFacade, glm::vec4(0.8f, 0.84f, 0.9f, 1.0f));
  mats[kFacadeC] = material("facade_red", tFacade, glm::vec4(1.0f, 0.78f, 0.7f, 1.0f));
  mats[kConcrete] = material("concrete", tConcrete);
  mats[kRoof] = material("roof", tRoof);
  mats[kBark] = material("bark", tBark);
  mats[kLeaves] = material("leaves", tLeaves);
  mats[kLeaves].alphaTest = true;
  mats[kLeaves].twoSided = true;
  mats[kNeedles] = material("needles", tNeedles);
  return buildScene("outdoor", generate, 8.0, targetTriangles, std::move(mats), std::move(tex));
}

namespace {
CameraPath basePath() {
  CameraPath p;
  p.width = 512;
  p.height = 512;
  p.fovYDeg = 60.0;
  p.frames = 120;
  p.keyframeEvery = 10;
  return p;
}
}  // namespace

CameraPath defaultIndoorPath() {
  CameraPath p = basePath();
  p.nearPlane = 0.1;
  p.farPlane = 100.0;
  constexpr double kEye = 1.7;
  struct K {
    double ex, ez, lx, ly, lz;
  };
  const K keys[] = {
      {3.0, -9.5, 6.0, 1.6, -1.5},  // SW room, facing its doorway
      {4.6, -6.4, 6.0, 1.6, -1.5},
      {6.0, -3.8, 6.0, 1.6, 1.5},   // lined up with the doorway
      {6.0, -1.5, 9.0, 1.6, 0.5},   // in the doorway
      {7.2, -0.2, 13.0, 1.6, 0.0},  // turning east into the corridor
      {10.0, 0.0, 16.0, 1.6, 0.0},
      {14.0, 0.0, 20.0, 1.6, 0.0},
      {18.0, 0.0, 18.5, 1.5, 5.0},  // glance into the NE room
      {21.0, 0.0, 27.0, 1.6, 0.0},
      {24.5, 0.0, 30.0, 1.5, -2.0},  // entering the hall
      {27.5, 0.3, 32.0, 1.5, 0.0},
      {30.0, 0.3, 32.0, 1.2, 0.0},  // facing the sphere on its pedestal
  };
  for (const K& k : keys) p.keys.push_back({{k.ex, kEye, k.ez}, {k.lx, k.ly, k.lz}});
  return p;
}

CameraPath defaultOutdoorPath() {
  CameraPath p = basePath();
  p.nearPlane = 0.5;
  p.farPlane = 1000.0;
  constexpr int kKeys = 13;
  for (int i = 0; i < kKeys; ++i) {
    const double t = double(i) / (kKeys - 1);
    // Look 25-30 m ahead along the lane, level with the eye's height above ground.
    const glm::dvec2 e = outdoor::lane(t), a = outdoor::lane(t + 0.15);
    p.keys.push_back({{e.x, outdoorTerrainHeight(e.x, e.y) + outdoor::kEyeAbove, e.y},
                      {a.x, outdoorTerrainHeight(a.x, a.y) + outdoor::kEyeAbove, a.y}});
  }
  return p;
}

}  // namespace hw::scenes
