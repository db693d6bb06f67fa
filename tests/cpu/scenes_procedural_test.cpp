// Procedural scenes: the triangle-count knob, mesh validity (normals, winding,
// indices, chunking), determinism, look invariance, and default paths that
// stay clear of geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "scenes/procedural.h"

namespace hw::scenes {
namespace {

using SceneFn = Scene (*)(std::size_t);

struct Named {
  const char* name;
  SceneFn make;
};
const Named kScenes[] = {{"indoor", makeIndoorScene}, {"outdoor", makeOutdoorScene}};

void expectValid(const Scene& s, const char* what) {
  ASSERT_FALSE(s.meshes.empty()) << what;
  for (const Texture& t : s.textures) {
    EXPECT_EQ(t.image.width(), 256) << what << " " << t.name;
    EXPECT_EQ(t.image.height(), 256) << what << " " << t.name;
  }
  for (const Material& m : s.materials)
    EXPECT_LT(m.texture, static_cast<int>(s.textures.size())) << what;
  std::size_t badNormals = 0, badIndices = 0, badWinding = 0, badUv = 0;
  for (const Mesh& m : s.meshes) {
    ASSERT_GE(m.material, 0);
    ASSERT_LT(m.material, static_cast<int>(s.materials.size()));
    ASSERT_EQ(m.indices.size() % 3, 0u);
    for (const Vertex& v : m.vertices) {
      const float len = glm::length(v.normal);
      if (!std::isfinite(len) || std::abs(len - 1.0f) > 1e-4f) ++badNormals;
      if (!std::isfinite(v.uv.x) || !std::isfinite(v.uv.y)) ++badUv;
    }
    for (std::uint32_t i : m.indices)
      if (i >= m.vertices.size()) ++badIndices;
    if (badIndices) continue;
    // Counter-clockwise front faces: the geometric normal agrees with the
    // vertex normals (outward).
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const Vertex &a = m.vertices[m.indices[t]], &b = m.vertices[m.indices[t + 1]],
                   &c = m.vertices[m.indices[t + 2]];
      const glm::vec3 g = glm::cross(b.position - a.position, c.position - a.position);
      if (glm::length(g) < 1e-9f) continue;
      if (glm::dot(g, a.normal + b.normal + c.normal) <= 0) ++badWinding;
    }
  }
  EXPECT_EQ(badNormals, 0u) << what;
  EXPECT_EQ(badIndices, 0u) << what;
  EXPECT_EQ(badWinding, 0u) << what;
  EXPECT_EQ(badUv, 0u) << what;
}

TEST(Procedural, TriangleCountFollowsTheKnob) {
  for (const Named& n : kScenes)
    for (std::size_t target : {10'000u, 100'000u, 1'000'000u}) {
      const Scene s = n.make(target);
      const double ratio = static_cast<double>(s.triangleCount()) / static_cast<double>(target);
      EXPECT_GT(ratio, 0.85) << n.name << " target " << target << " got " << s.triangleCount();
      EXPECT_LT(ratio, 1.15) << n.name << " target " << target << " got " << s.triangleCount();
    }
}

TEST(Procedural, MeshesAreValidAndChunked) {
  for (const Named& n : kScenes)
    for (std::size_t target : {10'000u, 1'000'000u}) {
      const Scene s = n.make(target);
      const std::string what = std::string(n.name) + ":" + std::to_string(target);
      expectValid(s, what.c_str());
      std::size_t biggest = 0;
      for (const Mesh& m : s.meshes) biggest = std::max(biggest, m.triangleCount());
      EXPECT_LE(biggest, 40'000u) << what;
      EXPECT_GE(s.meshes.size(), target >= 1'000'000u ? 50u : 5u) << what;
      EXPECT_LE(s.meshes.size(), 3000u) << what;
    }
}

TEST(Procedural, BoundsAreSane) {
  const Scene in = makeIndoorScene(10'000);
  EXPECT_NEAR(in.boundsMin.y, 0.0f, 1e-4f);
  EXPECT_NEAR(in.boundsMax.y, 3.0f, 1e-4f);
  const glm::vec3 ie = in.boundsMax - in.boundsMin;
  EXPECT_GT(ie.x, 20.0f);
  EXPECT_LT(ie.x, 40.0f);
  EXPECT_GT(ie.z, 20.0f);
  EXPECT_LT(ie.z, 40.0f);
  const Scene out = makeOutdoorScene(10'000);
  const glm::vec3 oe = out.boundsMax - out.boundsMin;
  EXPECT_NEAR(oe.x, 320.0f, 1.0f);
  EXPECT_NEAR(oe.z, 320.0f, 1.0f);
  EXPECT_GT(oe.y, 10.0f);
  EXPECT_LT(oe.y, 80.0f);
  for (const Mesh& m : out.meshes) {
    EXPECT_LE(m.boundsMin.x, m.boundsMax.x);
    EXPECT_GE(m.boundsMin.x, out.boundsMin.x);
  }
}

TEST(Procedural, IsDeterministic) {
  for (const Named& n : kScenes) {
    const Scene a = n.make(50'000), b = n.make(50'000);
    ASSERT_EQ(a.meshes.size(), b.meshes.size()) << n.name;
    for (std::size_t i = 0; i < a.meshes.size(); ++i) {
      ASSERT_EQ(a.meshes[i].vertices.size(), b.meshes[i].vertices.size());
      ASSERT_EQ(a.meshes[i].indices, b.meshes[i].indices);
      EXPECT_EQ(std::memcmp(a.meshes[i].vertices.data(), b.meshes[i].vertices.data(),
                            a.meshes[i].vertices.size() * sizeof(Vertex)),
                0);
    }
    ASSERT_EQ(a.textures.size(), b.textures.size());
    for (std::size_t i = 0; i < a.textures.size(); ++i)
      EXPECT_EQ(a.textures[i].image.pixels(), b.textures[i].image.pixels());
  }
}

double area(const Mesh& m) {
  double sum = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const glm::dvec3 a(m.vertices[m.indices[t]].position), b(m.vertices[m.indices[t + 1]].position),
        c(m.vertices[m.indices[t + 2]].position);
    sum += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return sum;
}

// The knob refines tessellation only: every material covers the same area
// (curved surfaces converge to theirs) and the bounds do not move.
TEST(Procedural, LookDoesNotDependOnTriangleCount) {
  for (const Named& n : kScenes) {
    const Scene lo = n.make(10'000), hi = n.make(1'000'000);
    std::map<int, double> aLo, aHi;
    for (const Mesh& m : lo.meshes) aLo[m.material] += area(m);
    for (const Mesh& m : hi.meshes) aHi[m.material] += area(m);
    ASSERT_EQ(aLo.size(), aHi.size()) << n.name;
    for (const auto& [mat, a] : aHi)
      EXPECT_NEAR(aLo[mat] / a, 1.0, 0.12)
          << n.name << " material " << lo.materials[static_cast<std::size_t>(mat)].name;
    EXPECT_LT(glm::length(lo.boundsMin - hi.boundsMin), 0.6f) << n.name;
    EXPECT_LT(glm::length(lo.boundsMax - hi.boundsMax), 0.6f) << n.name;
  }
}

TEST(Procedural, OutdoorHasAlphaTestedTwoSidedLeaves) {
  const Scene s = makeOutdoorScene(10'000);
  bool found = false;
  for (const Material& m : s.materials)
    if (m.alphaTest && m.twoSided && m.texture >= 0) {
      found = true;
      const auto& px = s.textures[static_cast<std::size_t>(m.texture)].image.pixels();
      const auto clear =
          std::count_if(px.begin(), px.end(), [](const Rgba8& p) { return p.a == 0; });
      EXPECT_GT(clear, static_cast<long>(px.size() / 5));
      EXPECT_LT(clear, static_cast<long>(px.size() * 4 / 5));
    }
  EXPECT_TRUE(found);
}

// --- Path clearance -----------------------------------------------------------

double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c) {
  // Ericson, Real-Time Collision Detection §5.1.5.
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = 1.0 / (va + vb + vc);
  return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// Smallest distance from any sampled eye to any triangle of the scene.
double pathClearance(const Scene& s, const CameraPath& path, glm::dvec3* where) {
  double best = 1e30;
  for (int i = 0; i < path.frames; ++i) {
    const glm::dvec3 e = path.cameraAt(i).eye;
    for (const Mesh& m : s.meshes) {
      if (e.x < m.boundsMin.x - best || e.x > m.boundsMax.x + best || e.y < m.boundsMin.y - best ||
          e.y > m.boundsMax.y + best || e.z < m.boundsMin.z - best || e.z > m.boundsMax.z + best)
        continue;
      for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const double d = pointTriangleDistance(e, glm::dvec3(m.vertices[m.indices[t]].position),
                                               glm::dvec3(m.vertices[m.indices[t + 1]].position),
                                               glm::dvec3(m.vertices[m.indices[t + 2]].position));
        if (d < best) {
          best = d;
          *where = e;
        }
      }
    }
  }
  return best;
}

TEST(Procedural, IndoorWalkStaysClearOfWallsAndFurniture) {
  const Scene s = makeIndoorScene(10'000);
  CameraPath p = defaultIndoorPath();
  EXPECT_EQ(p.width, 512);
  EXPECT_EQ(p.frames, 120);
  EXPECT_EQ(p.keyframeEvery, 10);
  // Dense sampling (2 cm steps) so that nothing is stepped over.
  p.frames = 2000;
  glm::dvec3 where(0.0);
  const double clearance = pathClearance(s, p, &where);
  EXPECT_GT(clearance, 0.25) << "closest at " << where.x << ", " << where.y << ", " << where.z;
  for (int i = 0; i < p.frames; ++i) EXPECT_NEAR(p.cameraAt(i).eye.y, 1.7, 1e-9);
  const glm::dvec3 first = p.cameraAt(0).eye, last = p.cameraAt(p.frames - 1).eye;
  EXPECT_LT(first.z, -1.5);  // starts in a room south of the corridor
  EXPECT_GT(last.x, 24.0);   // ends in the hall
}

TEST(Procedural, OutdoorDriveStaysAboveTerrainAndClear) {
  const Scene s = makeOutdoorScene(10'000);
  CameraPath p = defaultOutdoorPath();
  EXPECT_EQ(p.frames, 120);
  p.frames = 1500;
  for (int i = 0; i < p.frames; ++i) {
    const glm::dvec3 e = p.cameraAt(i).eye;
    const double above = e.y - outdoorTerrainHeight(e.x, e.z);
    EXPECT_GT(above, 2.5) << "frame " << i;
    EXPECT_LT(above, 8.0) << "frame " << i;
  }
  glm::dvec3 where(0.0);
  EXPECT_GT(pathClearance(s, p, &where), 2.0)
      << "closest at " << where.x << ", " << where.y << ", " << where.z;
}

TEST(Procedural, DefaultPathsRoundTrip) {
  for (const CameraPath& p : {defaultIndoorPath(), defaultOutdoorPath()}) {
    auto q = parseCameraPath(cameraPathToJson(p), "default.json");
    ASSERT_TRUE(q.ok()) << q.error().message;
    EXPECT_EQ(q->keys.size(), p.keys.size());
  }
}

}  // namespace
}  // namespace hw::scenes
