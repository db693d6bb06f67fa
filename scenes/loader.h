#pragma once
// Scene files through Assimp (OBJ, glTF, PLY, COLLADA, 3DS, FBX, …) and the
// scene "spec" strings of the command line: built-in names or a file path.
#include <string>
#include <vector>

#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/default_paths.h"
#include "scenes/scene.h"

namespace hw::scenes {

// Process-wide default of LoadOptions::allowExternalRefs (the command line's
// --allow-external-refs). Off unless set.
void setExternalRefsAllowed(bool allowed);
bool externalRefsAllowed();

struct LoadOptions {
  // Force a Z-up → Y-up conversion ((x, y, z) → (x, z, −y)). When false, the
  // file's own "UpAxis"/"UpAxisSign" metadata (FBX and others) decides.
  bool zUp = false;
  // Meshes with more triangles than this are split into spatial chunks so
  // that frustum culling has something to cull; 0 disables splitting.
  std::size_t maxTrianglesPerMesh = 20'000;
  // Files the model names (glTF buffers and images, OBJ mtllib, textures) must
  // lie in the model's folder tree unless this is set (--allow-external-refs;
  // default: externalRefsAllowed()).
  bool allowExternalRefs = externalRefsAllowed();
};

// Loads a model into a Y-up Scene: triangulated, node transforms applied
// (world space), smooth normals generated where missing, uv with v = 0 at the
// texture's top row. Materials carry the diffuse colour and diffuse texture
// (external PNG/JPG/TGA/BMP relative to the model's folder, or embedded);
// texture alpha enables alphaTest; AI_MATKEY_TWOSIDED sets twoSided. A texture
// that cannot be loaded is replaced by a magenta/white checker and reported
// in Scene::warnings. Errors (missing, empty, unsupported, corrupt file, or no
// triangles) name the file and the reason. Never throws.
Result<Scene> loadSceneFile(const std::string& path, const LoadOptions& options = {});

// `spec`: "indoor", "outdoor", "indoor:N", "outdoor:N" (N target triangles,
// optional suffix k or M, e.g. "outdoor:1M"; default 100k), or a path to a
// model file. An existing file always wins over a built-in name.
Result<Scene> loadScene(const std::string& spec);

// Default camera path for a spec: the built-in walks for "indoor"/"outdoor",
// q3 maps through their spawns, TORCS tracks along their centreline, MORSE
// terrains on foot; a model file is walked over its floor at eye height
// (loads the file; scenes/floor_walk.h), or, where no floor is found,
// orbited (flythroughPathFor) with a note saying so.
// `notes` (may be null) receives what the path had to fall back on, for the
// user (e.g. a TORCS track without its description).
Result<CameraPath> defaultPathFor(const std::string& spec);
Result<CameraPath> defaultPathFor(const std::string& spec, const DefaultPathOptions& options,
                                  std::vector<std::string>* notes);

}  // namespace hw::scenes
