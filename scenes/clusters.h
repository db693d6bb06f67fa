#pragma once
// Scene clusters: every mesh's triangles cut into runs that are spatially
// compact, each with its bounds, so that the geometry renderer can cull by
// cluster and draw only the geometry near a viewpoint (Zheng et al. 1999 §3:
// near objects are drawn, not warped) at a cost that follows the near
// triangles rather than the size of the mesh they belong to.
//
// A cluster is a contiguous range of one mesh's triangles in the mesh's own
// order: drawing any set of clusters in order draws their triangles in the
// same order as drawing the whole mesh, so culling clusters that produce no
// fragment leaves the image bit for bit as it was (the depth test keeps the
// first of two fragments at equal depth, so the order matters).
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "scenes/scene.h"

namespace hw::scenes {

struct Cluster {
  std::uint32_t mesh = 0;           // index into Scene::meshes
  std::uint32_t firstTriangle = 0;  // into the mesh's triangles (Mesh::indices / 3)
  std::uint32_t triangleCount = 0;  // ≥ 1
  // Axis-aligned bounds of the cluster's triangles' vertices (scene units).
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
};

struct ClusterOptions {
  // A run is cut while it holds more than maxTriangles, or more than
  // minTriangles and its bounds' longest side exceeds maxExtent (scene
  // units). minTriangles keeps scenes of large triangles (terrain, roads)
  // from becoming one cluster per triangle.
  std::uint32_t maxTriangles = 512;
  std::uint32_t minTriangles = 64;
  float maxExtent = 1.0f;
};

// Cuts every mesh of `scene` into clusters: each mesh's triangle sequence is
// cut in two where the surface-area cost (bounds' area × triangles, summed
// over both sides) is least, within the middle three quarters of the run,
// and again until every run meets ClusterOptions (a bounding volume
// hierarchy built over the order instead of over space). Clusters are listed
// mesh by mesh, in triangle order, and cover every triangle exactly once;
// meshes without triangles have none. How compact the clusters are depends
// on how coherent the mesh's order is (every loader emits triangles surface
// by surface). Indices must be < the mesh's vertex count
// (GeometryRenderer::create checks); one that is not adds nothing to the
// bounds (a cluster with no valid index has the point bounds 0). A
// non-positive or non-finite maxExtent counts as 0; triangle limits below 1
// as 1.
std::vector<Cluster> clusterScene(const Scene& scene, const ClusterOptions& options = {});

// Whether the box [lo, hi] comes within `distance` of `point` (strictly:
// its squared distance to the box is below distance², so 0 is never near).
bool boxWithin(const glm::vec3& lo, const glm::vec3& hi, const glm::dvec3& point,
               double distance);

struct ClusterStats {
  std::size_t clusters = 0;
  double meanTriangles = 0;
  std::size_t maxTriangles = 0;
  double meanExtent = 0;  // mean longest side of the bounds
  std::size_t singletons = 0;  // clusters of one triangle
};
ClusterStats clusterStats(const std::vector<Cluster>& clusters);

}  // namespace hw::scenes
