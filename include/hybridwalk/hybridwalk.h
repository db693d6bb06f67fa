#pragma once
// hybridwalk: real-time walkthroughs that mix geometry and images (Zheng,
// Bao, Peng & Sun 1999), as a library. Include this header and link
// hybridwalk::hybridwalk (CMake: find_package(hybridwalk)) or
// `pkg-config --libs hybridwalk`. docs/api.md has a complete example.
//   result.h    Result<T>, Status, Error: every call's errors
//   camera.h    Camera, Path, loadPath
//   scene.h     Scene: load by spec, or build from your own meshes
//   renderer.h  Renderer: camera → Frame (colour, depth, stats)
#include "hybridwalk/camera.h"
#include "hybridwalk/renderer.h"
#include "hybridwalk/result.h"
#include "hybridwalk/scene.h"

#define HYBRIDWALK_VERSION_MAJOR 0
#define HYBRIDWALK_VERSION_MINOR 1
#define HYBRIDWALK_VERSION_PATCH 0
