#include "core/camera.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "core/check.h"

namespace hw {

const char* depthModeName(DepthMode m) {
  switch (m) {
    case DepthMode::Fixed24: return "fixed24";
    case DepthMode::Float32: return "float32";
    case DepthMode::Float32Reversed: return "float32-reversed";
  }
  return "?";
}

bool parseDepthMode(const char* s, DepthMode* out) {
  for (DepthMode m : {DepthMode::Fixed24, DepthMode::Float32, DepthMode::Float32Reversed}) {
    if (std::strcmp(s, depthModeName(m)) == 0) {
      *out = m;
      return true;
    }
  }
  return false;
}

double zPrimeFromEyeZ(double zEye, double n, double f) {
  return kZPrimeScale * f / (f - n) * (1.0 - n / zEye);
}

double eyeZFromZPrime(double zPrime, double n, double f) {
  const double t = 1.0 - zPrime * (f - n) / (f * kZPrimeScale);  // = n / z
  if (t <= 0.0) return std::numeric_limits<double>::infinity();
  return n / t;
}

Camera Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& upHint,
                      double fovYRadians, int width, int height, double nearPlane,
                      double farPlane) {
  Camera c;
  c.eye = eye;
  glm::dvec3 w = target - eye;
  HW_CHECK_GT(glm::length(w), 0.0);
  w = glm::normalize(w);
  glm::dvec3 u = glm::cross(w, upHint);
  HW_CHECK_GT(glm::length(u), 1e-12);
  u = glm::normalize(u);
  c.forward = w;
  c.right = u;
  c.up = glm::cross(u, w);
  c.fovYRadians = fovYRadians;
  c.width = width;
  c.height = height;
  c.nearPlane = nearPlane;
  c.farPlane = farPlane;
  return c;
}

double Camera::fy() const { return 0.5 * height / std::tan(0.5 * fovYRadians); }

glm::dvec3 Camera::unproject(double u, double v, double zEye) const {
  const double x = (u - cx()) / fx();
  const double y = (cy() - v) / fy();
  return eye + zEye * (forward + x * right + y * up);
}

ProjectedPoint Camera::project(const glm::dvec3& world) const {
  const glm::dvec3 d = world - eye;
  ProjectedPoint p;
  p.zEye = glm::dot(d, forward);
  p.u = cx() + fx() * glm::dot(d, right) / p.zEye;
  p.v = cy() - fy() * glm::dot(d, up) / p.zEye;
  return p;
}

glm::dmat4 Camera::viewMatrix() const {
  // Rows are U, V, −W; GLM is column-major: m[col][row].
  glm::dmat4 m(1.0);
  for (int k = 0; k < 3; ++k) {
    m[k][0] = right[k];
    m[k][1] = up[k];
    m[k][2] = -forward[k];
  }
  m[3][0] = -glm::dot(right, eye);
  m[3][1] = -glm::dot(up, eye);
  m[3][2] = glm::dot(forward, eye);
  return m;
}

glm::dmat4 Camera::projectionMatrix(DepthMode mode, bool infiniteFar) const {
  const double n = nearPlane, f = farPlane;
  glm::dmat4 p(0.0);
  p[0][0] = 2.0 * fx() / width;
  p[1][1] = 2.0 * fy() / height;
  p[2][3] = -1.0;  // clip w = −z_gl = distance along W
  if (mode == DepthMode::Float32Reversed) {
    // window depth = n·f/((f−n)·z) − n/(f−n) = 1 − (standard window depth).
    if (infiniteFar) {
      p[2][2] = 0.0;  // window depth = n / z
      p[3][2] = n;
    } else {
      p[2][2] = n / (f - n);
      p[3][2] = f * n / (f - n);
    }
  } else if (infiniteFar) {
    p[2][2] = -1.0;
    p[3][2] = -2.0 * n;
  } else {
    p[2][2] = -(f + n) / (f - n);
    p[3][2] = -2.0 * f * n / (f - n);
  }
  return p;
}

glm::dmat4 Camera::worldFromCameraOpenCv() const {
  glm::dmat4 m(1.0);
  const glm::dvec3 down = -up;
  for (int k = 0; k < 3; ++k) {
    m[0][k] = right[k];
    m[1][k] = down[k];
    m[2][k] = forward[k];
    m[3][k] = eye[k];
  }
  return m;
}

}  // namespace hw
