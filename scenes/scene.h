#pragma once
// Scene: triangle meshes with materials, Y-up world, in the scene's units.
// Built procedurally (procedural.h) or loaded from files (loader.h).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "core/memory_budget.h"

namespace hw::scenes {

struct Vertex {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec2 uv{0.0f};  // texture coordinates; v = 0 is the image's top row
};

struct Texture {
  std::string name;
  Image<Rgba8> image;  // row 0 = top
};

struct Material {
  std::string name;
  glm::vec4 baseColour{1.0f};  // multiplies the texture (linear 0..1, as stored in 8-bit)
  int texture = -1;            // index into Scene::textures, or -1
  bool alphaTest = false;      // cut-out: discard where texture alpha < alphaCutoff
  float alphaCutoff = 0.5f;
  bool twoSided = false;       // draw back faces too
  bool unlit = false;          // emissive (sky, lamps): no shading
  bool sky = false;            // a sky surface: a backdrop, not something to stand on or see
                               // through to (TriangleGrid leaves it out; views count it as sky)
};

// One draw unit: a single material, counter-clockwise front faces, indexed
// triangles. Procedural scenes split geometry into spatial chunks so that the
// renderer's frustum culling has something to cull.
struct Mesh {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices;  // 3 per triangle
  int material = 0;
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};

  std::size_t triangleCount() const { return indices.size() / 3; }
  void computeBounds();
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
  glm::vec3 skyColour{0.55f, 0.70f, 0.90f};  // clear colour where nothing is drawn
  std::vector<std::string> warnings;  // non-fatal load problems (e.g. a texture replaced)
  // What loading charged to the run's memory budget, given back with the scene.
  std::shared_ptr<MemoryReservation> memory;

  std::size_t triangleCount() const;
  void computeBounds();  // from the meshes' bounds (calls Mesh::computeBounds)
};

// Removes every triangle of `mesh` whose corners (positions, in the same
// cyclic order) repeat an earlier triangle's, keeping the first; returns how
// many went. Invisible for the opaque renderer (a repeat drawn later fails the
// depth test) but not free: 200000 copies of one face cost 200000 × its area
// in fill on every frame.
std::size_t dropRepeatedTriangles(Mesh& mesh);

// The texture used where a file's texture cannot be found: a magenta/white
// checker, 64×64, so the gap is visible (loaders also record a warning).
Image<Rgba8> missingTexture();

// Appends an axis-aligned box to `mesh`: outward normals, counter-clockwise
// seen from outside (one-sided faces are culled from inside), uv 0..2 per face.
void appendBox(Mesh& mesh, const glm::vec3& lo, const glm::vec3& hi);

}  // namespace hw::scenes
