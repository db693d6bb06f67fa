// Scene clusters: every triangle in exactly one cluster, in each mesh's own
// order; bounds that hold exactly the cluster's vertices; the size and extent
// limits; compact clusters where the order is coherent; bad indices and
// degenerate options handled without a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "scenes/clusters.h"
#include "scenes/procedural.h"

namespace hw::scenes {
namespace {

// Checks coverage, order and bounds.
void expectPartition(const Scene& s, const std::vector<Cluster>& cs, const char* what) {
  std::size_t k = 0;
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    const Mesh& mesh = s.meshes[m];
    std::size_t next = 0;  // the next triangle a cluster must start at
    for (; k < cs.size() && cs[k].mesh == m; ++k) {
      const Cluster& c = cs[k];
      ASSERT_EQ(c.firstTriangle, next) << what << " mesh " << m << " cluster " << k;
      ASSERT_GE(c.triangleCount, 1u) << what;
      glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
      for (std::size_t t = c.firstTriangle; t < c.firstTriangle + c.triangleCount; ++t)
        for (int j = 0; j < 3; ++j) {
          const glm::vec3 p = mesh.vertices[mesh.indices[3 * t + static_cast<std::size_t>(j)]].position;
          lo = glm::min(lo, p);
          hi = glm::max(hi, p);
        }
      EXPECT_EQ(c.boundsMin, lo) << what << " cluster " << k;
      EXPECT_EQ(c.boundsMax, hi) << what << " cluster " << k;
      next += c.triangleCount;
    }
    EXPECT_EQ(next, mesh.triangleCount()) << what << " mesh " << m << ": triangles not covered";
  }
  EXPECT_EQ(k, cs.size()) << what << ": clusters out of mesh order";
}

float longest(const Cluster& c) {
  const glm::vec3 e = c.boundsMax - c.boundsMin;
  return std::max(e.x, std::max(e.y, e.z));
}

TEST(SceneClusters, PartitionTheProceduralScenesWithinTheLimits) {
  for (const Scene& s : {makeIndoorScene(20000), makeOutdoorScene(20000)}) {
    ClusterOptions o;
    const std::vector<Cluster> cs = clusterScene(s, o);
    expectPartition(s, cs, s.name.c_str());
    std::size_t tris = 0;
    for (const Cluster& c : cs) {
      tris += c.triangleCount;
      EXPECT_LE(c.triangleCount, o.maxTriangles) << s.name;
      if (c.triangleCount > o.minTriangles) {
        EXPECT_LE(longest(c), o.maxExtent) << s.name;
      }
    }
    EXPECT_EQ(tris, s.triangleCount()) << s.name;
    // Finer than the meshes, or culling by cluster gains nothing.
    EXPECT_GT(cs.size(), 4 * s.meshes.size()) << s.name;
  }
}

// Boxes 10 units apart appended one after another: where the order is
// coherent, no cluster spans two boxes.
TEST(SceneClusters, CoherentOrderGivesClustersThatDoNotSpanObjects) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh m;
  for (int b = 0; b < 40; ++b) {
    const glm::vec3 lo(10.0f * float(b % 8), 0.0f, 10.0f * float(b / 8));
    for (int j = 0; j < 8; ++j)  // 8 small boxes side by side make one object of 96 triangles
      appendBox(m, lo + glm::vec3(0.1f * float(j), 0, 0), lo + glm::vec3(0.1f * float(j + 1), 1, 1));
  }
  s.meshes.push_back(std::move(m));
  ClusterOptions o;
  o.maxTriangles = 512;
  o.minTriangles = 4;
  o.maxExtent = 2.0f;
  const std::vector<Cluster> cs = clusterScene(s, o);
  expectPartition(s, cs, "boxes");
  EXPECT_GE(cs.size(), 40u);
  for (const Cluster& c : cs) EXPECT_LE(longest(c), 1.0f + 1e-5f) << c.firstTriangle;
}

TEST(SceneClusters, LargeTrianglesStopAtMinTriangles) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh m;
  for (int k = 0; k < 100; ++k) {  // a strip of 100 triangles, each 50 units long
    const float x = 50.0f * float(k);
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({{x, 0, 0}});
    m.vertices.push_back({{x + 50, 0, 0}});
    m.vertices.push_back({{x, 0, 50}});
    m.indices.insert(m.indices.end(), {base, base + 2, base + 1});
  }
  s.meshes.push_back(std::move(m));
  ClusterOptions o;
  o.minTriangles = 16;
  const std::vector<Cluster> cs = clusterScene(s, o);
  expectPartition(s, cs, "strip");
  for (const Cluster& c : cs) {
    EXPECT_LE(c.triangleCount, 16u);
    EXPECT_GT(c.triangleCount, 16u / 2 / 2) << "cut far below minTriangles";
  }
}

TEST(SceneClusters, BadIndicesEmptyMeshesAndDegenerateOptions) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh empty;
  Mesh bad;
  bad.vertices.push_back({{1, 2, 3}});
  bad.vertices.push_back({{4, 5, 6}});
  bad.indices = {0, 1, 7, 9, 9, 9};  // one triangle with a bad index, one with none valid
  s.meshes.push_back(empty);
  s.meshes.push_back(bad);
  ClusterOptions o;
  o.maxTriangles = 0;
  o.minTriangles = 0;
  o.maxExtent = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Cluster> cs = clusterScene(s, o);
  ASSERT_EQ(cs.size(), 2u);  // one triangle per cluster, none for the empty mesh
  EXPECT_EQ(cs[0].mesh, 1u);
  EXPECT_EQ(cs[0].boundsMin, glm::vec3(1, 2, 3));
  EXPECT_EQ(cs[0].boundsMax, glm::vec3(4, 5, 6));
  EXPECT_EQ(cs[1].firstTriangle, 1u);
  EXPECT_EQ(cs[1].boundsMin, glm::vec3(0.0f));
  EXPECT_EQ(cs[1].boundsMax, glm::vec3(0.0f));
  EXPECT_TRUE(clusterScene(Scene{}).empty());
}

TEST(SceneClusters, BoxWithinIsTheEuclideanDistanceToTheBox) {
  const glm::vec3 lo(0, 0, 0), hi(1, 2, 3);
  EXPECT_TRUE(boxWithin(lo, hi, {0.5, 1, 1}, 1e-9));  // inside
  EXPECT_FALSE(boxWithin(lo, hi, {0.5, 1, 1}, 0.0));  // 0 is never near
  EXPECT_TRUE(boxWithin(lo, hi, {4, 6, 3}, 5.0 + 1e-9));  // corner (1,2,3): distance 5
  EXPECT_FALSE(boxWithin(lo, hi, {4, 6, 3}, 5.0));
  EXPECT_TRUE(boxWithin(lo, hi, {-2, 1, 1}, 2.0 + 1e-9));  // face: distance 2
  EXPECT_FALSE(boxWithin(lo, hi, {-2, 1, 1}, 2.0));
}

}  // namespace
}  // namespace hw::scenes
