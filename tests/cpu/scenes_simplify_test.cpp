// Cluster simplification: a planar grid with affine texture coordinates
// loses its inner vertices at error 0 and covers the same area with the same
// texture mapping; borders, seams and curved surfaces stay unless the error
// budget allows; the error reported bounds how far the surface moved.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <glm/glm.hpp>

#include "scenes/procedural.h"
#include "scenes/simplify.h"

namespace hw::scenes {
namespace {

// An n×n grid of cells over [0, size]² in the plane y = height, normal +y,
// uv = (x, z) / 2 + offset (affine), counter-clockwise seen from above.
Mesh grid(int n, double size = 1.0, double height = 0.0) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      Vertex v;
      const double x = size * i / n, z = size * j / n;
      v.position = glm::vec3(float(x), float(height), float(z));
      v.normal = glm::vec3(0, 1, 0);
      v.uv = glm::vec2(float(x / 2 + 0.25), float(z / 2 + 3.0));
      m.vertices.push_back(v);
    }
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Seen from +y with x right and z down: (i,j) → (i,j+1) → (i+1,j) is counter-clockwise.
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
      m.indices.insert(m.indices.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
    }
  m.computeBounds();
  return m;
}

glm::dvec3 pos(const Mesh& m, std::uint32_t i) { return glm::dvec3(m.vertices[i].position); }

// Sum of the triangles' areas, signed by their normal's y.
double signedAreaY(const Mesh& m, const std::vector<std::uint32_t>& idx) {
  double a = 0;
  for (std::size_t t = 0; t + 2 < idx.size(); t += 3)
    a += 0.5 * glm::cross(pos(m, idx[t + 1]) - pos(m, idx[t]), pos(m, idx[t + 2]) - pos(m, idx[t])).y;
  return a;
}

// The uv the triangles interpolate at (x, z) of a y-plane mesh; false when no
// triangle holds the point.
bool uvAt(const Mesh& m, const std::vector<std::uint32_t>& idx, double x, double z,
          glm::dvec2* uv) {
  for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
    const glm::dvec3 a = pos(m, idx[t]), b = pos(m, idx[t + 1]), c = pos(m, idx[t + 2]);
    const auto e = [](glm::dvec3 p, glm::dvec3 q, double px, double pz) {
      return (q.x - p.x) * (pz - p.z) - (q.z - p.z) * (px - p.x);
    };
    const double area = e(a, b, c.x, c.z);
    const double w0 = e(b, c, x, z) / area, w1 = e(c, a, x, z) / area, w2 = e(a, b, x, z) / area;
    if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
    *uv = w0 * glm::dvec2(m.vertices[idx[t]].uv) + w1 * glm::dvec2(m.vertices[idx[t + 1]].uv) +
          w2 * glm::dvec2(m.vertices[idx[t + 2]].uv);
    return true;
  }
  return false;
}

std::set<std::uint32_t> used(const std::vector<std::uint32_t>& idx) {
  return std::set<std::uint32_t>(idx.begin(), idx.end());
}

TEST(Simplify, PlanarGridKeepsItsOutlineAreaAndTexture) {
  const int n = 12;
  const Mesh m = grid(n);
  const SimplifiedTriangles s = simplifyTriangles(m, 0, static_cast<std::uint32_t>(m.triangleCount()), {});
  EXPECT_EQ(s.maxError, 0.0);
  ASSERT_EQ(s.indices.size() % 3, 0u);
  // The 4n border vertices stay, and about none of the inner ones (a disc
  // of 4n vertices needs 4n − 2 triangles; an inner vertex whose fan no
  // neighbour sees whole cannot go by a half-edge collapse).
  const std::set<std::uint32_t> u = used(s.indices);
  int inner = 0;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      const bool kept = u.count(static_cast<std::uint32_t>(j * (n + 1) + i)) > 0;
      if (border) {
        EXPECT_TRUE(kept) << i << "," << j;
      }
      inner += !border && kept;
    }
  EXPECT_LE(inner, 2);
  EXPECT_EQ(s.indices.size() / 3, std::size_t(4 * n - 2 + 2 * inner));
  // Same area, every triangle facing the same way (no fold, no overlap).
  EXPECT_NEAR(signedAreaY(m, s.indices), signedAreaY(m, m.indices), 1e-6);
  for (std::size_t t = 0; t < s.indices.size(); t += 3) {
    const glm::dvec3 nrm = glm::cross(pos(m, s.indices[t + 1]) - pos(m, s.indices[t]),
                                      pos(m, s.indices[t + 2]) - pos(m, s.indices[t]));
    EXPECT_GT(nrm.y, 0) << "triangle " << t / 3 << " flipped or degenerate";
  }
  // The texture lands where it did.
  for (int k = 0; k < 200; ++k) {
    const double x = 0.003 + 0.994 * ((k * 37) % 101) / 100.0, z = 0.002 + 0.995 * ((k * 53) % 97) / 96.0;
    glm::dvec2 uv;
    ASSERT_TRUE(uvAt(m, s.indices, x, z, &uv)) << x << "," << z;
    EXPECT_NEAR(uv.x, x / 2 + 0.25, 1e-5);
    EXPECT_NEAR(uv.y, z / 2 + 3.0, 1e-5);
  }
}

TEST(Simplify, LargeFlatMeshKeepsFansBounded) {
  const int n = 200;
  const Mesh m = grid(n);
  const SimplifiedTriangles s = simplifyTriangles(m, 0, static_cast<std::uint32_t>(m.triangleCount()), {});
  // Nearly down to its border (4n vertices, 4n − 2 triangles), no vertex
  // with more than 64 neighbours (plus the two of its own border).
  EXPECT_LT(s.indices.size() / 3, std::size_t(4 * n + 4 * n / 4));
  std::vector<std::set<std::uint32_t>> around(m.vertices.size());
  for (std::size_t t = 0; t < s.indices.size(); t += 3)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        if (j != k) around[s.indices[t + j]].insert(s.indices[t + k]);
  std::size_t most = 0;
  for (const auto& a : around) most = std::max(most, a.size());
  EXPECT_LE(most, 66u);
  EXPECT_NEAR(signedAreaY(m, s.indices), signedAreaY(m, m.indices), 1e-6);
}

TEST(Simplify, TwoClustersOfOneGridKeepTheirSharedEdge) {
  const int n = 8;
  const Mesh m = grid(n);
  const auto half = static_cast<std::uint32_t>(m.triangleCount() / 2);  // rows 0..3 and 4..7
  const SimplifiedTriangles a = simplifyTriangles(m, 0, half, {});
  const SimplifiedTriangles b = simplifyTriangles(m, half, half, {});
  const std::set<std::uint32_t> ua = used(a.indices), ub = used(b.indices);
  for (int i = 0; i <= n; ++i) {
    const auto v = static_cast<std::uint32_t>(4 * (n + 1) + i);  // the shared row
    EXPECT_EQ(ua.count(v), 1u) << i;
    EXPECT_EQ(ub.count(v), 1u) << i;
  }
  EXPECT_LT(a.indices.size(), std::size_t(3 * half));
  EXPECT_NEAR(signedAreaY(m, a.indices) + signedAreaY(m, b.indices), signedAreaY(m, m.indices),
              1e-6);
}

TEST(Simplify, TextureSeamsAndNormalsStay) {
  const int n = 6;
  Mesh m = grid(n);
  // Texture coordinates that are not affine in the position: every inner
  // vertex must stay.
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    m.vertices[v].uv.x += float((v * v * 7 + v * 3) % 11) * 0.05f;
  const SimplifiedTriangles s = simplifyTriangles(m, 0, static_cast<std::uint32_t>(m.triangleCount()), {});
  EXPECT_EQ(s.indices.size(), m.indices.size());
  // Normals that differ (smooth shading across a crease that is not there).
  Mesh k = grid(n);
  for (std::size_t v = 0; v < k.vertices.size(); ++v)
    k.vertices[v].normal = glm::normalize(glm::vec3(float(v % 3) * 0.1f, 1.0f, 0.0f));
  const SimplifiedTriangles t = simplifyTriangles(k, 0, static_cast<std::uint32_t>(k.triangleCount()), {});
  EXPECT_EQ(t.indices.size(), k.indices.size());
}

// A grid bent into a cap of a sphere of this radius (curved both ways: no
// cell is planar), normals of the sphere.
Mesh cap(int n, double radius) {
  Mesh m = grid(n);
  for (auto& v : m.vertices) {
    const glm::dvec3 c(0.5, -radius, 0.5);
    const glm::dvec3 d = glm::normalize(glm::dvec3(v.position) - c);
    v.position = glm::vec3(c + radius * d);
    v.normal = glm::vec3(d);
  }
  return m;
}

// Distance from p to triangle abc.
double pointTriangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  const glm::dvec3 q = p - n * glm::dot(n, p - a);
  const auto inside = [&](glm::dvec3 x, glm::dvec3 y) { return glm::dot(glm::cross(y - x, q - x), n) >= 0; };
  if (inside(a, b) && inside(b, c) && inside(c, a)) return std::abs(glm::dot(n, p - a));
  const auto seg = [&](glm::dvec3 x, glm::dvec3 y) {
    const double t = std::clamp(glm::dot(p - x, y - x) / glm::dot(y - x, y - x), 0.0, 1.0);
    return glm::length(p - (x + t * (y - x)));
  };
  return std::min({seg(a, b), seg(b, c), seg(c, a)});
}

TEST(Simplify, CurvedSurfaceMovesNoMoreThanTheErrorItReports) {
  const Mesh m = cap(10, 2.0);
  const auto count = static_cast<std::uint32_t>(m.triangleCount());
  // At error 0 and the default normal tolerance nothing goes.
  EXPECT_EQ(simplifyTriangles(m, 0, count, {}).indices.size(), m.indices.size());
  SimplifyOptions loose;
  loose.maxError = 0.01;
  loose.normalCos = 0.9;
  loose.uvTolerance = 1.0;
  const SimplifiedTriangles s = simplifyTriangles(m, 0, count, loose);
  EXPECT_LT(s.indices.size(), m.indices.size());
  EXPECT_GT(s.maxError, 0.0);
  EXPECT_LE(s.maxError, loose.maxError);
  // Every original vertex lies within the reported error of the new surface.
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
    double d = 1e9;
    for (std::size_t t = 0; t < s.indices.size(); t += 3)
      d = std::min(d, pointTriangle(pos(m, v), pos(m, s.indices[t]), pos(m, s.indices[t + 1]),
                                    pos(m, s.indices[t + 2])));
    EXPECT_LE(d, s.maxError + 1e-6) << "vertex " << v;
  }
}

TEST(Simplify, DegenerateAndEmptyInput) {
  Mesh m = grid(2);
  m.indices.insert(m.indices.end(), {0, 0, 1});  // no area: dropped
  const auto count = static_cast<std::uint32_t>(m.triangleCount());
  const SimplifiedTriangles s = simplifyTriangles(m, 0, count, {});
  EXPECT_EQ(s.indices.size() % 3, 0u);
  for (std::size_t t = 0; t < s.indices.size(); t += 3)
    EXPECT_FALSE(s.indices[t] == s.indices[t + 1] && s.indices[t + 1] == s.indices[t + 2]);
  EXPECT_TRUE(simplifyTriangles(m, 0, 0, {}).indices.empty());
  // Every vertex at one point: nothing has area, nothing moves, nothing crashes.
  Mesh flat = grid(3);
  for (auto& v : flat.vertices) v.position = glm::vec3(1.0f);
  const SimplifiedTriangles f =
      simplifyTriangles(flat, 0, static_cast<std::uint32_t>(flat.triangleCount()), {});
  EXPECT_EQ(f.indices.size(), flat.indices.size());
}

TEST(Simplify, BuiltInIndoorSceneLosesMostOfItsTriangles) {
  // Mesh by mesh, as the renderer simplifies; the meshes' borders stay.
  const Scene s = makeIndoorScene(200'000);
  std::size_t before = 0, after = 0;
  for (const Mesh& m : s.meshes) {
    const auto count = static_cast<std::uint32_t>(m.triangleCount());
    const SimplifiedTriangles r = simplifyTriangles(m, 0, count, {});
    before += count;
    after += r.indices.size() / 3;
    EXPECT_EQ(r.maxError, 0.0) << m.name;
    ASSERT_EQ(r.source.size(), r.indices.size() / 3);
    ASSERT_EQ(r.error.size(), r.source.size());
    EXPECT_TRUE(std::is_sorted(r.source.begin(), r.source.end())) << m.name;
    EXPECT_TRUE(std::adjacent_find(r.source.begin(), r.source.end()) == r.source.end()) << m.name;
  }
  EXPECT_LT(after * 3, before) << before << " → " << after;
}

}  // namespace
}  // namespace hw::scenes
