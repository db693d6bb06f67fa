// libFuzzer target for the camera-path parser (DESIGN.md "Camera path"):
// arbitrary bytes must give a path or an error, never a crash or a hang; an
// accepted path must yield finite cameras with an orthonormal frame, and
// serialise to JSON that parses back to the same cameras.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scenes/camera_path.h"

namespace {

[[noreturn]] void fail(const char* what, int frame) {
  std::fprintf(stderr, "camera_path_fuzz: %s at frame %d\n", what, frame);
  std::abort();
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto p = hw::scenes::parseCameraPath(text, "fuzz.json");
  if (!p) {
    if (p.error().message.empty()) fail("empty error message", -1);
    return 0;
  }
  if (p->frames > 100000) return 0;  // valid but too slow to sample here
  const int step = std::max(1, p->frames / 16);
  for (int i = 0; i < p->frames; i += step) {
    const hw::Camera c = p->cameraAt(i);
    if (!finite(c.eye) || !finite(c.forward) || !finite(c.right) || !finite(c.up)) fail("non-finite camera", i);
    if (std::abs(glm::length(c.forward) - 1) > 1e-6 || std::abs(glm::dot(c.forward, c.up)) > 1e-6 ||
        std::abs(glm::dot(c.forward, c.right)) > 1e-6)
      fail("camera frame not orthonormal", i);
  }
  auto again = hw::scenes::parseCameraPath(hw::scenes::cameraPathToJson(*p), "roundtrip.json");
  if (!again) fail("serialised path does not parse back", -1);
  const hw::Camera a = p->cameraAt(p->frames - 1), b = again->cameraAt(again->frames - 1);
  if (glm::length(a.eye - b.eye) > 1e-6 * (1 + glm::length(a.eye))) fail("round trip moved the camera", p->frames - 1);
  return 0;
}
