#pragma once
// One OpenGL 4.5 core context interface, two implementations: OSMesa
// (headless, llvmpipe; the default everywhere) and a GLFW window. Creating
// one loads the GL entry-point table (gl_api.h) from it. No GL headers here.
#include <memory>
#include <string>

#include "core/result.h"

struct GLFWwindow;

namespace hw::gl {

// OpenGL error accounting for callers outside gl/ folders (issue #7: a walk
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

}  // namespace hw::gl
