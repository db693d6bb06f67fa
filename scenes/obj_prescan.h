#pragma once
// What an OBJ file will ask of memory, counted from its text before Assimp
// reads it: Assimp's OBJ importer keeps every face as its own vectors and
// then one vertex per face corner, so memory grows with the face-vertex
// references, not with the file size (8 bytes of "f 1 2 3" cost ~200).
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace hw::scenes {

struct ObjCounts {
  std::uint64_t vertices = 0;    // "v" lines
  std::uint64_t faces = 0;       // "f" lines
  std::uint64_t references = 0;  // vertex references on "f" lines
  std::vector<std::string> mtllibs;  // "mtllib NAME" names as written (at most 16 kept)
};

// One pass over the file in 1 MiB blocks (no line is held whole).
Result<ObjCounts> countObjElements(const std::string& path);

// Bytes the import holds at its peak: 200 per face-vertex reference and 100
// per vertex (measured: a 1100² grid, 7.3 M references, peaked at 1.6 GB in
// a whole render run).
std::uint64_t objImportBytes(const ObjCounts& c);

}  // namespace hw::scenes
