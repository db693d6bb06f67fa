#pragma once
// QuadMesh: the level-of-detail model of one keyframe (Zheng et al. 1999 §1.2):
// one spatial quad per leaf rectangle of the binary subdivision.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/rect.h"

#include "keyframe/delta_buffer.h"

namespace hw::keyframe {

// Leaf rectangles are in keyframe image coordinates (core/rect.h).
using hw::PixelRect;

struct Quad {
  PixelRect rect;
  // Corners at the rectangle's OUTER pixel edges (the paper's half-pixel
  // expansion), in order top-left (x0,y0), top-right (x1,y0), bottom-right
  // (x1,y1), bottom-left (x0,y1) of the image.
  std::array<glm::dvec3, 4> world;  // world-space corners
  std::array<glm::dvec2, 4> pixel;  // keyframe image coordinates (u, v) of the corners
  std::array<double, 4> eyeZ;       // corner depth along the keyframe's W (> 0, finite)
  float maxDelta = 0.0f;            // max |Δ²| over the leaf (z' units)
};

struct QuadMeshStats {
  int quads = 0;
  int onePixelLeaves = 0;
  long long emptyPixels = 0;
  int clampedCorners = 0;  // corners whose fitted z' was clamped (near the horizon)
  double deltaMs = 0, subdivideMs = 0, cornersMs = 0;
  // Which test the build used (DESIGN.md: "report which one a run used").
  DeltaCriterion criterion = DeltaCriterion::FivePoint;
  double tauZPrime = 0;      // threshold applied to |Δ²z'| (z' units)
  double tauParallaxPx = 0;  // > 0: tauZPrime was derived from this parallax bound
};

struct QuadMesh {
  int width = 0, height = 0;  // keyframe resolution
  std::vector<Quad> quads;
  QuadMeshStats stats;
};

// World point on a quad at keyframe image position (u, v). The quad is planar
// and 1/z is affine on a plane, so 1/z is interpolated bilinearly from the
// corners (exact for unclamped corners). `camera` is the keyframe's.
glm::dvec3 quadPointAt(const Quad& quad, const Camera& camera, double u, double v);
// Its depth along the keyframe's W at (u, v) (the 1/z bilinear above).
double quadEyeZAt(const Quad& quad, double u, double v);

}  // namespace hw::keyframe
