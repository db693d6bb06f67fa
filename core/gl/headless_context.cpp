// createHeadlessContext: the backend choice (context.h) over the EGL and
// OSMesa implementations this build has.
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "core/gl/context.h"
#include "core/gl/headless_backends.h"

namespace hw::gl {
namespace {

struct State {
  std::mutex mutex;
  bool optionsSet = false;
  HeadlessOptions options;
  // The first context's backend and device: a second context uses them.
  Backend active = Backend::Auto;
  int activeDevice = -1;
  ContextStrings strings;
};

State& state() {
  static State s;
  return s;
}

// HYBRIDWALK_GL, or an error naming the bad value.
Result<Backend> environmentBackend() {
  const char* env = std::getenv("HYBRIDWALK_GL");
  Backend b = Backend::Auto;
  if (env && *env && !parseBackend(env, &b))
    return makeError(std::string("HYBRIDWALK_GL=") + env +
                     " in the environment: expected auto, egl or osmesa");
  return b;
}

// `b` asked for in a build without it; `suggestOther`: name the backend the
// build has (not when that one was tried and failed, as under --gl auto).
std::string notBuilt(Backend b, bool suggestOther = true) {
  return std::string("this hybridwalk was built without ") +
         (b == Backend::Egl ? "EGL (configure with -DHW_WITH_EGL=ON and libegl-dev installed)"
                            : "OSMesa (configure with -DHW_WITH_OSMESA=ON and libosmesa6-dev "
                              "installed)") +
         (suggestOther ? std::string("; use --gl ") + (b == Backend::Egl ? "osmesa" : "egl") : "");
}

Result<std::unique_ptr<Context>> create(Backend b, int device, bool second) {
#ifdef HW_HAVE_EGL
  if (b == Backend::Egl) return detail::createEglContext(device, second);
#endif
#ifdef HW_HAVE_OSMESA
  if (b == Backend::OsMesa) {
    if (device >= 0)
      return makeError("--gl-device " + std::to_string(device) +
                       " picks an EGL device, but the backend is OSMesa (--gl osmesa or "
                       "HYBRIDWALK_GL=osmesa); drop one of them");
    return detail::createOsMesaContext(second);
  }
#endif
  (void)device;
  (void)second;
  return makeError(notBuilt(b));
}

}  // namespace

const char* backendName(Backend b) {
  switch (b) {
    case Backend::Egl: return "egl";
    case Backend::OsMesa: return "osmesa";
    case Backend::Auto: break;
  }
  return "auto";
}

bool parseBackend(const std::string& s, Backend* out) {
  for (Backend b : {Backend::Auto, Backend::Egl, Backend::OsMesa})
    if (s == backendName(b)) {
      *out = b;
      return true;
    }
  return false;
}

bool backendBuilt(Backend b) {
  switch (b) {
    case Backend::Egl:
#ifdef HW_HAVE_EGL
      return true;
#else
      return false;
#endif
    case Backend::OsMesa:
#ifdef HW_HAVE_OSMESA
      return true;
#else
      return false;
#endif
    case Backend::Auto: break;
  }
  return true;
}

namespace detail {
bool forcedFailure() {
  const char* fail = std::getenv("HW_GL_FAIL");
  return fail && std::strcmp(fail, "1") == 0;
}
}  // namespace detail

HeadlessOptions headlessOptions() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  if (s.optionsSet) return s.options;
  HeadlessOptions o;
  if (auto b = environmentBackend()) o.backend = *b;
  return o;
}

void setHeadlessOptions(const HeadlessOptions& o) {
  State& s = state();
  std::lock_guard lock(s.mutex);
  s.options = o;
  s.optionsSet = true;
}

Result<std::unique_ptr<Context>> createHeadlessContext() {
  State& s = state();
  {
    std::lock_guard lock(s.mutex);
    if (!s.optionsSet) {
      auto b = environmentBackend();
      if (!b) return b.error();
    }
  }
  return createHeadlessContext(headlessOptions());
}

Result<std::unique_ptr<Context>> createHeadlessContext(const HeadlessOptions& o) {
  Backend b = o.backend;
  Result<std::unique_ptr<Context>> ctx = makeError("");
  if (b == Backend::Auto) {
    // EGL when it gives a 4.5 core context, else OSMesa; both reasons when
    // neither does.
    std::string eglWhy = notBuilt(Backend::Egl, false);
#ifdef HW_HAVE_EGL
    ctx = detail::createEglContext(o.eglDevice, false);
    if (ctx) b = Backend::Egl;
    else eglWhy = ctx.error().message;
#endif
    if (!ctx && o.eglDevice >= 0) return makeError(eglWhy);  // a device names EGL
    if (!ctx) {
#ifdef HW_HAVE_OSMESA
      ctx = detail::createOsMesaContext(false);
      if (ctx) b = Backend::OsMesa;
      else
        return makeError("no headless OpenGL 4.5 core context: EGL: " + eglWhy +
                         "; OSMesa: " + ctx.error().message);
#else
      return makeError("no headless OpenGL 4.5 core context: EGL: " + eglWhy + "; OSMesa: " +
                       notBuilt(Backend::OsMesa, false));
#endif
    }
  } else {
    ctx = create(b, o.eglDevice, false);
    if (!ctx) return ctx.error();
  }
  State& s = state();
  std::lock_guard lock(s.mutex);
  s.active = b;
  s.activeDevice = o.eglDevice;
  s.strings = {(*ctx)->backend(), (*ctx)->vendor(), (*ctx)->renderer(), (*ctx)->version()};
  return ctx;
}

Result<std::unique_ptr<Context>> createSecondHeadlessContext() {
  State& s = state();
  Backend b;
  int device;
  {
    std::lock_guard lock(s.mutex);
    b = s.active;
    device = s.activeDevice;
  }
  if (b == Backend::Auto)
    return makeError("cannot create a second headless OpenGL context: no first one was created "
                     "with createHeadlessContext()");
  return create(b, device, true);
}

ContextStrings lastHeadlessContextStrings() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  return s.strings;
}

std::vector<BackendProbe> probeHeadlessBackends() {
  std::vector<BackendProbe> out;
#ifdef HW_HAVE_EGL
  out = detail::probeEgl();
#endif
#ifdef HW_HAVE_OSMESA
  out.push_back(detail::probeOsMesa());
#endif
  return out;
}

}  // namespace hw::gl
