#pragma once
// What the AC3D and Blender readers share: triangles grouped into meshes per
// (material, ground cell), the degenerate-triangle test, texture lookup and
// decoding.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "core/result.h"
#include "scenes/scene.h"

namespace hw::scenes::detail {

std::string lower(std::string s);

// True when some texel is transparent (alpha < 128).
bool hasCutout(const Image<Rgba8>& img);

// SGI by our decoder, anything else through stb.
Result<Image<Rgba8>> decodeAnyImage(const std::string& bytes, const std::string& what);

// First file found: dir/name, dir/filename(name), then a case-insensitive
// file-name match in dir; for each dir in order.
std::optional<std::filesystem::path> findTexture(const std::vector<std::filesystem::path>& dirs,
                                                 std::string name);

// sin(smallest angle) below ~1e-6: zero area, or a needle no raster shows.
bool degenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

// Groups triangles into meshes per (material, ground cell). Vertices are
// given per batch (a surface, an Assimp mesh) by batch-local index and
// shared within a batch and mesh.
class ChunkBuilder {
 public:
  ChunkBuilder(Scene& scene, double cellSize) : scene_(scene), cell_(cellSize) {}

  void beginBatch() { remap_.clear(); }

  void addTriangle(int material, const std::vector<Vertex>& verts, std::uint32_t i0,
                   std::uint32_t i1, std::uint32_t i2) {
    const glm::vec3 c = (verts[i0].position + verts[i1].position + verts[i2].position) / 3.0f;
    int cx = 0, cz = 0;
    if (cell_ > 0) {
      cx = static_cast<int>(std::floor(std::clamp(c.x / cell_, -1e6, 1e6)));
      cz = static_cast<int>(std::floor(std::clamp(c.z / cell_, -1e6, 1e6)));
    }
    const auto key = std::make_tuple(material, cx, cz);
    auto it = meshOf_.find(key);
    if (it == meshOf_.end()) {
      Mesh m;
      m.material = material;
      m.name = scene_.materials[static_cast<std::size_t>(material)].name + "@" +
               std::to_string(cx) + "," + std::to_string(cz);
      scene_.meshes.push_back(std::move(m));
      it = meshOf_.emplace(key, scene_.meshes.size() - 1).first;
    }
    Mesh& mesh = scene_.meshes[it->second];
    for (std::uint32_t i : {i0, i1, i2}) {
      const std::uint64_t k = (static_cast<std::uint64_t>(it->second) << 32) | i;
      auto [r, inserted] = remap_.try_emplace(k, static_cast<std::uint32_t>(mesh.vertices.size()));
      if (inserted) mesh.vertices.push_back(verts[i]);
      mesh.indices.push_back(r->second);
    }
  }

 private:
  Scene& scene_;
  double cell_;
  std::map<std::tuple<int, int, int>, std::size_t> meshOf_;
  std::unordered_map<std::uint64_t, std::uint32_t> remap_;
};

}  // namespace hw::scenes::detail
