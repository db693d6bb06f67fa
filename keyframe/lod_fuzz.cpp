// libFuzzer target for the LOD builder (Zheng et al. 1999 §1.2): random small
// depth buffers, coverage, τ and criterion. Aborts unless the leaves tile the
// valid pixels exactly once, leaves > 1 px are within τ, and every corner is
// finite with 0 < eyeZ.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "keyframe/lod_builder.h"

namespace {

using namespace hw;
using namespace hw::keyframe;

struct Reader {
  const std::uint8_t* p;
  size_t n;
  std::uint8_t byte() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
};

[[noreturn]] void fail(const char* what, int a, int b) {
  std::fprintf(stderr, "lod_fuzz: %s (%d, %d)\n", what, a, b);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  Reader in{data, size};
  const int w = 1 + in.byte() % 64, h = 1 + in.byte() % 64;
  const std::uint8_t flags = in.byte();
  const std::uint8_t tauMant = in.byte(), tauExp = in.byte();
  const std::uint8_t camByte = in.byte();

  LodOptions o;
  o.criterion = (flags & 1) ? DeltaCriterion::PerAxisMax : DeltaCriterion::FivePoint;
  o.tau = tauExp == 255 ? 0.0 : std::ldexp(1.0 + tauMant / 256.0, tauExp % 40 - 4);
  if (flags & 2) o.tauParallaxPx = std::ldexp(1.0 + tauMant / 256.0, tauExp % 16 - 12);

  const double nearPlane = std::ldexp(1.0, camByte % 8 - 4);                  // 1/16 … 8
  const double farPlane = nearPlane * std::ldexp(1.0, 1 + camByte / 8 % 20);  // ×2 … ×2^20
  const double fov = 0.2 + 2.8 * (flags >> 2) / 63.0;                         // (0, π)
  const Camera cam =
      Camera::lookAt({0.5, -1, 2}, {0.5, -1.3, 1}, {0, 1, 0}, fov, w, h, nearPlane, farPlane);

  // Depth: a plane with a few steps, plus noise and special values per pixel.
  Image<double> z(w, h);
  Image<std::uint8_t> cov(w, h);
  const double zInf = kZPrimeScale * farPlane / (farPlane - nearPlane);
  const double base = (in.byte() / 255.0) * zInf, gx = (in.byte() - 128) * 97.0,
               gy = (in.byte() - 128) * 131.0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint8_t a = in.byte(), b = in.byte();
      double v =
          base + gx * x + gy * y + (a & 0x30) * 4096.0 + (b - 128) * ((a & 0x40) ? 64.0 : 1.0);
      switch (a & 0x0f) {
        case 1:
          v = std::nan("");
          break;
        case 2:
          v = (b & 1 ? 1 : -1) * std::numeric_limits<double>::infinity();
          break;
        case 3:
          v = (b & 1 ? 1 : -1) * std::ldexp(1.0, b % 1024);
          break;
        case 4:
          v = zInf + b;
          break;
        default:
          break;
      }
      if (flags & 0x80) v = std::round(v);
      z(x, y) = v;
      cov(x, y) = (a & 0x80) ? 0 : 1;
    }
  }

  LodBuilder builder;
  QuadMesh mesh;
  const Status st = builder.build(z.view(), cov.view(), cam, o, &mesh);
  if (!st.ok()) {
    std::fprintf(stderr, "%s\n", st.error().message.c_str());
    fail("build failed on valid input", w, h);
  }

  Image<int> count(w, h, 0);
  const double tau = builder.tauZPrime();
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    if (!(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= w && r.y1 <= h && r.x0 < r.x1 && r.y0 < r.y1))
      fail("leaf outside the image", r.x0, r.y0);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) ++count(x, y);
    if (r.area() > 1 && !(q.maxDelta <= tau)) fail("leaf above tau", r.x0, r.y0);
    for (int i = 0; i < 4; ++i) {
      const glm::dvec3& p = q.world[i];
      if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        fail("non-finite corner", r.x0, r.y0);
      if (!(q.eyeZ[i] > 0.0 && std::isfinite(q.eyeZ[i]))) fail("bad corner depth", r.x0, r.y0);
    }
  }
  long long empty = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool valid = cov(x, y) != 0 && std::isfinite(z(x, y));
      empty += !valid;
      if (count(x, y) != (valid ? 1 : 0)) fail("tiling broken at pixel", x, y);
    }
  if (empty != mesh.stats.emptyPixels) fail("emptyPixels wrong", static_cast<int>(empty), 0);
  return 0;
}
