#include "core/depth.h"

#include <cmath>
#include <cstring>

namespace hw {

void convertDepth(const void* raw, int width, int height, DepthMode mode, double n, double f,
                  Image<double>& zPrime, Image<float>& eyeZ, Image<std::uint8_t>& covered) {
  if (zPrime.width() != width || zPrime.height() != height) zPrime.resize(width, height);
  if (eyeZ.width() != width || eyeZ.height() != height) eyeZ.resize(width, height);
  if (covered.width() != width || covered.height() != height) covered.resize(width, height);
  for (int gy = 0; gy < height; ++gy) {
    const int y = height - 1 - gy;
    double* zp = &zPrime(0, y);
    float* ez = &eyeZ(0, y);
    std::uint8_t* cv = &covered(0, y);
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(gy) * width + x;
      double z = 0.0, zpv = kZPrimeScale;
      bool empty = true;
      if (mode == DepthMode::Fixed24) {
        std::uint32_t v;
        std::memcpy(&v, static_cast<const std::uint32_t*>(raw) + i, sizeof v);
        const std::uint32_t d24 = v >> 8;
        if (d24 < 0xFFFFFFu) {
          empty = false;
          zpv = static_cast<double>(d24);
          z = eyeZFromZPrime(zpv, n, f);
        }
      } else {
        float d;
        std::memcpy(&d, static_cast<const float*>(raw) + i, sizeof d);
        if (mode == DepthMode::Float32) {
          if (std::isfinite(d) && d < 1.0f && d >= 0.0f) {
            empty = false;
            zpv = static_cast<double>(d) * kZPrimeScale;
            z = eyeZFromZPrime(zpv, n, f);
          }
        } else if (std::isfinite(d) && d > 0.0f && d <= 1.0f) {
          // Reversed: d = n·f/((f−n)·z) − n/(f−n); z' = (1 − d)·S. Eye z is
          // taken from d directly, where the float keeps its precision.
          empty = false;
          const double dd = d;
          zpv = (1.0 - dd) * kZPrimeScale;
          z = f * n / ((f - n) * dd + n);
        }
      }
      if (empty || !std::isfinite(z)) {
        zp[x] = kZPrimeScale;
        ez[x] = 0.0f;
        cv[x] = 0;
      } else {
        zp[x] = zpv;
        ez[x] = static_cast<float>(z);
        cv[x] = 1;
      }
    }
  }
}

}  // namespace hw
