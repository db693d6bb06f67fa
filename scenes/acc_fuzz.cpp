// libFuzzer target for the AC3D (.ac/.acc) parser (scenes/ac3d.h):
// any text must give a model or an error naming the source, never a crash, a
// hang or memory out of proportion to the input (declared counts allocate
// nothing by themselves). Accepted geometry has valid indices and materials.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scenes/ac3d.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hw::scenes;
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto m = parseAc3d(text, "fuzz.acc", "/nonexistent-folder");
  if (!m.ok()) {
    if (m.error().message.find("fuzz.acc") == std::string::npos) {
      std::fprintf(stderr, "acc_fuzz: error without the source name: %s\n",
                   m.error().message.c_str());
      std::abort();
    }
    return 0;
  }
  for (const hw::scenes::Mesh& mesh : m->scene.meshes) {
    if (mesh.indices.size() % 3 != 0) std::abort();
    for (std::uint32_t i : mesh.indices)
      if (i >= mesh.vertices.size()) std::abort();
    if (mesh.material < 0 || static_cast<std::size_t>(mesh.material) >= m->scene.materials.size())
      std::abort();
  }
  return 0;
}
