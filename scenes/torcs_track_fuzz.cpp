// libFuzzer target for the TORCS track description reader and centreline
// integration (scenes/torcs_track.h): any bytes must give a description (and
// a centreline or an error) or an error naming the source, never a crash, a
// hang or a non-finite point. Seed corpus: tests/fuzz/torcs_track/.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "scenes/torcs_track.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hw::scenes;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto d = parseTorcsTrackXml(text, "fuzz.xml");
  if (!d.ok()) {
    if (d.error().message.find("fuzz.xml") == std::string::npos) {
      std::fprintf(stderr, "error without the source name: %s\n", d.error().message.c_str());
      std::abort();
    }
    return 0;
  }
  TorcsCentrelineOptions o;
  o.sampleMetres = 5.0;
  o.closeMetres = 1e9;
  o.closeDegrees = 360;
  auto c = integrateTorcsCentreline(*d, o);
  if (!c.ok()) return 0;
  for (const auto& p : c->points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) std::abort();
  return 0;
}
