// libFuzzer target for the Quake 3 shader-script parser (scripts/*.shader in
// pk3s, scenes/q3bsp.h): any text must give shader definitions and at most
// one warning naming the script, never a crash or a hang.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "scenes/q3bsp.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto s = hw::scenes::summarizeQ3ShaderScript(text, "fuzz.shader");
  if (!s.warning.empty() && s.warning.find("fuzz.shader") == std::string::npos) {
    std::fprintf(stderr, "q3shader_fuzz: warning without the script name: %s\n", s.warning.c_str());
    std::abort();
  }
  if (s.shaders > size) std::abort();  // every shader needs at least a name and braces
  return 0;
}
