#include "warp/warp_vertices.h"

#include "core/check.h"
#include "warp/sky_rects.h"

namespace hw::warp {

WarpVertices warpVertices(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh,
                          bool skyBackdrop) {
  HW_CHECK_EQ(kf.colour.width(), mesh.width);
  HW_CHECK_EQ(kf.colour.height(), mesh.height);
  WarpVertices out;
  std::vector<keyframe::PixelRect> sky;
  if (skyBackdrop) emptyRects(kf.covered, sky);
  out.quads = static_cast<int>(mesh.quads.size());
  out.skyRects = static_cast<int>(sky.size());
  out.data.reserve((mesh.quads.size() + sky.size()) * 4 * kFloatsPerWarpVertex);
  const double invW = 1.0 / mesh.width, invH = 1.0 / mesh.height;
  for (const keyframe::Quad& q : mesh.quads)
    for (int k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) out.data.push_back(static_cast<float>(q.world[k][c]));
      const double s = q.pixel[k].x * invW, t = q.pixel[k].y * invH, w = q.eyeZ[k];
      out.data.push_back(static_cast<float>(s * w));
      out.data.push_back(static_cast<float>(t * w));
      out.data.push_back(static_cast<float>(w));
    }
  // Each sky corner is the direction through that keyframe image point at
  // depth 1 along W, so its projective texcoord is (s, t, 1).
  for (const keyframe::PixelRect& r : sky) {
    const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
    const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 d = kf.camera.unproject(us[k], vs[k], 1.0) - kf.camera.eye;
      for (int c = 0; c < 3; ++c) out.data.push_back(static_cast<float>(d[c]));
      out.data.push_back(static_cast<float>(us[k] * invW));
      out.data.push_back(static_cast<float>(vs[k] * invH));
      out.data.push_back(1.0f);
    }
  }
  return out;
}

}  // namespace hw::warp
