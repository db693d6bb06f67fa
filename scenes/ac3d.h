#pragma once
// AC3D models (.ac/.acc, our own parser), as TORCS tracks use them.
// AC3D reference: Inivis, "AC3D file format" (ac3d.org/ac3d/man/ac3dfileformat.html);
// TORCS extensions as read by TORCS' grloadac.cpp (multi-layer `texture`
// lines, SURF type 4 = triangle strip, 6-number vertices with normals).
#include <cstddef>
#include <string>
#include <vector>

#include "core/result.h"
#include "scenes/scene.h"

namespace hw::scenes {

struct Ac3dOptions {
  // Folders searched for textures after the model's own folder, in order
  // (TORCS: data/textures, data/img of the install). loadTorcsTrack fills them.
  std::vector<std::string> textureDirs;
  // Triangles are grouped into meshes per (material, square cell of this
  // size on the ground plane), in the file's units (metres for TORCS), so
  // that frustum culling has something to cull. ≤ 0: one mesh per material.
  double chunkSizeMetres = 200.0;
  // Alpha cut-off of textures whose name contains "tree", "trans-" or
  // "arbor" (TORCS' own rule, grloadac.cpp); other textures with
  // transparent texels (alpha < 128) use Material::alphaCutoff's 0.5.
  float foliageAlphaCutoff = 0.65f;
};

struct Ac3dStats {
  std::size_t objects = 0;              // OBJECT blocks, all types
  std::size_t surfaces = 0;             // SURF records, all types
  std::size_t lineSurfaces = 0;         // types 1/2 (lines), skipped
  std::size_t twoSidedSurfaces = 0;     // SURF flag 0x20
  std::size_t multiLayerObjects = 0;    // objects naming more than the base texture layer
  std::size_t degenerateTriangles = 0;  // repeated index or zero area: dropped
  std::size_t missingTextures = 0;      // replaced by a checker (see Scene::warnings)
};

struct Ac3dModel {
  Scene scene;  // Y-up as AC3D is; counter-clockwise front faces; uv v = 0 at the image top
  Ac3dStats stats;
  // Per material: the base texture's file name as written in the file ("" for none).
  std::vector<std::string> materialTextureNames;
};

// Parses AC3D text (`source` names it in messages, `folder` is where its
// textures are looked for first). Object hierarchies are flattened with
// `loc` (parent frame) and `rot` (9 numbers, row i = image of axis i, as
// plib reads them). Of a TORCS object's texture layers only the base one
// (`texture NAME base`, or a plain `texture NAME`) is used; `tiled`,
// `skids` and `shad` layers are ignored, as are extra uv pairs in refs.
// Polygons are fans, type-4 surfaces strips; degenerate triangles are
// dropped. SURF flag 0x20 → Material::twoSided. Textures: PNG/JPG/TGA via
// stb, SGI .rgb/.rgba/.sgi/.bw by our own decoder; a missing or unreadable
// texture becomes a checker plus a warning. Errors (not AC3D, truncated
// blocks, out-of-range indices, malformed numbers, no triangles) give
// source:line and what was expected. Never throws.
Result<Ac3dModel> parseAc3d(const std::string& text, const std::string& source,
                            const std::string& folder, const Ac3dOptions& options = {});
Result<Ac3dModel> loadAc3dFile(const std::string& path, const Ac3dOptions& options = {});

}  // namespace hw::scenes
