#include "keyframe/quad_validation.h"

#include <cmath>
#include <limits>

#include "core/check.h"

namespace hw::keyframe {

QuadValidation validateQuads(const Keyframe& kf, const QuadMesh& mesh,
                             std::span<const Camera> targets,
                             const QuadValidationOptions& options) {
  HW_CHECK(std::isfinite(options.tolerancePx) && options.tolerancePx > 0.0);
  HW_CHECK_GE(options.minBadPixels, 1);
  const int w = kf.zPrime.width(), h = kf.zPrime.height();
  HW_CHECK_EQ(mesh.width, w);
  HW_CHECK_EQ(mesh.height, h);
  HW_CHECK_EQ(kf.covered.width(), w);
  HW_CHECK_EQ(kf.covered.height(), h);
  const bool haveEyeZ = !kf.eyeZ.empty();
  if (haveEyeZ) {
    HW_CHECK_EQ(kf.eyeZ.width(), w);
    HW_CHECK_EQ(kf.eyeZ.height(), h);
  }
  const Camera& cam = kf.camera;
  const double fx = cam.fx(), fy = cam.fy(), cx = cam.cx(), cy = cam.cy();
  const double n = cam.nearPlane, f = cam.farPlane;
  constexpr double kInf = std::numeric_limits<double>::infinity();

  QuadValidation out;
  out.quads.resize(mesh.quads.size());
  for (std::size_t k = 0; k < mesh.quads.size(); ++k) {
    const Quad& q = mesh.quads[k];
    const PixelRect& r = q.rect;
    HW_CHECK(r.x0 >= 0 && r.y0 >= 0 && r.x0 < r.x1 && r.y0 < r.y1 && r.x1 <= w && r.y1 <= h);
    QuadCheck& c = out.quads[k];
    c.quad = static_cast<int>(k);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        if (kf.covered(x, y) == 0) continue;
        const double zPix = haveEyeZ ? static_cast<double>(kf.eyeZ(x, y))
                                     : eyeZFromZPrime(kf.zPrime(x, y), n, f);
        if (!(zPix > 0.0) || !std::isfinite(zPix)) continue;
        const double u = x + 0.5, v = y + 0.5;
        const double zQuad = quadEyeZAt(q, u, v);
        // Both points on the keyframe ray through (u, v): E + z·d.
        const glm::dvec3 d = cam.forward + ((u - cx) / fx) * cam.right + ((cy - v) / fy) * cam.up;
        const glm::dvec3 pPix = cam.eye + zPix * d, pQuad = cam.eye + zQuad * d;
        c.parallaxPxPerUnit = std::max(c.parallaxPxPerUnit, fx * std::fabs(1.0 / zPix - 1.0 / zQuad));
        bool bad = false;
        for (std::size_t t = 0; t < targets.size(); ++t) {
          const Camera& tc = targets[t];
          const ProjectedPoint a = tc.project(pPix);
          if (!(a.zEye > tc.nearPlane) || !(a.u >= 0.0 && a.u <= tc.width) ||
              !(a.v >= 0.0 && a.v <= tc.height))
            continue;
          ++out.checkedPixels;
          const ProjectedPoint b = tc.project(pQuad);
          double err = kInf;
          if (b.zEye > tc.nearPlane && std::isfinite(b.u) && std::isfinite(b.v))
            err = std::hypot(a.u - b.u, a.v - b.v);
          if (err > options.tolerancePx) bad = true;
          if (err > c.maxErrorPx) {
            c.maxErrorPx = err;
            c.worstTarget = static_cast<int>(t);
            c.worstX = x;
            c.worstY = y;
          }
        }
        c.badPixels += bad;
      }
    c.flagged = c.badPixels >= options.minBadPixels;
    out.flagged += c.flagged;
    out.badPixels += c.badPixels;
    out.maxParallaxPxPerUnit = std::max(out.maxParallaxPxPerUnit, c.parallaxPxPerUnit);
    if (c.maxErrorPx > out.maxErrorPx) {
      out.maxErrorPx = c.maxErrorPx;
      out.worstQuad = c.quad;
    }
  }
  return out;
}

}  // namespace hw::keyframe
