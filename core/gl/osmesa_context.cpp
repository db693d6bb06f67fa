// OSMesa context. Only this file includes GL/osmesa.h (which pulls in the
// prototypes of GL/gl.h); everything else goes through gl_api.h.
#ifdef HW_HAVE_OSMESA

#include <GL/osmesa.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include "core/gl/context.h"
#include "core/gl/headless_backends.h"

// The entry-point table's glGetString (core/gl/gl_api.h, not included here:
// its glcorearb.h would meet osmesa.h's gl.h).
namespace hwgl {
extern decltype(&::glGetString) glGetString;
}

namespace hw::gl {
Status loadGlFunctions(void* (*getProc)(const char*));
}

namespace hw::gl::detail {
namespace {

using GetStringFn = const GLubyte* (*)(GLenum);

class OsMesaContext final : public Context {
 public:
  explicit OsMesaContext(OSMesaContext ctx) : ctx_(ctx), buffer_(kSize * kSize * 4) {
    backend_ = "osmesa";
  }
  ~OsMesaContext() override { OSMesaDestroyContext(ctx_); }
  void makeCurrent() override {
    OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize);
  }
  bool init() {
    if (!OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize)) return false;
    auto getString = reinterpret_cast<GetStringFn>(OSMesaGetProcAddress("glGetString"));
    if (!getString) return false;
    auto str = [&](GLenum e) {
      const GLubyte* s = getString(e);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    vendor_ = str(GL_VENDOR);
    renderer_ = str(GL_RENDERER);
    version_ = str(GL_VERSION);
    return true;
  }

 private:
  static constexpr int kSize = 16;
  OSMesaContext ctx_;
  std::vector<unsigned char> buffer_;
};

void* osmesaProc(const char* name) {
  return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

const int kAttribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                        OSMESA_DEPTH_BITS, 24,
                        OSMESA_STENCIL_BITS, 0,
                        OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                        OSMESA_CONTEXT_MAJOR_VERSION, 4,
                        OSMESA_CONTEXT_MINOR_VERSION, 5,
                        0};

// One context per thread may be created concurrently with GL calls on
// another (the keyframe worker): the creation itself is serialised.
std::mutex gCreationMutex;

constexpr const char* kCannotCreate =
    "cannot create an OSMesa OpenGL 4.5 core context (expected Mesa >= 20 with llvmpipe; "
    "install libosmesa6, and check GALLIUM_DRIVER/LIBGL_ALWAYS_SOFTWARE are not set to an "
    "unavailable driver)";

}  // namespace

Result<std::unique_ptr<Context>> createOsMesaContext(bool second) {
  if (forcedFailure())
    return makeError("cannot create an OSMesa OpenGL context: HW_GL_FAIL=1 is set");
  std::lock_guard lock(gCreationMutex);
  OSMesaContext ctx = OSMesaCreateContextAttribs(kAttribs, nullptr);
  if (!ctx) return makeError(kCannotCreate);
  auto context = std::make_unique<OsMesaContext>(ctx);
  if (!context->init()) return makeError("cannot make the OSMesa context current");
  // OSMesaGetProcAddress hands out Mesa's dispatch stubs, which are the same
  // for every context and call into the context current on the calling
  // thread (checked: equal pointers from two contexts on two threads). So a
  // table already filled from OSMesa serves a second context as it is, and is
  // not rewritten while another thread may be calling through it.
  const bool tableFromOsMesa =
      reinterpret_cast<void*>(hwgl::glGetString) == osmesaProc("glGetString");
  if (second && !tableFromOsMesa) {
    // Refilling it would pull the table from under the thread that uses it.
    return makeError(
        "cannot create a second OSMesa context for a worker thread: the GL entry points were "
        "loaded from another kind of context (a GLFW window or EGL); create the first context "
        "with createHeadlessContext()");
  }
  if (!tableFromOsMesa) HW_TRY(loadGlFunctions(&osmesaProc));
  return std::unique_ptr<Context>(std::move(context));
}

BackendProbe probeOsMesa() {
  BackendProbe p;
  p.backend = Backend::OsMesa;
  p.name = "OSMesa";
  std::lock_guard lock(gCreationMutex);
  OSMesaContext ctx = OSMesaCreateContextAttribs(kAttribs, nullptr);
  if (!ctx) {
    p.error = kCannotCreate;
    return p;
  }
  {
    OsMesaContext context(ctx);  // destroys ctx
    if (context.init()) {
      p.core45 = true;
      p.vendor = context.vendor();
      p.renderer = context.renderer();
      p.version = context.version();
      OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    } else {
      p.error = "cannot make the OSMesa context current";
    }
  }
  return p;
}

}  // namespace hw::gl::detail

#endif  // HW_HAVE_OSMESA
