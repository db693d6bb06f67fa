#pragma once
// MORSE environments: Blender .blend files through Assimp, the SkyBox and
// collision boxes hidden.
#include <string>
#include <vector>

#include "core/result.h"
#include "scenes/scene.h"

namespace hw::scenes {

struct BlendOptions {
  // Nodes with these names are left out with all their children.
  std::vector<std::string> hiddenNodes{"SkyBox"};
  // Nodes whose names start with these lose their own meshes but keep their
  // children: MORSE's "BB_" objects are invisible collision boxes that
  // parent the visible tree (Tree.001 → BB_Trunk.001 → Plane-Tree.001).
  std::vector<std::string> hiddenNodePrefixes{"BB_"};
  bool zUp = true;                // Blender is Z-up: (x, y, z) → (x, z, −y)
  double chunkSizeMetres = 25.0;  // as Ac3dOptions::chunkSizeMetres
};

// A .blend through Assimp's Blender importer with node transforms applied
// and hidden nodes dropped. Blender procedural textures (Assimp names them
// "Procedural,...") cannot be evaluated: those materials use their diffuse
// colour. Embedded (packed) images are decoded; all materials are
// two-sided (Blender draws both sides by default). Never throws; Assimp's
// error text is quoted.
Result<Scene> loadBlendFile(const std::string& path, const BlendOptions& options = {});

}  // namespace hw::scenes
