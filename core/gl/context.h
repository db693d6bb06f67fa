#pragma once
// One OpenGL 4.5 core context interface, two implementations: OSMesa
// (headless, llvmpipe; the default everywhere) and a GLFW window. Creating
// one loads the GL entry-point table (gl_api.h) from it. No GL headers here.
#include <memory>
#include <string>

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
  // GL_RENDERER and GL_VERSION strings of this context.
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }

 protected:
  std::string renderer_, version_;
};

// OSMesa core-profile 4.5 context. Rendering goes to framebuffer objects; the
// context's own buffer is a tiny placeholder. Error if Mesa cannot create it
// (message says what to install or set). HW_GL_FAIL=1 in the environment makes
// creation fail on purpose (to test that callers report it).
Result<std::unique_ptr<Context>> createHeadlessContext();

// Another OSMesa context, to be made current on another thread (e.g. the
// keyframe worker) while the first one stays in use. OSMesa's entry points
// are per-thread dispatch stubs, so the table loaded for the first context
// serves it unchanged; error when that table came from a GLFW window instead
// (it would have to be refilled under the thread using it). Creation is
// serialised with other context creations; the context belongs to the
// thread that created it.
Result<std::unique_ptr<Context>> createSecondHeadlessContext();

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
