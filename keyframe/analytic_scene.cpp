#include "keyframe/analytic_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hw::keyframe {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The ray is eye + t·d with d = W + x·U + y·V, so d·W = 1 and t is eye depth.
double hitPlane(const AnalyticScene::Plane& p, const glm::dvec3& e, const glm::dvec3& d) {
  const double dn = glm::dot(d, p.normal);
  if (dn == 0.0) return kInf;
  const double t = glm::dot(p.point - e, p.normal) / dn;
  return t > 0.0 ? t : kInf;
}

double hitBox(const AnalyticScene::Box& b, const glm::dvec3& e, const glm::dvec3& d, double tMin) {
  double t0 = -kInf, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (e[k] < b.lo[k] || e[k] > b.hi[k]) return kInf;
      continue;
    }
    double a = (b.lo[k] - e[k]) / d[k], c = (b.hi[k] - e[k]) / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  if (t1 < t0) return kInf;
  if (t0 >= tMin) return t0;
  if (t1 >= tMin) return t1;  // eye inside: the far side (a room's walls)
  return kInf;
}

double hitSphere(const AnalyticScene::Sphere& s, const glm::dvec3& e, const glm::dvec3& d,
                 double tMin) {
  const glm::dvec3 oc = e - s.centre;
  const double a = glm::dot(d, d), b = glm::dot(oc, d), c = glm::dot(oc, oc) - s.radius * s.radius;
  const double disc = b * b - a * c;
  if (disc < 0.0) return kInf;
  const double r = std::sqrt(disc);
  const double ta = (-b - r) / a, tb = (-b + r) / a;
  if (ta >= tMin) return ta;
  if (tb >= tMin) return tb;
  return kInf;
}

}  // namespace

double castRay(const AnalyticScene& scene, const Camera& cam, double u, double v, int* primitive) {
  const double x = (u - cam.cx()) / cam.fx();
  const double y = (cam.cy() - v) / cam.fy();
  const glm::dvec3 d = cam.forward + x * cam.right + y * cam.up;
  const double tMin = cam.nearPlane;
  double best = kInf;
  int id = -1, k = 0;
  auto consider = [&](double t) {
    if (t >= tMin && t < best) {
      best = t;
      id = k;
    }
    ++k;
  };
  for (const auto& p : scene.planes) consider(hitPlane(p, cam.eye, d));
  for (const auto& b : scene.boxes) consider(hitBox(b, cam.eye, d, tMin));
  for (const auto& s : scene.spheres) consider(hitSphere(s, cam.eye, d, tMin));
  if (primitive) *primitive = id;
  return best;
}

Keyframe renderAnalyticKeyframe(const AnalyticScene& scene, const Camera& cam, bool quantise24,
                                Image<int>* primitiveIds) {
  Keyframe kf;
  kf.camera = cam;
  kf.depthMode = DepthMode::Fixed24;
  const int w = cam.width, h = cam.height;
  kf.colour.resize(w, h);
  kf.zPrime.resize(w, h, kZPrimeScale);
  kf.eyeZ.resize(w, h, 0.0f);
  kf.covered.resize(w, h, 0);
  if (primitiveIds) primitiveIds->resize(w, h, -1);
  std::vector<Rgba8> colours;
  for (const auto& p : scene.planes) colours.push_back(p.colour);
  for (const auto& b : scene.boxes) colours.push_back(b.colour);
  for (const auto& s : scene.spheres) colours.push_back(s.colour);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      int id = -1;
      const double z = castRay(scene, cam, i + 0.5, j + 0.5, &id);
      if (!(z <= cam.farPlane)) {
        kf.colour(i, j) = Rgba8{20, 20, 40, 255};
        continue;
      }
      double zp = zPrimeFromEyeZ(z, cam.nearPlane, cam.farPlane);
      if (quantise24) zp = std::round(zp);
      kf.zPrime(i, j) = zp;
      kf.eyeZ(i, j) = static_cast<float>(z);
      kf.covered(i, j) = 1;
      if (primitiveIds) (*primitiveIds)(i, j) = id;
      // A world-space checker so the overlay shows texture inside the quads.
      const glm::dvec3 p = cam.unproject(i + 0.5, j + 0.5, z);
      const int check =
          (static_cast<int>(std::floor(p.x * 2)) + static_cast<int>(std::floor(p.y * 2)) +
           static_cast<int>(std::floor(p.z * 2))) &
          1;
      Rgba8 c = colours[static_cast<std::size_t>(id)];
      if (check) {
        c.r = static_cast<std::uint8_t>(c.r * 3 / 4);
        c.g = static_cast<std::uint8_t>(c.g * 3 / 4);
        c.b = static_cast<std::uint8_t>(c.b * 3 / 4);
      }
      kf.colour(i, j) = c;
    }
  }
  return kf;
}

AnalyticScene makeRoomScene() {
  AnalyticScene s;
  s.boxes.push_back({{-3.0, 0.0, -8.0}, {3.0, 3.0, 0.5}, {210, 205, 190, 255}});   // the room
  s.boxes.push_back({{-2.5, 0.0, -6.5}, {-1.2, 0.9, -5.0}, {170, 110, 70, 255}});  // a chest
  s.boxes.push_back({{0.8, 0.0, -4.2}, {1.6, 1.6, -3.4}, {120, 150, 90, 255}});    // a cabinet
  s.spheres.push_back({{0.2, 0.6, -5.5}, 0.6, {90, 130, 210, 255}});
  // A panel standing against the right wall.
  s.boxes.push_back({{2.6, 0.0, -7.5}, {2.9, 2.4, -6.0}, {200, 80, 80, 255}});
  return s;
}

Camera makeRoomCamera(int width, int height) {
  return Camera::lookAt({-1.5, 1.6, -0.5}, {1.5, 0.9, -7.5}, {0, 1, 0}, 1.0471975511965976, width,
                        height, 0.1, 100.0);
}

}  // namespace hw::keyframe
