#include "warp/forward_splat.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace hw::warp {
namespace {

// An empty layer of w × h pixels: nothing covered.
void resetLayer(Layer& l, int w, int h) {
  l.colour.resize(w, h, Rgba8{});
  l.coverage.resize(w, h, 0);
  l.eyeZ.resize(w, h, 0.0f);
}

}  // namespace

double forwardSplat(const SplatSource& src, const Camera& target, Layer& out) {
  const int w = target.width, h = target.height;
  resetLayer(out, w, h);
  std::uint8_t* covered = out.coverage.data();
  float* depth = out.eyeZ.data();
  Rgba8* colour = out.colour.data();
  const Camera& sc = src.camera;
  const int sw = sc.width, sh = sc.height;
  double stretchSum = 0;
  long stretchN = 0;
  auto fill = [&](double u, double v, double hx, double hy, float z, Rgba8 c, bool sky) {
    const int x0 = std::max(0, static_cast<int>(std::ceil(u - hx - 0.5)));
    const int x1 = std::min(w - 1, static_cast<int>(std::floor(u + hx - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(v - hy - 0.5)));
    const int y1 = std::min(h - 1, static_cast<int>(std::floor(v + hy - 0.5)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t t = static_cast<std::size_t>(y) * w + x;
        if (sky) {
          if (!covered[t]) covered[t] = 1, depth[t] = kSkyEyeZ, colour[t] = c;
        } else if (!covered[t] || z < depth[t]) {
          depth[t] = z, colour[t] = c, covered[t] = 1;
        }
      }
  };
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x) {
      const std::size_t s = static_cast<std::size_t>(y) * sw + x;
      const Rgba8 c = src.colour(x, y);
      if (!src.covered(x, y)) {
        const ProjectedPoint p = target.project(target.eye + src.point[s]);
        if (p.zEye <= 1e-9 || !std::isfinite(p.u) || !std::isfinite(p.v)) continue;
        fill(p.u, p.v, 0.75, 0.75, 0, c, true);
        continue;
      }
      const double z = src.eyeZ(x, y);
      const ProjectedPoint p = target.project(src.point[s]);
      if (p.zEye <= target.nearPlane) continue;
      if (p.u < -8 || p.v < -8 || p.u > w + 8 || p.v > h + 8) continue;
      // A neighbour on the same surface: depth within 25 % (one probe pixel
      // spans several frame pixels, so grazing floors change fast); else the
      // one on the other side, mirrored; else a point at the same depth.
      auto continuous = [&](int xn, int yn) {
        return xn >= 0 && yn >= 0 && xn < sw && yn < sh && src.covered(xn, yn) &&
               std::abs(src.eyeZ(xn, yn) - z) < 0.25 * z;
      };
      auto step = [&](int dx, int dy, double* du, double* dv) {
        ProjectedPoint q;
        double sign = 1;
        if (continuous(x + dx, y + dy)) {
          q = target.project(src.point[static_cast<std::size_t>(y + dy) * sw + (x + dx)]);
        } else if (continuous(x - dx, y - dy)) {
          q = target.project(src.point[static_cast<std::size_t>(y - dy) * sw + (x - dx)]);
          sign = -1;
        } else {
          q = target.project(sc.unproject(x + dx + 0.5, y + dy + 0.5, z));
        }
        *du = sign * (q.u - p.u);
        *dv = sign * (q.v - p.v);
        return q.zEye > target.nearPlane;
      };
      double dux = 0, dvx = 0, duy = 0, dvy = 0;
      double hx = 0.5, hy = 0.5;
      if (step(1, 0, &dux, &dvx) && step(0, 1, &duy, &dvy)) {
        hx = std::clamp(0.5 * (std::abs(dux) + std::abs(duy)), 0.5, 8.0);
        hy = std::clamp(0.5 * (std::abs(dvx) + std::abs(dvy)), 0.5, 8.0);
        if (p.u >= 0 && p.v >= 0 && p.u < w && p.v < h) {
          const double area = std::abs(dux * dvy - duy * dvx);
          stretchSum += std::abs(std::log2(std::max(area, 1e-4)));
          ++stretchN;
        }
      }
      fill(p.u, p.v, hx, hy, static_cast<float>(p.zEye), c, false);
    }
  return stretchN ? stretchSum / static_cast<double>(stretchN) : 0.0;
}

}  // namespace hw::warp
