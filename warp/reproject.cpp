#include "warp/reproject.h"

#include <algorithm>
#include <cmath>

namespace hw::warp {

std::vector<WarpSample> reprojectSamples(const keyframe::Keyframe& kf,
                                         const keyframe::QuadMesh& mesh, const Camera& target,
                                         int samplesPerAxis) {
  std::vector<WarpSample> out;
  for (const keyframe::Quad& q : mesh.quads) {
    const int nx = std::min(samplesPerAxis, q.rect.width());
    const int ny = std::min(samplesPerAxis, q.rect.height());
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) {
        const int px = q.rect.x0 + (2 * a + 1) * q.rect.width() / (2 * nx);
        const int py = q.rect.y0 + (2 * b + 1) * q.rect.height() / (2 * ny);
        if (!kf.covered(px, py)) continue;
        WarpSample s;
        s.sourceU = px + 0.5;
        s.sourceV = py + 0.5;
        const glm::dvec3 w = keyframe::quadPointAt(q, kf.camera, s.sourceU, s.sourceV);
        const ProjectedPoint p = target.project(w);
        if (!(p.zEye > 0) || !std::isfinite(p.u) || !std::isfinite(p.v)) continue;
        s.targetU = p.u;
        s.targetV = p.v;
        s.targetZ = p.zEye;
        s.colour = kf.colour(px, py);
        out.push_back(s);
      }
  }
  return out;
}

}  // namespace hw::warp
