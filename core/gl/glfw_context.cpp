#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "core/gl/context.h"
#include "core/gl/gl_api.h"

namespace hw::gl {
namespace {

std::string lastGlfwError() {
  const char* desc = nullptr;
  glfwGetError(&desc);
  return desc ? desc : "unknown GLFW error";
}

void* glfwProc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

class GlfwContext final : public WindowContext {
 public:
  explicit GlfwContext(GLFWwindow* w) : window_(w) { backend_ = "glfw"; }
  ~GlfwContext() override {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  void makeCurrent() override { glfwMakeContextCurrent(window_); }
  GLFWwindow* window() override { return window_; }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  bool shouldClose() override { return glfwWindowShouldClose(window_); }
  void pollEvents() override { glfwPollEvents(); }
  void setStrings() {
    vendor_ = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
    renderer_ = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    version_ = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  }

 private:
  GLFWwindow* window_;
};

// The worker's hidden window: owned by the main thread, which destroys it;
// GLFW stays initialised for the main window (no glfwTerminate here).
class HiddenWindowContext final : public WindowContext {
 public:
  explicit HiddenWindowContext(GLFWwindow* w) : window_(w) { backend_ = "glfw"; }
  ~HiddenWindowContext() override { glfwDestroyWindow(window_); }
  void makeCurrent() override { glfwMakeContextCurrent(window_); }
  GLFWwindow* window() override { return window_; }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  bool shouldClose() override { return glfwWindowShouldClose(window_); }
  void pollEvents() override {}  // events are the main window's business
  void setStrings(const std::string& vendor, const std::string& renderer,
                  const std::string& version) {
    vendor_ = vendor;
    renderer_ = renderer;
    version_ = version;
  }

 private:
  GLFWwindow* window_;
};

// A window's context made current on a worker thread; destroyed there, it
// detaches the context from that thread (glfwMakeContextCurrent may be called
// from any thread), so the main thread may destroy the window afterwards.
class AttachedContext final : public Context {
 public:
  explicit AttachedContext(WindowContext& w) : window_(w) {
    backend_ = w.backend();
    vendor_ = w.vendor();
    renderer_ = w.renderer();
    version_ = w.version();
  }
  ~AttachedContext() override { glfwMakeContextCurrent(nullptr); }
  void makeCurrent() override { window_.makeCurrent(); }

 private:
  WindowContext& window_;
};

std::string glString(GLenum e) {
  const GLubyte* s = glGetString(e);
  return s ? reinterpret_cast<const char*>(s) : "?";
}

}  // namespace

Result<std::unique_ptr<WindowContext>> createSecondWindowContext(WindowContext& main) {
  const char* fail = std::getenv("HW_GL_FAIL_SECOND");
  if (fail && std::strcmp(fail, "1") == 0)
    return makeError("cannot create a hidden window for a second OpenGL context: "
                     "HW_GL_FAIL_SECOND=1 is set");
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow* w = glfwCreateWindow(16, 16, "hybridwalk worker", nullptr, /*share=*/nullptr);
  glfwDefaultWindowHints();
  if (!w) {
    const std::string err = lastGlfwError();
    main.makeCurrent();
    return makeError("cannot create a hidden window with an OpenGL 4.5 core context for a "
                     "second context: " + err);
  }
  auto ctx = std::make_unique<HiddenWindowContext>(w);
  // Its strings, read through the table (checked per entry on the worker).
  ctx->makeCurrent();
  ctx->setStrings(glString(GL_VENDOR), glString(GL_RENDERER), glString(GL_VERSION));
  main.makeCurrent();
  return std::unique_ptr<WindowContext>(std::move(ctx));
}

Result<std::unique_ptr<Context>> attachWindowContext(WindowContext& second) {
  second.makeCurrent();
  if (glfwGetCurrentContext() != second.window())
    return makeError("cannot make the second window's OpenGL context current on this thread: " +
                     lastGlfwError());
  std::string differ;
#define HW_GL_COMPARE(type, name)                                                      \
  if (reinterpret_cast<void*>(hwgl::name) != glfwProc(#name))                         \
    differ += std::string(differ.empty() ? "" : ", ") + #name;
  HW_GL_FUNCTIONS(HW_GL_COMPARE)
#undef HW_GL_COMPARE
  if (!differ.empty()) {
    glfwMakeContextCurrent(nullptr);
    return makeError("the OpenGL entry points of the second window's context differ from the "
                     "table loaded for the main window (" + differ +
                     "): the library does not hand out per-thread dispatch stubs, so the table "
                     "cannot serve both contexts");
  }
  return std::unique_ptr<Context>(std::make_unique<AttachedContext>(second));
}

Result<std::unique_ptr<WindowContext>> createWindowContext(int width, int height,
                                                           const std::string& title,
                                                           bool visible) {
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
    return makeError("cannot open a window: no DISPLAY is set (run under xvfb-run, or use the "
                     "headless commands)");
  if (!glfwInit()) return makeError("cannot initialise GLFW: " + lastGlfwError());
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* w = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!w) {
    std::string err = lastGlfwError();
    glfwTerminate();
    return makeError("cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                     " window with an OpenGL 4.5 core context: " + err);
  }
  auto ctx = std::make_unique<GlfwContext>(w);
  ctx->makeCurrent();
  HW_TRY(loadGlFunctions(&glfwProc));
  ctx->setStrings();
  return std::unique_ptr<WindowContext>(std::move(ctx));
}

}  // namespace hw::gl
