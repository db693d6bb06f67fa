#include "keyframe/quad_mesh.h"

namespace hw::keyframe {

double quadEyeZAt(const Quad& q, double u, double v) {
  const double s = (u - q.pixel[0].x) / (q.pixel[1].x - q.pixel[0].x);
  const double t = (v - q.pixel[0].y) / (q.pixel[3].y - q.pixel[0].y);
  const double inv = (1 - s) * (1 - t) / q.eyeZ[0] + s * (1 - t) / q.eyeZ[1] +
                     s * t / q.eyeZ[2] + (1 - s) * t / q.eyeZ[3];
  return 1.0 / inv;
}

glm::dvec3 quadPointAt(const Quad& q, const Camera& camera, double u, double v) {
  return camera.unproject(u, v, quadEyeZAt(q, u, v));
}

}  // namespace hw::keyframe
