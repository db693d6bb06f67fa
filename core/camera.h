#pragma once
// Pinhole camera with the conventions of Zheng et al. 1999 §1.1: eye E,
// orthonormal U (right), V (up), W (view direction), vertical fov α, M×N pixels,
// near/far planes. Image coordinates (u, v) are continuous pixels, u to the
// right from the left edge, v down from the top edge; pixel (i, j) has its
// centre at (i + 0.5, j + 0.5). All maths in double (DESIGN.md "Camera").
//
// Precision: unprojection, projection and matrix products are in
// double (relative 1e-16; a corner's world position at 2,400 units, the
// largest scene, is exact to 3e-13). Float enters only where its 2^-24 ≈ 6e-8
// relative error is far inside the 0.5 px reprojection budget, each stated
// where it happens: GL vertex data and the view-projection uniform
// (warp/gl/warper.cpp WarpVertex, keyframe/gl/geometry_renderer.cpp draw():
// ≤ 0.07 px at 2 units' depth, 0.27 px at a 0.5 near plane, in the largest
// scene), texcoords (≤ 1e-3 px at 4096 px), float eye-depth images
// (Keyframe::eyeZ, Layer::eyeZ: relative 6e-8 against the depth merge's 2 %
// tolerance). Keyframe z' stays double (exact 24-bit integers).
#include <glm/glm.hpp>

namespace hw {

// How the depth attachment stores depth. All three are mapped to the same
// z' scale (eq. 2) before any threshold is applied.
enum class DepthMode { Fixed24, Float32, Float32Reversed };
// Default keyframe depth buffer. Float32Reversed: `hybridwalk stress` found
// Fixed24 and Float32 lose corner accuracy from far/near 1e5 (0.36 % of the
// distance; 4.1 % at 1e6) while reversed-Z stays at ≤ 1.5e-6 with the same
// quads, PSNR and z' scale. Fixed24 (the paper's) stays available.
constexpr DepthMode kDefaultDepthMode = DepthMode::Float32Reversed;
const char* depthModeName(DepthMode m);
bool parseDepthMode(const char* s, DepthMode* out);

// z' scale: a 24-bit depth buffer stores window depth × (2^24 − 1). Eq. (2)
// writes 2^24; the two differ by at most one unit.
constexpr double kZPrimeScale = 16777215.0;

// Eq. (2): z' = S · f/(f−n) · (1 − n/z), z = eye-space distance along W.
double zPrimeFromEyeZ(double zEye, double nearPlane, double farPlane);
// Inverse of eq. (2). z' at or past S·f/(f−n) (infinity) returns +inf.
double eyeZFromZPrime(double zPrime, double nearPlane, double farPlane);

struct ProjectedPoint {
  double u = 0, v = 0;  // image coordinates, pixels
  double zEye = 0;      // distance along W (negative: behind the eye)
};

struct Camera {
  glm::dvec3 eye{0.0};
  glm::dvec3 right{1, 0, 0};     // U
  glm::dvec3 up{0, 1, 0};        // V
  glm::dvec3 forward{0, 0, -1};  // W
  double fovYRadians = 1.0471975511965976;  // 60°
  int width = 512;
  int height = 512;
  double nearPlane = 0.1;
  double farPlane = 1000.0;

  // Builds U, V, W from a target point and an up hint. Precondition: target
  // differs from eye and is not along upHint (checked).
  static Camera lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& upHint,
                       double fovYRadians, int width, int height, double nearPlane,
                       double farPlane);

  double fy() const;  // focal length in pixels; square pixels, so fx == fy
  double fx() const { return fy(); }
  double cx() const { return 0.5 * width; }
  double cy() const { return 0.5 * height; }

  // World point seen at image position (u, v) at eye-space depth zEye: the
  // paper's V = H_E P.
  glm::dvec3 unproject(double u, double v, double zEye) const;
  ProjectedPoint project(const glm::dvec3& world) const;

  // GL matrices. viewMatrix: world → GL eye space (−Z forward). The
  // projection follows `mode`: standard OpenGL [−1, 1] for Fixed24/Float32,
  // and 1 → 0 with glClipControl(ZERO_TO_ONE) for Float32Reversed.
  // infiniteFar puts the far plane at infinity (window depth 1 − n/z standard,
  // n/z reversed).
  glm::dmat4 viewMatrix() const;
  glm::dmat4 projectionMatrix(DepthMode mode, bool infiniteFar = false) const;

  // Camera pose with OpenCV axes (x right, y down, z forward), for export.
  glm::dmat4 worldFromCameraOpenCv() const;
};

}  // namespace hw
