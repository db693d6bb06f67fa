// EGL headless context: desktop OpenGL 4.5 core through eglBindAPI(EGL_OPENGL_API)
// with no surface at all (EGL_KHR_surfaceless_context); rendering goes to
// framebuffer objects. The display is Mesa's surfaceless platform
// (EGL_MESA_platform_surfaceless: llvmpipe, or the first GPU render node) or
// one EGL device (EGL_EXT_platform_device: any vendor's GPU, no display
// server). Only this file includes EGL headers.
#ifdef HW_HAVE_EGL

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/gl/context.h"
#include "core/gl/gl_api.h"
#include "core/gl/headless_backends.h"

namespace hw::gl::detail {
namespace {

// Serialises context creation (one per thread may be created while another
// thread draws) and the display cache.
std::mutex gEglMutex;

void* eglProc(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: {
      char buf[32];
      std::snprintf(buf, sizeof buf, "EGL error 0x%04x", static_cast<unsigned>(e));
      return buf;
    }
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// What else to try when this display cannot give a context: OSMesa only in a
// build that has it.
#ifdef HW_HAVE_OSMESA
constexpr const char* kTryOther = "use --gl osmesa or another device";
#else
constexpr const char* kTryOther = "use another device (--gl-device N; `hybridwalk info` lists them)";
#endif

const char* clientExtensions() { return eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS); }

// The EGL devices, or an error when the library cannot enumerate them.
Result<std::vector<EGLDeviceEXT>> devices() {
  const char* ext = clientExtensions();
  if (!hasExtension(ext, "EGL_EXT_device_enumeration") &&
      !hasExtension(ext, "EGL_EXT_device_base"))
    return makeError("the EGL library cannot list devices (no EGL_EXT_device_enumeration)");
  auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglProc("eglQueryDevicesEXT"));
  if (!query) return makeError("the EGL library has no eglQueryDevicesEXT");
  EGLint n = 0;
  if (!query(0, nullptr, &n)) return makeError("eglQueryDevicesEXT failed: " + eglErrorName(eglGetError()));
  std::vector<EGLDeviceEXT> out(static_cast<size_t>(n));
  if (n > 0 && !query(n, out.data(), &n))
    return makeError("eglQueryDevicesEXT failed: " + eglErrorName(eglGetError()));
  out.resize(static_cast<size_t>(n));
  return out;
}

// "EGL device N (/dev/dri/renderD128)" or "(EGL_MESA_device_software)".
std::string deviceName(EGLDeviceEXT dev, int index) {
  auto str = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglProc("eglQueryDeviceStringEXT"));
  std::string what;
  if (str) {
    const char* ext = str(dev, EGL_EXTENSIONS);
    if (hasExtension(ext, "EGL_EXT_device_drm_render_node")) {
      const char* f = str(dev, EGL_DRM_RENDER_NODE_FILE_EXT);
      if (f) what = f;
    }
    if (what.empty() && hasExtension(ext, "EGL_EXT_device_drm")) {
      const char* f = str(dev, EGL_DRM_DEVICE_FILE_EXT);
      if (f) what = f;
    }
    if (what.empty() && ext) what = ext;
  }
  return "EGL device " + std::to_string(index) + (what.empty() ? "" : " (" + what + ")");
}

struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string name;
};

// An initialised display for `device` (−1: the default, see context.h).
// Displays stay initialised for the life of the process: eglTerminate would
// pull them from under contexts on other threads. Call with gEglMutex held.
Result<Display> openDisplay(int device) {
  static std::map<int, Display> cache;
  if (auto it = cache.find(device); it != cache.end()) return it->second;
  const int asked = device;
  const char* ext = clientExtensions();
  if (!ext)
    return makeError("cannot use EGL: the EGL library has no client extensions (need EGL 1.5 "
                     "with EGL_EXT_platform_base; install libegl1 and a driver: libegl-mesa0 "
                     "for Mesa/llvmpipe, or the GPU vendor's; docs/gpu.md)");
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglProc("eglGetPlatformDisplayEXT"));
  Display d;
  // The default: the first hardware device (not Mesa's software one), so a
  // GPU that only its vendor's library drives (NVIDIA) wins over Mesa's
  // surfaceless platform, which would give llvmpipe there; without one, the
  // surfaceless platform; else device 0.
  if (device < 0 && hasExtension(ext, "EGL_EXT_platform_device")) {
    if (auto list = devices()) {
      auto str =
          reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglProc("eglQueryDeviceStringEXT"));
      for (size_t i = 0; str && i < list->size(); ++i)
        if (!hasExtension(str((*list)[i], EGL_EXTENSIONS), "EGL_MESA_device_software")) {
          device = static_cast<int>(i);
          break;
        }
    }
  }
  if (device >= 0 || !hasExtension(ext, "EGL_MESA_platform_surfaceless")) {
    auto list = devices();
    if (!list) {
      if (device >= 0)
        return makeError("--gl-device " + std::to_string(device) + ": " + list.error().message);
      return makeError("cannot open an EGL display: no EGL_MESA_platform_surfaceless and " +
                       list.error().message +
                       " (install libegl-mesa0 for Mesa/llvmpipe, or the GPU vendor's EGL "
                       "library; docs/gpu.md)");
    }
    const int n = static_cast<int>(list->size());
    const int index = device >= 0 ? device : 0;
    if (index >= n)
      return makeError("EGL device " + std::to_string(index) + " does not exist: this machine has " +
                       std::to_string(n) + " EGL device" + (n == 1 ? "" : "s") +
                       (n > 0 ? " (0.." + std::to_string(n - 1) + ")" : "") +
                       "; list them with `hybridwalk info`");
    if (!hasExtension(ext, "EGL_EXT_platform_device") || !getPlatformDisplay)
      return makeError("cannot open an EGL device: the EGL library lacks EGL_EXT_platform_device");
    d.name = deviceName((*list)[static_cast<size_t>(index)], index);
    d.display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, (*list)[static_cast<size_t>(index)],
                                   nullptr);
  } else {
    d.name = "EGL surfaceless platform";
    if (!getPlatformDisplay)
      return makeError("cannot open an EGL display: the EGL library has no eglGetPlatformDisplayEXT");
    d.display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  }
  if (d.display == EGL_NO_DISPLAY)
    return makeError("cannot open the " + d.name + ": " + eglErrorName(eglGetError()) +
                     " (install libegl-mesa0 for Mesa/llvmpipe, or the GPU vendor's EGL "
                     "library; docs/gpu.md)");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(d.display, &major, &minor))
    return makeError("cannot initialise the " + d.name + ": " + eglErrorName(eglGetError()) +
                     " (is the driver installed and /dev/dri readable? docs/gpu.md)");
  cache[asked] = d;
  return d;
}

class EglContext final : public Context {
 public:
  EglContext(EGLDisplay display, EGLContext ctx) : display_(display), ctx_(ctx) {
    backend_ = "egl";
  }
  ~EglContext() override {
    if (eglGetCurrentContext() == ctx_)
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, ctx_);
  }
  void makeCurrent() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_); }
  // Read through eglGetProcAddress, so a probe leaves the table alone.
  void readStrings() {
    auto getString = reinterpret_cast<PFNGLGETSTRINGPROC>(eglProc("glGetString"));
    auto str = [&](GLenum e) {
      const GLubyte* s = getString ? getString(e) : nullptr;
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    vendor_ = str(GL_VENDOR);
    renderer_ = str(GL_RENDERER);
    version_ = str(GL_VERSION);
  }

 private:
  EGLDisplay display_;
  EGLContext ctx_;
};

// A 4.5 core context on `device`, current on the calling thread. Call with
// gEglMutex held.
Result<std::unique_ptr<EglContext>> createCurrent(int device) {
  auto d = openDisplay(device);
  if (!d) return d.error();
  if (!eglBindAPI(EGL_OPENGL_API))
    return makeError("the " + d->name + " does not offer desktop OpenGL (eglBindAPI(EGL_OPENGL_API): " +
                     eglErrorName(eglGetError()) + "); " + kTryOther);
  const char* ext = eglQueryString(d->display, EGL_EXTENSIONS);
  // Rendering goes to FBOs, so no config is needed where the driver allows
  // it (Mesa's surfaceless platform offers no config with EGL_OPENGL_BIT);
  // otherwise any OpenGL-renderable one.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(ext, "EGL_KHR_no_config_context")) {
    const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(d->display, want, &config, 1, &n) || n < 1)
      return makeError("the " + d->name + " has no OpenGL config and lacks "
                       "EGL_KHR_no_config_context; " + kTryOther);
  }
  if (!hasExtension(ext, "EGL_KHR_surfaceless_context"))
    return makeError("the " + d->name + " lacks EGL_KHR_surfaceless_context (needed to render "
                     "without a window); " + kTryOther);
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4,
                            EGL_CONTEXT_MINOR_VERSION, 5,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                            EGL_NONE};
  EGLContext ctx = eglCreateContext(d->display, config, EGL_NO_CONTEXT, attribs);
  if (ctx == EGL_NO_CONTEXT)
    return makeError("the " + d->name + " refused an OpenGL 4.5 core context (" +
                     eglErrorName(eglGetError()) +
                     "): the driver offers less; update it, or " + kTryOther);
  auto context = std::make_unique<EglContext>(d->display, ctx);
  if (!eglMakeCurrent(d->display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
    return makeError("cannot make the OpenGL context of the " + d->name + " current without a "
                     "surface (" + eglErrorName(eglGetError()) + ")");
  context->readStrings();
  return context;
}

}  // namespace

Result<std::unique_ptr<Context>> createEglContext(int device, bool second) {
  if (forcedFailure())
    return makeError("cannot create an EGL OpenGL context: HW_GL_FAIL=1 is set");
  std::lock_guard lock(gEglMutex);
  auto context = createCurrent(device);
  if (!context) return context.error();
  // EGL (glvnd's libEGL and the vendors') hands out dispatch stubs that call
  // into the context current on the calling thread, so one table serves every
  // context. A second context checks that on its own thread, entry by entry,
  // instead of refilling the table under the thread that uses it.
  std::string differ;
#define HW_GL_COMPARE(type, name)                                      \
  if (reinterpret_cast<void*>(hwgl::name) != eglProc(#name))          \
    differ += std::string(differ.empty() ? "" : ", ") + #name;
  HW_GL_FUNCTIONS(HW_GL_COMPARE)
#undef HW_GL_COMPARE
  if (second && !differ.empty()) {
    eglMakeCurrent(eglGetCurrentDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    return makeError("cannot create a second EGL context for a worker thread: the GL entry points "
                     "loaded for the first context differ from this thread's (" + differ +
                     "); create the first context with createHeadlessContext()");
  }
  if (!differ.empty()) HW_TRY(loadGlFunctions(&eglProc));
  return std::unique_ptr<Context>(std::move(*context));
}

std::vector<BackendProbe> probeEgl() {
  std::vector<BackendProbe> out;
  std::lock_guard lock(gEglMutex);
  // The caller's current EGL context (if any) is current again afterwards.
  const EGLDisplay prevDisplay = eglGetCurrentDisplay();
  const EGLContext prevContext = eglGetCurrentContext();
  auto probe = [&](int device, const std::string& fallbackName) {
    BackendProbe p;
    p.backend = Backend::Egl;
    p.eglDevice = device;
    auto d = openDisplay(device);
    p.name = d ? d->name : fallbackName;
    auto c = createCurrent(device);
    if (c) {
      p.core45 = true;
      p.vendor = (*c)->vendor();
      p.renderer = (*c)->renderer();
      p.version = (*c)->version();
    } else {
      p.error = c.error().message;
    }
    out.push_back(p);
  };
  probe(-1, "EGL default display");
  auto list = devices();
  if (list)
    for (size_t i = 0; i < list->size(); ++i)
      probe(static_cast<int>(i), "EGL device " + std::to_string(i));
  if (prevContext != EGL_NO_CONTEXT)
    eglMakeCurrent(prevDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, prevContext);
  return out;
}

}  // namespace hw::gl::detail

#endif  // HW_HAVE_EGL
