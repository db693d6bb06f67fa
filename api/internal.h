#pragma once
// What the public API's classes hold (include/hybridwalk), shared by its
// implementation files; conversions between its types and the project's.
#include <string>

#include "core/camera.h"
#include "hybridwalk/camera.h"
#include "hybridwalk/scene.h"
#include "scenes/scene.h"

namespace hybridwalk {

struct Scene::Impl {
  hw::scenes::Scene scene;
  std::string spec;  // load(): its spec; build(): empty
};

namespace detail {

inline glm::dvec3 toGlm(const Vec3& v) { return {v.x, v.y, v.z}; }
inline Vec3 fromGlm(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
hw::Camera toInternal(const Camera& c);
Camera fromInternal(const hw::Camera& c);
// Error unless finite, orthonormal axes (to 1e-6), fov in (0, π), size in
// 1 … 16384 and 0 < near < far. `what` names the camera in the message.
hw::Status checkCamera(const Camera& c, const std::string& what);

}  // namespace detail
}  // namespace hybridwalk
