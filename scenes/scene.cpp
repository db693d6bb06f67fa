#include "scenes/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace hw::scenes {

std::size_t dropRepeatedTriangles(Mesh& mesh) {
  const std::size_t n = mesh.indices.size() / 3;
  if (n < 2) return 0;
  auto less = [](const glm::vec3& p, const glm::vec3& q) {
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
  };
  // Each triangle's corners from its least one on, winding kept.
  std::vector<std::array<glm::vec3, 3>> key(n);
  for (std::size_t t = 0; t < n; ++t) {
    std::array<glm::vec3, 3> c;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t i = mesh.indices[3 * t + k];
      c[k] = i < mesh.vertices.size() ? mesh.vertices[i].position : glm::vec3(0.0f);
    }
    std::size_t first = 0;
    for (std::size_t k = 1; k < 3; ++k)
      if (less(c[k], c[first])) first = k;
    key[t] = {c[first], c[(first + 1) % 3], c[(first + 2) % 3]};
  }
  auto keyLess = [&](std::size_t a, std::size_t b) {
    for (std::size_t k = 0; k < 3; ++k) {
      if (less(key[a][k], key[b][k])) return true;
      if (less(key[b][k], key[a][k])) return false;
    }
    return false;
  };
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), keyLess);  // equal keys: first one first
  std::vector<char> repeat(n, 0);
  for (std::size_t i = 1; i < n; ++i)
    if (!keyLess(order[i - 1], order[i])) repeat[order[i]] = 1;
  std::size_t kept = 0;
  for (std::size_t t = 0; t < n; ++t) {
    if (repeat[t]) continue;
    for (std::size_t k = 0; k < 3; ++k) mesh.indices[3 * kept + k] = mesh.indices[3 * t + k];
    ++kept;
  }
  mesh.indices.resize(3 * kept);
  return n - kept;
}

void Mesh::computeBounds() {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const Vertex& v : vertices) {
    lo = glm::min(lo, v.position);
    hi = glm::max(hi, v.position);
  }
  if (vertices.empty()) lo = hi = glm::vec3(0.0f);
  boundsMin = lo;
  boundsMax = hi;
}

std::size_t Scene::triangleCount() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangleCount();
  return n;
}

void Scene::computeBounds() {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  bool any = false;
  for (Mesh& m : meshes) {
    m.computeBounds();
    if (m.vertices.empty()) continue;
    lo = glm::min(lo, m.boundsMin);
    hi = glm::max(hi, m.boundsMax);
    any = true;
  }
  boundsMin = any ? lo : glm::vec3(0.0f);
  boundsMax = any ? hi : glm::vec3(0.0f);
}

Image<Rgba8> missingTexture() {
  Image<Rgba8> img(64, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      img(x, y) = ((x / 8 + y / 8) % 2) ? Rgba8{255, 0, 255, 255} : Rgba8{255, 255, 255, 255};
  return img;
}

void appendBox(Mesh& m, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const glm::vec3 c = 0.5f * (lo + hi), e = 0.5f * (hi - lo);
  for (const glm::vec3& n : normals) {
    const glm::vec3 a = std::abs(n.y) > 0.5f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    const glm::vec3 b = glm::cross(n, a);
    const glm::vec3 fc = c + n * glm::dot(glm::abs(n), e);
    const glm::vec3 ea = a * glm::dot(glm::abs(a), e), eb = b * glm::dot(glm::abs(b), e);
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    const glm::vec3 corners[4] = {fc - ea - eb, fc + ea - eb, fc + ea + eb, fc - ea + eb};
    const glm::vec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) m.vertices.push_back(Vertex{corners[k], n, uvs[k] * 2.0f});
    // (−a−b) → (a−b) → (a+b) turns counter-clockwise about n = a × b.
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
}

}  // namespace hw::scenes
