#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>
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
  explicit GlfwContext(GLFWwindow* w) : window_(w) {}
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
    renderer_ = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    version_ = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  }

 private:
  GLFWwindow* window_;
};

}  // namespace

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
