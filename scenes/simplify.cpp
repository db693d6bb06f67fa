#include "scenes/simplify.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <queue>
#include <unordered_map>
#include <utility>

#include <glm/glm.hpp>

namespace hw::scenes {
namespace {

struct Local {
  std::uint32_t index = 0;  // into the mesh's vertices
  glm::dvec3 p{0.0}, n{0.0};
  glm::dvec2 uv{0.0};
};

class Simplifier {
 public:
  Simplifier(const Mesh& mesh, std::uint32_t first, std::uint32_t count,
             const SimplifyOptions& options)
      : opt_(options) {
    std::unordered_map<std::uint32_t, int> local;
    double scale = 1.0;
    for (std::uint32_t t = first; t < first + count; ++t) {
      std::array<int, 3> tri{};
      const std::uint32_t* ix = &mesh.indices[3 * std::size_t(t)];
      if (ix[0] == ix[1] || ix[1] == ix[2] || ix[0] == ix[2]) continue;  // no area
      for (int j = 0; j < 3; ++j) {
        auto [it, fresh] = local.emplace(ix[j], static_cast<int>(verts_.size()));
        if (fresh) {
          const Vertex& mv = mesh.vertices[ix[j]];
          Local l;
          l.index = ix[j];
          l.p = glm::dvec3(mv.position);
          const double len = glm::length(glm::dvec3(mv.normal));
          l.n = len > 0 ? glm::dvec3(mv.normal) / len : glm::dvec3(0.0);
          l.uv = glm::dvec2(mv.uv);
          verts_.push_back(l);
          scale = std::max({scale, std::abs(l.p.x), std::abs(l.p.y), std::abs(l.p.z)});
        }
        tri[static_cast<std::size_t>(j)] = it->second;
      }
      tris_.push_back(tri);
      source_.push_back(t);
    }
    // Float positions carry a relative rounding of 2^-24: errors below a few
    // of those are no movement at all.
    eps_ = 8.0 * FLT_EPSILON * scale;
    alive_.assign(tris_.size(), true);
    vtris_.resize(verts_.size());
    for (std::size_t t = 0; t < tris_.size(); ++t)
      for (int v : tris_[t]) vtris_[static_cast<std::size_t>(v)].push_back(static_cast<int>(t));
    err_.assign(verts_.size(), 0.0);
    lockBorders();
  }

  SimplifiedTriangles run() {
    // Cheapest collapse first; an entry is stale once its vertex's fan has
    // changed (its stamp moved on), and is checked again when taken.
    using Entry = std::pair<double, std::array<int, 3>>;  // error, {u, v, stamp}
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    std::vector<int> stamp(verts_.size(), 0);
    const auto offer = [&](int u) {
      if (locked_[static_cast<std::size_t>(u)] || vtris_[static_cast<std::size_t>(u)].empty())
        return;
      neighbours(u, ring_);
      if (!fanRemovable(u)) return;
      double best = opt_.maxError + 1.0;
      int bestV = -1;
      for (int v : ring_) {
        double e = 0;
        if (canCollapse(u, v, &e) && e < best) {
          best = e;
          bestV = v;
          if (e == 0) break;  // nothing is cheaper
        }
      }
      if (bestV >= 0) queue.push({best, {u, bestV, stamp[static_cast<std::size_t>(u)]}});
    };
    for (std::size_t u = 0; u < verts_.size(); ++u) offer(static_cast<int>(u));
    std::vector<int> around;
    while (!queue.empty()) {
      const auto [e, uvs] = queue.top();
      queue.pop();
      const int u = uvs[0], v = uvs[1];
      if (vtris_[static_cast<std::size_t>(u)].empty() || uvs[2] != stamp[static_cast<std::size_t>(u)])
        continue;
      neighbours(u, ring_);  // u's fan is as when offered (same stamp)
      double now = 0;
      if (!canCollapse(u, v, &now)) {  // v's side changed since
        ++stamp[static_cast<std::size_t>(u)];
        offer(u);
        continue;
      }
      around = ring_;
      collapse(u, v, now);
      for (int w : around) {
        ++stamp[static_cast<std::size_t>(w)];
        offer(w);
      }
    }
    SimplifiedTriangles out;
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      if (!alive_[t]) continue;
      float e = 0;
      for (int v : tris_[t]) {
        out.indices.push_back(verts_[static_cast<std::size_t>(v)].index);
        e = std::max(e, static_cast<float>(err_[static_cast<std::size_t>(v)]));
      }
      out.source.push_back(source_[t]);
      out.error.push_back(e);
      out.maxError = std::max(out.maxError, double(e));
    }
    return out;
  }

 private:
  static glm::dvec3 cross3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return glm::cross(b - a, c - a);
  }

  // Vertices stay where their fan is not a closed, consistently oriented disc
  // of these triangles, or where one of their triangles has no area
  // or their normal is zero.
  void lockBorders() {
    locked_.assign(verts_.size(), false);
    std::unordered_map<std::uint64_t, int> directed;  // (a << 32 | b) → uses
    for (const auto& t : tris_)
      for (int j = 0; j < 3; ++j) {
        const auto a = static_cast<std::uint64_t>(t[static_cast<std::size_t>(j)]);
        const auto b = static_cast<std::uint64_t>(t[static_cast<std::size_t>((j + 1) % 3)]);
        ++directed[a << 32 | b];
      }
    const auto uses = [&](int from, int to) {
      const auto it = directed.find(std::uint64_t(from) << 32 | std::uint64_t(to));
      return it == directed.end() ? 0 : it->second;
    };
    for (const auto& t : tris_) {
      const double area2 = glm::length(cross3(verts_[static_cast<std::size_t>(t[0])].p,
                                              verts_[static_cast<std::size_t>(t[1])].p,
                                              verts_[static_cast<std::size_t>(t[2])].p));
      for (int j = 0; j < 3; ++j) {
        const int a = t[static_cast<std::size_t>(j)], b = t[static_cast<std::size_t>((j + 1) % 3)];
        const int fwd = uses(a, b), back = uses(b, a);
        if (fwd != 1 || back != 1) {  // open, non-manifold or inconsistently oriented
          locked_[static_cast<std::size_t>(a)] = true;
          locked_[static_cast<std::size_t>(b)] = true;
        }
        if (!(area2 > eps_ * eps_)) locked_[static_cast<std::size_t>(a)] = true;
      }
    }
    for (std::size_t v = 0; v < verts_.size(); ++v) {
      if (verts_[v].n == glm::dvec3(0.0)) locked_[v] = true;
      if (locked_[v]) continue;
      // Every edge shared by exactly two triangles: a closed fan is a single
      // disc when it has as many triangles as neighbours.
      neighbours(static_cast<int>(v), ring_);
      if (ring_.size() != vtris_[v].size() || ring_.size() < 3) locked_[v] = true;
    }
  }

  // The vertices sharing a live triangle with v (sorted, unique).
  void neighbours(int v, std::vector<int>& out) const {
    out.clear();
    for (int t : vtris_[static_cast<std::size_t>(v)])
      for (int w : tris_[static_cast<std::size_t>(t)])
        if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  // Whether u's fan (ring_ = its neighbours) allows removing u at all: the
  // normals agree and the texture coordinates are affine over it.
  bool fanRemovable(int u) const {
    const Local& U = verts_[static_cast<std::size_t>(u)];
    // Shading: the normals u's triangles interpolate stay within normalCos.
    for (int w : ring_)
      if (glm::dot(U.n, verts_[static_cast<std::size_t>(w)].n) < opt_.normalCos) return false;
    // Texture coordinates: affine over u's fan (within uvTolerance), so that
    // any triangulation of the fan's outline maps the texture as before. The
    // map is the fan's largest triangle's, extended over its plane.
    int widest = -1;
    double widestArea = 0;
    for (int t : vtris_[static_cast<std::size_t>(u)]) {
      const auto& tri = tris_[static_cast<std::size_t>(t)];
      const double a = glm::length(cross3(verts_[static_cast<std::size_t>(tri[0])].p,
                                          verts_[static_cast<std::size_t>(tri[1])].p,
                                          verts_[static_cast<std::size_t>(tri[2])].p));
      if (a > widestArea) {
        widestArea = a;
        widest = t;
      }
    }
    if (widest < 0) return false;
    {
      const auto& tri = tris_[static_cast<std::size_t>(widest)];
      const Local& a = verts_[static_cast<std::size_t>(tri[0])];
      const Local& b = verts_[static_cast<std::size_t>(tri[1])];
      const Local& c = verts_[static_cast<std::size_t>(tri[2])];
      const glm::dvec3 n = glm::cross(b.p - a.p, c.p - a.p);
      const double n2 = glm::dot(n, n);
      const auto affine = [&](const Local& w) {
        const double wb = glm::dot(glm::cross(w.p - a.p, c.p - a.p), n) / n2;
        const double wc = glm::dot(glm::cross(b.p - a.p, w.p - a.p), n) / n2;
        const glm::dvec2 uv = a.uv + wb * (b.uv - a.uv) + wc * (c.uv - a.uv);
        return std::abs(uv.x - w.uv.x) <= opt_.uvTolerance &&
               std::abs(uv.y - w.uv.y) <= opt_.uvTolerance;
      };
      if (!affine(U)) return false;
      for (int w : ring_)
        if (!affine(verts_[static_cast<std::size_t>(w)])) return false;
    }
    return true;
  }

  // Whether u may merge into v; *error = v's error afterwards.
  bool canCollapse(int u, int v, double* error) {
    const Local& U = verts_[static_cast<std::size_t>(u)];
    const Local& V = verts_[static_cast<std::size_t>(v)];
    // Link condition: u and v share exactly the two vertices opposite their
    // edge, or the collapse would fold the surface.
    neighbours(v, ringV_);
    std::size_t common = 0;
    for (int w : ring_)
      if (std::binary_search(ringV_.begin(), ringV_.end(), w)) ++common;
    if (common != 2) return false;
    // v's fan afterwards: u's neighbours join it, u and v leave. A cap keeps
    // fans (and the work per collapse) bounded on large flat meshes, and
    // slivers fewer.
    if (ring_.size() + ringV_.size() - 4 > kMaxValence) return false;
    double moved = 0;   // v from the planes of u's triangles
    double missed = 0;  // u from the planes of the new triangles
    for (int t : vtris_[static_cast<std::size_t>(u)]) {
      const auto& tri = tris_[static_cast<std::size_t>(t)];
      std::array<glm::dvec3, 3> p{};
      bool hasV = false;
      for (std::size_t j = 0; j < 3; ++j) {
        p[j] = verts_[static_cast<std::size_t>(tri[j])].p;
        hasV = hasV || tri[j] == v;
      }
      const glm::dvec3 nOld = glm::cross(p[1] - p[0], p[2] - p[0]);
      const double lenOld = glm::length(nOld);
      moved = std::max(moved, std::abs(glm::dot(nOld, V.p - U.p)) / lenOld);
      if (hasV) continue;  // goes away with the collapse
      for (std::size_t j = 0; j < 3; ++j)
        if (tri[j] == u) p[j] = V.p;
      const glm::dvec3 nNew = glm::cross(p[1] - p[0], p[2] - p[0]);
      const double lenNew = glm::length(nNew);
      if (!(lenNew > eps_ * eps_) || glm::dot(nNew, nOld) <= 0) return false;  // flips
      missed = std::max(missed, std::abs(glm::dot(nNew / lenNew, U.p - p[0])));
    }
    double step = std::max(moved, missed);
    if (step <= eps_) step = 0;
    *error = std::max(err_[static_cast<std::size_t>(u)], err_[static_cast<std::size_t>(v)]) + step;
    return *error <= opt_.maxError;
  }

  void collapse(int u, int v, double error) {
    auto& fromU = vtris_[static_cast<std::size_t>(u)];
    for (int t : fromU) {
      auto& tri = tris_[static_cast<std::size_t>(t)];
      if (tri[0] == v || tri[1] == v || tri[2] == v) {
        alive_[static_cast<std::size_t>(t)] = false;
        for (int w : tri) {
          if (w == u) continue;
          auto& list = vtris_[static_cast<std::size_t>(w)];
          list.erase(std::remove(list.begin(), list.end(), t), list.end());
        }
        continue;
      }
      for (int& w : tri)
        if (w == u) w = v;
      vtris_[static_cast<std::size_t>(v)].push_back(t);
    }
    fromU.clear();
    err_[static_cast<std::size_t>(v)] = error;
  }

  static constexpr std::size_t kMaxValence = 64;
  SimplifyOptions opt_;
  double eps_ = 0;
  std::vector<Local> verts_;
  std::vector<std::array<int, 3>> tris_;
  std::vector<std::uint32_t> source_;  // each triangle's index in the mesh
  std::vector<bool> alive_;
  std::vector<std::vector<int>> vtris_;
  std::vector<bool> locked_;
  std::vector<double> err_;
  std::vector<int> ring_, ringV_;  // scratch
};

}  // namespace

SimplifiedTriangles simplifyTriangles(const Mesh& mesh, std::uint32_t firstTriangle,
                                      std::uint32_t triangleCount, const SimplifyOptions& options) {
  Simplifier s(mesh, firstTriangle, triangleCount, options);
  return s.run();
}

}  // namespace hw::scenes
