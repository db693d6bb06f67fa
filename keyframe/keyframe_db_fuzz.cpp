// libFuzzer target for the keyframe database reader (docs/keyframe-db.md):
// any bytes must decode as a keyframe file or give an error naming the file,
// and any text must parse as index.json entries or give an error; never a
// crash, a hang or an allocation beyond what the input's size allows. A
// decoded keyframe must pass the reader's own promises: finite camera and
// quad corners inside the image, sizes matching the header.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/json_guard.h"
#include "keyframe/keyframe_db.h"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "keyframe_db_fuzz: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hw;
  using namespace hw::keyframe;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  CachedKeyframe out;
  const Status s = decodeKeyframe(bytes, "fuzz.hwkf", out);
  if (!s.ok()) {
    if (s.error().message.find("fuzz.hwkf") == std::string::npos) fail("error without the file name");
  } else {
    const Keyframe& k = out.keyframe;
    if (k.colour.width() != k.camera.width || k.colour.height() != k.camera.height ||
        out.mesh.width != k.camera.width || out.mesh.height != k.camera.height)
      fail("decoded sizes disagree");
    for (const Quad& q : out.mesh.quads)
      for (int c = 0; c < 4; ++c) {
        if (!std::isfinite(q.world[c].x) || !std::isfinite(q.eyeZ[c]) || !(q.eyeZ[c] > 0))
          fail("accepted a non-finite quad corner");
        if (q.pixel[c].x < -1 || q.pixel[c].x > k.camera.width + 1) fail("accepted a corner outside");
      }
  }
  // The same bytes as index.json text.
  auto j = parseJsonStrict(bytes, "fuzz.json");
  if (j.ok()) {
    auto entries = parseKeyframeEntries(j->is_object() && j->contains("keyframes")
                                            ? (*j)["keyframes"]
                                            : *j,
                                        "fuzz.json");
    if (entries.ok())
      for (const KeyframeDbEntry& e : *entries)
        if (e.frame < 0 || e.file.find('/') != std::string::npos) fail("accepted a bad entry");
    (void)indexChecksum(*j);
  }
  return 0;
}
