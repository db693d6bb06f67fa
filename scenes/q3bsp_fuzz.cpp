// libFuzzer target for the Quake 3 BSP parser (scenes/q3bsp.h): any bytes
// must give a map or an error naming the source, never a crash, a hang or
// out-of-bounds geometry. Seed corpus: tests/fuzz/q3bsp/ (the unit test's
// minimal map and variants).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "scenes/q3bsp.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hw::scenes;
  Q3Options options;
  options.patchSubdivisions = 4;
  options.maxTriangles = 2'000'000;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  auto map = parseQ3Bsp(bytes, "fuzz.bsp", nullptr, options);
  if (!map.ok()) {
    if (map.error().message.find("fuzz.bsp") == std::string::npos) {
      std::fprintf(stderr, "error without the source name: %s\n", map.error().message.c_str());
      std::abort();
    }
    return 0;
  }
  for (const Mesh& m : map->scene.meshes) {
    if (m.material < 0 || static_cast<std::size_t>(m.material) >= map->scene.materials.size())
      std::abort();
    if (m.indices.size() % 3 != 0) std::abort();
    for (std::uint32_t i : m.indices)
      if (i >= m.vertices.size()) std::abort();
  }
  return 0;
}
