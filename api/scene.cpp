// Public scenes: loaded by spec, or checked and copied from the caller's
// meshes, materials and textures.
#include "hybridwalk/scene.h"

#include <cmath>
#include <glm/glm.hpp>
#include <string>
#include <utility>

#include "api/internal.h"
#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"

namespace hybridwalk {
namespace {

std::string meshName(const MeshDesc& m, std::size_t i) {
  return "mesh " + std::to_string(i) + (m.name.empty() ? "" : " ('" + m.name + "')");
}

bool allFinite(const std::vector<float>& v) {
  for (float x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Smooth normals: area-weighted face normals summed per vertex.
void computeNormals(hw::scenes::Mesh& m) {
  std::vector<glm::vec3> n(m.vertices.size(), glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::vec3& a = m.vertices[m.indices[t]].position;
    const glm::vec3& b = m.vertices[m.indices[t + 1]].position;
    const glm::vec3& c = m.vertices[m.indices[t + 2]].position;
    const glm::vec3 f = glm::cross(b - a, c - a);
    for (int k = 0; k < 3; ++k) n[m.indices[t + static_cast<std::size_t>(k)]] += f;
  }
  for (std::size_t v = 0; v < n.size(); ++v) {
    const float l = glm::length(n[v]);
    m.vertices[v].normal = l > 0 ? n[v] / l : glm::vec3(0, 1, 0);
  }
}

}  // namespace

Scene::Scene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

Result<Scene> Scene::load(const std::string& spec) {
  auto s = hw::scenes::loadScene(spec);
  if (!s) return s.error();
  auto impl = std::make_unique<Impl>();
  impl->scene = std::move(*s);
  impl->spec = spec;
  return Scene(std::move(impl));
}

Result<Scene> Scene::build(const SceneDesc& desc) {
  auto impl = std::make_unique<Impl>();
  hw::scenes::Scene& s = impl->scene;
  s.name = desc.name;
  s.skyColour = {desc.skyColour[0], desc.skyColour[1], desc.skyColour[2]};
  for (float c : desc.skyColour)
    if (!(c >= 0 && c <= 1)) return hw::makeError("scene: skyColour: expected values in 0..1");
  for (std::size_t i = 0; i < desc.textures.size(); ++i) {
    const TextureDesc& t = desc.textures[i];
    const std::string what = "texture " + std::to_string(i);
    if (t.width < 1 || t.height < 1 || t.width > 16384 || t.height > 16384)
      return hw::makeError(what + ": size: expected 1 ... 16384 pixels each way, got " +
                           std::to_string(t.width) + "x" + std::to_string(t.height));
    const std::size_t want =
        static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height) * 4;
    if (t.rgba.size() != want)
      return hw::makeError(what + ": expected width*height*4 = " + std::to_string(want) +
                           " bytes of RGBA, got " + std::to_string(t.rgba.size()));
    hw::scenes::Texture tex;
    tex.name = t.name;
    tex.image.resize(t.width, t.height);
    for (std::size_t p = 0; p < want / 4; ++p)
      tex.image.data()[p] =
          hw::Rgba8{t.rgba[4 * p], t.rgba[4 * p + 1], t.rgba[4 * p + 2], t.rgba[4 * p + 3]};
    s.textures.push_back(std::move(tex));
  }
  if (desc.materials.empty()) s.materials.push_back(hw::scenes::Material{"default"});
  for (std::size_t i = 0; i < desc.materials.size(); ++i) {
    const MaterialDesc& m = desc.materials[i];
    const std::string what = "material " + std::to_string(i);
    if (m.texture < -1 || m.texture >= static_cast<int>(desc.textures.size()))
      return hw::makeError(what + ": texture " + std::to_string(m.texture) +
                           ": expected -1 or 0 ... " +
                           std::to_string(static_cast<int>(desc.textures.size()) - 1));
    for (float c : m.baseColour)
      if (!(c >= 0 && c <= 1)) return hw::makeError(what + ": baseColour: expected values in 0..1");
    hw::scenes::Material mat;
    mat.name = m.name;
    mat.baseColour = {m.baseColour[0], m.baseColour[1], m.baseColour[2], m.baseColour[3]};
    mat.texture = m.texture;
    mat.twoSided = m.twoSided;
    mat.unlit = m.unlit;
    mat.alphaTest = m.alphaTest;
    mat.alphaCutoff = m.alphaCutoff;
    s.materials.push_back(std::move(mat));
  }
  std::size_t triangles = 0;
  for (std::size_t i = 0; i < desc.meshes.size(); ++i) {
    const MeshDesc& m = desc.meshes[i];
    const std::string what = meshName(m, i);
    if (m.positions.size() % 3 != 0)
      return hw::makeError(what + ": positions: expected 3 floats per vertex, got " +
                           std::to_string(m.positions.size()) + " floats");
    const std::size_t nv = m.positions.size() / 3;
    if (!m.normals.empty() && m.normals.size() != 3 * nv)
      return hw::makeError(what + ": normals: expected 3 floats per vertex (" +
                           std::to_string(3 * nv) + ") or none, got " +
                           std::to_string(m.normals.size()));
    if (!m.uvs.empty() && m.uvs.size() != 2 * nv)
      return hw::makeError(what + ": uvs: expected 2 floats per vertex (" + std::to_string(2 * nv) +
                           ") or none, got " + std::to_string(m.uvs.size()));
    if (!allFinite(m.positions) || !allFinite(m.normals) || !allFinite(m.uvs))
      return hw::makeError(what + ": a position, normal or uv is not finite");
    if (m.indices.size() % 3 != 0)
      return hw::makeError(what + ": indices: expected 3 per triangle, got " +
                           std::to_string(m.indices.size()));
    for (std::size_t k = 0; k < m.indices.size(); ++k)
      if (m.indices[k] >= nv)
        return hw::makeError(what + ": index " + std::to_string(k) + " is " +
                             std::to_string(m.indices[k]) + ", past the " + std::to_string(nv) +
                             " vertices");
    if (m.material < 0 || m.material >= static_cast<int>(s.materials.size()))
      return hw::makeError(what + ": material " + std::to_string(m.material) + ": expected 0 ... " +
                           std::to_string(static_cast<int>(s.materials.size()) - 1));
    hw::scenes::Mesh mesh;
    mesh.name = m.name;
    mesh.material = m.material;
    mesh.indices = m.indices;
    mesh.vertices.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      auto& vx = mesh.vertices[v];
      vx.position = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
      if (!m.normals.empty()) {
        const glm::vec3 n{m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]};
        vx.normal = glm::length(n) > 0 ? glm::normalize(n) : glm::vec3(0, 1, 0);
      }
      if (!m.uvs.empty()) vx.uv = {m.uvs[2 * v], m.uvs[2 * v + 1]};
    }
    if (m.normals.empty()) computeNormals(mesh);
    triangles += mesh.triangleCount();
    s.meshes.push_back(std::move(mesh));
  }
  if (triangles == 0) return hw::makeError("scene '" + desc.name + "': no triangles");
  s.computeBounds();
  return Scene(std::move(impl));
}

const std::string& Scene::name() const { return impl_->scene.name; }
std::size_t Scene::triangleCount() const { return impl_->scene.triangleCount(); }
Vec3 Scene::boundsMin() const {
  const glm::vec3& b = impl_->scene.boundsMin;
  return {b.x, b.y, b.z};
}
Vec3 Scene::boundsMax() const {
  const glm::vec3& b = impl_->scene.boundsMax;
  return {b.x, b.y, b.z};
}
const std::vector<std::string>& Scene::warnings() const { return impl_->scene.warnings; }

Result<Path> Scene::defaultPath() const {
  hw::scenes::CameraPath p;
  if (!impl_->spec.empty()) {
    auto r = hw::scenes::defaultPathFor(impl_->spec);
    if (!r) return r.error();
    p = std::move(*r);
  } else {
    p = hw::scenes::flythroughPathFor(impl_->scene);
  }
  Path out;
  out.keyframeEvery = p.keyframeEvery;
  for (const hw::Camera& c : p.cameras()) out.cameras.push_back(detail::fromInternal(c));
  return out;
}

}  // namespace hybridwalk
