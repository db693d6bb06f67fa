#pragma once
// The headless backends behind createHeadlessContext (context.h): each file
// defines its functions only when its library was found at configure time
// (HW_HAVE_EGL, HW_HAVE_OSMESA). No GL headers here.
#include <memory>
#include <string>
#include <vector>

#include "core/gl/context.h"
#include "core/result.h"

namespace hw::gl::detail {

// `second`: a context for another thread, on the table loaded for the first.
Result<std::unique_ptr<Context>> createOsMesaContext(bool second);
Result<std::unique_ptr<Context>> createEglContext(int device, bool second);

// EGL's default display and each device, probed (context.h BackendProbe);
// one entry with the error when EGL itself is unusable.
std::vector<BackendProbe> probeEgl();
// OSMesa's strings from a throw-away context (the table is not touched).
BackendProbe probeOsMesa();

// HW_GL_FAIL=1 in the environment.
bool forcedFailure();

}  // namespace hw::gl::detail
