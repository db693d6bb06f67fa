#include "scenes/clusters.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace hw::scenes {
namespace {

float longestSide(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 e = hi - lo;
  return std::max(e.x, std::max(e.y, e.z));
}

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
  bool valid() const { return lo.x <= hi.x; }
  void add(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const Box& add(const Box& b) {
    if (b.valid()) lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi);
    return *this;
  }
  float longestSide() const { return valid() ? hw::scenes::longestSide(lo, hi) : 0.0f; }
  double halfArea() const {
    if (!valid()) return 0;
    const glm::dvec3 e = glm::dvec3(hi) - glm::dvec3(lo);
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

}  // namespace

std::vector<Cluster> clusterScene(const Scene& scene, const ClusterOptions& options) {
  const std::uint32_t maxTris = std::max<std::uint32_t>(options.maxTriangles, 1);
  const std::uint32_t minTris = std::clamp<std::uint32_t>(options.minTriangles, 1, maxTris);
  const float maxExtent =
      std::isfinite(options.maxExtent) && options.maxExtent > 0 ? options.maxExtent : 0.0f;
  std::vector<Cluster> out;
  std::vector<Box> tri, prefix, suffix;
  std::vector<std::pair<std::size_t, std::size_t>> stack;  // ranges [a, b) still to cut
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const std::size_t tris = mesh.indices.size() / 3;
    if (tris == 0) continue;
    tri.assign(tris, Box{});
    for (std::size_t t = 0; t < tris; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t i = mesh.indices[3 * t + static_cast<std::size_t>(k)];
        if (i < mesh.vertices.size()) tri[t].add(mesh.vertices[i].position);
      }
    prefix.resize(tris);
    suffix.resize(tris + 1);
    stack.assign(1, {0, tris});
    while (!stack.empty()) {
      const auto [a, b] = stack.back();
      stack.pop_back();
      const std::size_t n = b - a;
      Box all;
      for (std::size_t t = a; t < b; ++t) all.add(tri[t]);
      if (n <= minTris || (n <= maxTris && !(all.longestSide() > maxExtent))) {
        Cluster c;
        c.mesh = static_cast<std::uint32_t>(m);
        c.firstTriangle = static_cast<std::uint32_t>(a);
        c.triangleCount = static_cast<std::uint32_t>(n);
        c.boundsMin = all.valid() ? all.lo : glm::vec3(0.0f);
        c.boundsMax = all.valid() ? all.hi : glm::vec3(0.0f);
        out.push_back(c);
        continue;
      }
      // The cut with the least surface-area cost (area × triangles on each
      // side), kept within the middle three quarters so that the depth of
      // the recursion stays logarithmic.
      Box acc;
      for (std::size_t t = a; t < b; ++t) prefix[t] = acc.add(tri[t]);
      acc = Box{};
      suffix[b] = acc;
      for (std::size_t t = b; t-- > a;) suffix[t] = acc.add(tri[t]);
      const std::size_t lo = a + std::max<std::size_t>(n / 8, 1), hi = b - std::max<std::size_t>(n / 8, 1);
      std::size_t best = a + n / 2;
      double bestCost = std::numeric_limits<double>::infinity();
      for (std::size_t p = lo; p <= hi; ++p) {
        const double cost = prefix[p - 1].halfArea() * double(p - a) + suffix[p].halfArea() * double(b - p);
        if (cost < bestCost) bestCost = cost, best = p;
      }
      // Right half first on the stack so that clusters come out in order.
      stack.push_back({best, b});
      stack.push_back({a, best});
    }
  }
  return out;
}

bool boxWithin(const glm::vec3& lo, const glm::vec3& hi, const glm::dvec3& point,
               double distance) {
  const glm::dvec3 d =
      glm::max(glm::max(glm::dvec3(lo) - point, point - glm::dvec3(hi)), glm::dvec3(0.0));
  return glm::dot(d, d) < distance * distance;
}

ClusterStats clusterStats(const std::vector<Cluster>& clusters) {
  ClusterStats s;
  s.clusters = clusters.size();
  double tris = 0, extent = 0;
  for (const Cluster& c : clusters) {
    tris += c.triangleCount;
    extent += longestSide(c.boundsMin, c.boundsMax);
    s.maxTriangles = std::max<std::size_t>(s.maxTriangles, c.triangleCount);
    s.singletons += c.triangleCount == 1;
  }
  if (!clusters.empty()) {
    s.meanTriangles = tris / double(clusters.size());
    s.meanExtent = extent / double(clusters.size());
  }
  return s;
}

}  // namespace hw::scenes
