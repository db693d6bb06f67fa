#include "scenes/scene.h"

#include <limits>

namespace hw::scenes {

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

}  // namespace hw::scenes
