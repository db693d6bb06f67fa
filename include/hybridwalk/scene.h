#pragma once
// Scenes of the hybridwalk library: triangle meshes with materials and
// textures, Y-up world, in the scene's own units. Load one by the command
// line's scene spec (`hybridwalk walk --scene`), or build one from your own
// meshes (SceneDesc; the data is copied).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hybridwalk/camera.h"
#include "hybridwalk/result.h"

namespace hybridwalk {

// One draw unit: indexed triangles of one material, counter-clockwise front
// faces (back faces are culled unless the material is two-sided).
struct MeshDesc {
  std::string name;
  std::vector<float> positions;        // x, y, z per vertex (scene units)
  std::vector<float> normals;          // x, y, z per vertex; empty = computed (smooth)
  std::vector<float> uvs;              // u, v per vertex, v = 0 at the texture's top; empty = 0
  std::vector<std::uint32_t> indices;  // 3 per triangle
  int material = 0;                    // index into SceneDesc::materials
};

struct MaterialDesc {
  std::string name;
  float baseColour[4] = {1, 1, 1, 1};  // linear 0..1; multiplies the texture
  int texture = -1;                    // index into SceneDesc::textures, or -1
  bool twoSided = false;               // draw back faces too
  bool unlit = false;                  // emissive: no shading (sky, lamps)
  bool alphaTest = false;              // discard where texture alpha < alphaCutoff
  float alphaCutoff = 0.5f;
};

struct TextureDesc {
  std::string name;
  int width = 0, height = 0;       // pixels, 1 … 16384
  std::vector<std::uint8_t> rgba;  // width·height·4 bytes, row 0 = top
};

struct SceneDesc {
  std::string name = "scene";
  std::vector<MeshDesc> meshes;         // at least one triangle in all
  std::vector<MaterialDesc> materials;  // empty = one white material
  std::vector<TextureDesc> textures;
  float skyColour[3] = {0.55f, 0.70f, 0.90f};  // where nothing is drawn, 0..1
};

class Scene {
 public:
  // `spec` as the command line's --scene: "indoor", "outdoor", "indoor:N" /
  // "outdoor:N" (N triangles, suffix k or M), "q3:MAP" / "torcs:TRACK" after
  // `hybridwalk scenes fetch`, or a model file (OBJ, glTF, PLY, COLLADA, …).
  // Errors name the file or spec and the reason.
  static Result<Scene> load(const std::string& spec);
  // Checks and copies `desc`. Errors: no triangles, index count not a
  // multiple of 3, an index past the vertices, positions/normals/uvs not 3/3/2
  // per vertex, a non-finite value, a material or texture index out of range,
  // texture data not width·height·4 bytes.
  static Result<Scene> build(const SceneDesc& desc);

  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  ~Scene();

  const std::string& name() const;
  std::size_t triangleCount() const;
  Vec3 boundsMin() const;
  Vec3 boundsMax() const;
  // Non-fatal load problems (e.g. a texture replaced by a checker).
  const std::vector<std::string>& warnings() const;
  // The path `hybridwalk walk` takes without --path: a loaded spec's own
  // default path, or for a built scene an orbit inside its bounds (512x512,
  // 120 frames, a keyframe every 10).
  Result<Path> defaultPath() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  explicit Scene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hybridwalk
