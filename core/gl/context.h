#pragma once
// One OpenGL 4.5 core context interface, three implementations: headless
// EGL (any driver: Mesa's surfaceless platform on llvmpipe, or a GPU picked by
// EGL_EXT_platform_device), headless OSMesa (llvmpipe), and a GLFW window.
// Creating one loads the GL entry-point table (gl_api.h) from it. No GL
// headers here.
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"

struct GLFWwindow;

namespace hw::gl {

// OpenGL error accounting for callers outside gl/ folders (a walk
// counts errors per frame). Both need a current context.
// Drains glGetError and returns how many errors were pending (0: none).
int drainGlErrors();
// GL_DEBUG_TYPE_ERROR messages the KHR_debug callback has seen in this
// process, or −1 when no callback is installed (release builds without
// HW_GL_DEBUG=1; see loadGlFunctions in gl_api.h).
long long debugCallbackErrors();

class Context {
 public:
  virtual ~Context() = default;
  virtual void makeCurrent() = 0;
  // "egl", "osmesa" or "glfw", and the GL_VENDOR, GL_RENDERER and GL_VERSION
  // strings of this context.
  const std::string& backend() const { return backend_; }
  const std::string& vendor() const { return vendor_; }
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }

 protected:
  std::string backend_, vendor_, renderer_, version_;
};

// Which library a headless context comes from. Auto: EGL when it gives a 4.5
// core context, OSMesa otherwise.
enum class Backend { Auto, Egl, OsMesa };
const char* backendName(Backend b);                   // "auto", "egl", "osmesa"
bool parseBackend(const std::string& s, Backend* out);  // false: not one of those
// Whether this build has the backend (HW_WITH_EGL / HW_WITH_OSMESA at
// configure time; Auto: always).
bool backendBuilt(Backend b);

struct HeadlessOptions {
  Backend backend = Backend::Auto;
  // Index into the EGL devices (eglQueryDevicesEXT, EGL_EXT_platform_device);
  // −1: the first hardware device (not EGL_MESA_device_software); without
  // one, Mesa's surfaceless platform (llvmpipe) when the EGL library has it,
  // else device 0. Only EGL.
  int eglDevice = -1;
};
// The process-wide choice createHeadlessContext() uses: starts as
// HYBRIDWALK_GL from the environment (auto|egl|osmesa; unset = auto), set by
// the CLI's --gl and --gl-device. A bad HYBRIDWALK_GL is reported by
// createHeadlessContext.
HeadlessOptions headlessOptions();
void setHeadlessOptions(const HeadlessOptions& o);

// A headless core-profile 4.5 context from the backend `o` asks for.
// Rendering goes to framebuffer objects (EGL: no surface at all; OSMesa: a
// tiny placeholder buffer). Error if it cannot be created (one line: what was
// tried, what to install or set). HW_GL_FAIL=1 in the environment makes
// creation fail on purpose for every backend (to test that callers report it).
Result<std::unique_ptr<Context>> createHeadlessContext(const HeadlessOptions& o);
Result<std::unique_ptr<Context>> createHeadlessContext();  // with headlessOptions()

// Another headless context of the same backend (and EGL device) as the last
// first one, to be made current on another thread (e.g. the keyframe worker)
// while the first one stays in use. Both libraries hand out dispatch stubs
// that call into the context current on the calling thread, so the table
// loaded for the first context serves it unchanged (EGL: checked entry by
// entry on the calling thread); error when that table came from a GLFW window
// or another backend (it would have to be refilled under the thread using
// it). Creation is serialised with other context creations; the context
// belongs to the thread that created it.
Result<std::unique_ptr<Context>> createSecondHeadlessContext();

// Backend, GL_VENDOR, GL_RENDERER, GL_VERSION of the last first headless
// context created in this process (all empty before one): what a report's
// machine block records.
struct ContextStrings {
  std::string backend, vendor, renderer, version;
};
ContextStrings lastHeadlessContextStrings();

// What `hybridwalk info` lists: one entry per way to get a headless context
// on this machine (OSMesa; EGL's surfaceless platform; each EGL device),
// each tried by creating a 4.5 core context and reading its strings.
struct BackendProbe {
  Backend backend = Backend::Egl;
  int eglDevice = -1;   // −1: not a device (OSMesa, or EGL's default display)
  std::string name;     // e.g. "EGL device 0 (EGL_MESA_device_software)"
  std::string vendor, renderer, version;
  bool core45 = false;  // a 4.5 core context was created and made current
  std::string error;    // why not, when !core45
};
std::vector<BackendProbe> probeHeadlessBackends();


class WindowContext : public Context {
 public:
  virtual GLFWwindow* window() = 0;
  virtual void swapBuffers() = 0;
  virtual bool shouldClose() = 0;
  virtual void pollEvents() = 0;
};

// A GLFW window with a 4.5 core context. Error when there is no display
// (set DISPLAY, or run under xvfb-run) or the context cannot be created.
Result<std::unique_ptr<WindowContext>> createWindowContext(int width, int height,
                                                           const std::string& title,
                                                           bool visible = true);

// A second context for a worker thread when the main one is a GLFW window
// (the viewer's keyframe worker): a hidden 16x16 window
// (GLFW_VISIBLE false) with its own 4.5 core context, sharing nothing with
// `main` (no GL object crosses contexts). Call on the main thread with `main`
// current (GLFW creates and destroys windows only there); `main` is current
// again on return. Destroy it on the main thread too, after the worker has let
// go of it (attachWindowContext's handle destroyed). HW_GL_FAIL_SECOND=1 in the
// environment makes creation fail on purpose (to test that callers report it).
Result<std::unique_ptr<WindowContext>> createSecondWindowContext(WindowContext& main);

// Worker side: makes `second` (from createSecondWindowContext) current on the
// calling thread and returns a handle whose destruction detaches it from that
// thread again; the handle does not own the window. The entry-point table
// loaded for the main window serves this context unchanged: GLX/GLVND's
// glXGetProcAddress (behind glfwGetProcAddress) hands out the same dispatch
// stubs for every context, and they call into the context current on the
// calling thread. Checked here for every table entry (the pointers this
// thread's glfwGetProcAddress returns must equal the table's); an error names
// the ones that differ instead of refilling the table under the main thread.
Result<std::unique_ptr<Context>> attachWindowContext(WindowContext& second);

}  // namespace hw::gl
