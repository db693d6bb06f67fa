// Public cameras and paths: conversions and checks.
#include "hybridwalk/camera.h"

#include <cmath>
#include <string>
#include <utility>

#include "api/internal.h"
#include "core/result.h"
#include "core/short_number.h"
#include "scenes/camera_path.h"

namespace hybridwalk {
namespace detail {

hw::Camera toInternal(const Camera& c) {
  hw::Camera h;
  h.eye = toGlm(c.eye);
  h.right = toGlm(c.right);
  h.up = toGlm(c.up);
  h.forward = toGlm(c.forward);
  h.fovYRadians = c.fovYRadians;
  h.width = c.width;
  h.height = c.height;
  h.nearPlane = c.nearPlane;
  h.farPlane = c.farPlane;
  return h;
}

Camera fromInternal(const hw::Camera& h) {
  Camera c;
  c.eye = fromGlm(h.eye);
  c.right = fromGlm(h.right);
  c.up = fromGlm(h.up);
  c.forward = fromGlm(h.forward);
  c.fovYRadians = h.fovYRadians;
  c.width = h.width;
  c.height = h.height;
  c.nearPlane = h.nearPlane;
  c.farPlane = h.farPlane;
  return c;
}

hw::Status checkCamera(const Camera& c, const std::string& what) {
  const glm::dvec3 e = toGlm(c.eye), r = toGlm(c.right), u = toGlm(c.up), f = toGlm(c.forward);
  auto finite = [](const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite(e) || !finite(r) || !finite(u) || !finite(f))
    return hw::makeError(what + ": eye and axes must be finite");
  constexpr double kTol = 1e-6;
  if (std::abs(glm::length(r) - 1) > kTol || std::abs(glm::length(u) - 1) > kTol ||
      std::abs(glm::length(f) - 1) > kTol || std::abs(glm::dot(r, u)) > kTol ||
      std::abs(glm::dot(r, f)) > kTol || std::abs(glm::dot(u, f)) > kTol)
    return hw::makeError(what +
                         ": right, up and forward must be orthonormal (to 1e-6); build the "
                         "camera with Camera::lookAt");
  if (!(c.fovYRadians > 0 && c.fovYRadians < 3.14159265358979323846))
    return hw::makeError(what + ": fovYRadians: expected 0 < fov < pi, got " +
                         hw::shortNumber(c.fovYRadians));
  if (c.width < 1 || c.width > 16384 || c.height < 1 || c.height > 16384)
    return hw::makeError(what + ": size: expected 1 ... 16384 pixels each way, got " +
                         std::to_string(c.width) + "x" + std::to_string(c.height));
  if (!(c.nearPlane > 0 && c.nearPlane < c.farPlane && std::isfinite(c.farPlane)))
    return hw::makeError(what + ": planes: expected 0 < near < far (finite), got near " +
                         hw::shortNumber(c.nearPlane) + ", far " + hw::shortNumber(c.farPlane));
  return {};
}

}  // namespace detail

Result<Camera> Camera::lookAt(const Vec3& eye, const Vec3& target, const Vec3& upHint,
                              double fovYRadians, int width, int height, double nearPlane,
                              double farPlane) {
  const glm::dvec3 e = detail::toGlm(eye), t = detail::toGlm(target), u = detail::toGlm(upHint);
  for (double v : {e.x, e.y, e.z, t.x, t.y, t.z, u.x, u.y, u.z})
    if (!std::isfinite(v))
      return hw::makeError("Camera::lookAt: eye, target and up must be finite");
  const glm::dvec3 d = t - e;
  if (!(glm::length(d) > 0)) return hw::makeError("Camera::lookAt: target equals eye");
  if (!(glm::length(u) > 0) || glm::length(glm::cross(glm::normalize(d), glm::normalize(u))) < 1e-9)
    return hw::makeError("Camera::lookAt: the view direction is along the up hint (or up is 0)");
  Camera probe;
  probe.fovYRadians = fovYRadians;
  probe.width = width;
  probe.height = height;
  probe.nearPlane = nearPlane;
  probe.farPlane = farPlane;
  HW_TRY(detail::checkCamera(probe, "Camera::lookAt"));
  return detail::fromInternal(
      hw::Camera::lookAt(e, t, u, fovYRadians, width, height, nearPlane, farPlane));
}

Result<Path> loadPath(const std::string& file) {
  auto p = hw::scenes::loadCameraPath(file);
  if (!p) return p.error();
  Path out;
  out.keyframeEvery = p->keyframeEvery;
  for (const hw::Camera& c : p->cameras()) out.cameras.push_back(detail::fromInternal(c));
  return out;
}

}  // namespace hybridwalk
