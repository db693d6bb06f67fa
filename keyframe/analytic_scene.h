#pragma once
// Analytic keyframes without GL, for tests and benchmarks of the LOD builder:
// ray-cast planes, boxes and spheres per pixel centre, then quantise eq. (2)
// like a 24-bit depth buffer (Zheng et al. 1999 §1.2).
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "keyframe/keyframe.h"

namespace hw::keyframe {

struct AnalyticScene {
  struct Plane {  // infinite plane through `point` with normal `normal`
    glm::dvec3 point{0.0}, normal{0, 1, 0};
    Rgba8 colour{200, 200, 200, 255};
  };
  struct Box {  // axis-aligned; seen from inside when the eye is inside (a room)
    glm::dvec3 lo{-1.0}, hi{1.0};
    Rgba8 colour{180, 120, 90, 255};
  };
  struct Sphere {
    glm::dvec3 centre{0.0};
    double radius = 1.0;
    Rgba8 colour{90, 140, 200, 255};
  };
  std::vector<Plane> planes;
  std::vector<Box> boxes;
  std::vector<Sphere> spheres;
};

// Eye depth (distance along W) of the nearest hit through image position
// (u, v) with depth >= near, or +inf. *primitive gets the hit's index in the
// order planes, boxes, spheres (−1 if none).
double castRay(const AnalyticScene& scene, const Camera& camera, double u, double v,
               int* primitive = nullptr);

// A keyframe of `scene`: per pixel centre, eyeZ = nearest hit; covered where
// near <= z <= far; zPrime = zPrimeFromEyeZ(z), rounded to an integer when
// `quantise24` (what a 24-bit depth buffer holds); empty pixels hold
// kZPrimeScale and eyeZ 0. Colour: the primitive's colour with a checker.
// primitiveIds (optional) gets the primitive index per pixel, −1 if empty.
Keyframe renderAnalyticKeyframe(const AnalyticScene& scene, const Camera& camera,
                                bool quantise24 = true, Image<int>* primitiveIds = nullptr);

// A room-like test scene (6 m × 3 m × 8 m room, two boxes, a sphere, a
// wall panel) and a camera standing in it looking at the far corner.
AnalyticScene makeRoomScene();
Camera makeRoomCamera(int width, int height);

}  // namespace hw::keyframe
