// hybridwalk in your own GLFW window: the library borrows the window's
// OpenGL context, renders each frame the hybrid way at a camera that walks
// around the built-in indoor scene, and draws it into the window.
// `embed_glfw [FRAMES [SCREENSHOT.ppm]]`: after FRAMES frames (0 = until
// closed) the window is read back, written as a PPM if asked, and compared
// with the library's last frame; exit 1 if they differ.
#include <GLFW/glfw3.h>  // with GL/gl.h for the types and enums
#include <hybridwalk/hybridwalk.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace hybridwalk;

int fail(const char* what) { return std::fprintf(stderr, "embed_glfw: %s\n", what), 1; }

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::atoi(argv[1]) : 0;
  const char* screenshot = argc > 2 ? argv[2] : nullptr;
  if (!glfwInit()) return fail("cannot initialise GLFW (no display? try xvfb-run)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);  // the library needs 4.5 core
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(640, 480, "hybridwalk embedded", nullptr, nullptr);
  if (!window) return glfwTerminate(), fail("cannot open a window with OpenGL 4.5 core");
  glfwMakeContextCurrent(window);
  int status = 0;
  {
    auto scene = Scene::load("indoor");
    if (!scene) return fail(scene.error().message.c_str());
    RendererDesc desc;
    desc.context = ContextKind::Current;
    desc.getProcAddress = reinterpret_cast<GetProcAddress>(glfwGetProcAddress);
    auto renderer = Renderer::create(*scene, desc);
    if (!renderer) return fail(renderer.error().message.c_str());
    auto home = scene->defaultPath();  // the scene's own walk: start where it starts
    if (!home) return fail(home.error().message.c_str());
    const Camera start = home->cameras.front();
    Frame frame;
    for (int i = 0; !glfwWindowShouldClose(window) && (frames == 0 || i < frames); ++i) {
      int w = 0, h = 0;
      glfwGetFramebufferSize(window, &w, &h);
      // Turn slowly on the spot, drifting forward.
      const double a = 0.01 * i;
      const Vec3 f = start.forward,
                 eye{start.eye.x + 0.02 * i * f.x, start.eye.y, start.eye.z + 0.02 * i * f.z};
      const Vec3 look{eye.x + f.x * std::cos(a) - f.z * std::sin(a), eye.y + f.y,
                      eye.z + f.z * std::cos(a) + f.x * std::sin(a)};
      auto cam = Camera::lookAt(eye, look, {0, 1, 0}, start.fovYRadians, w, h, start.nearPlane,
                                start.farPlane);
      if (!cam) return fail(cam.error().message.c_str());
      if (auto st = renderer->render(*cam, frame); !st) return fail(st.error().message.c_str());
      if (auto st = renderer->present(frame, w, h); !st) return fail(st.error().message.c_str());
      if (frames > 0 && i == frames - 1) {  // read back what the window shows
        auto readPixels =
            reinterpret_cast<void (*)(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*)>(
                glfwGetProcAddress("glReadPixels"));
        std::vector<unsigned char> shot(static_cast<std::size_t>(w) * h * 4);
        readPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, shot.data());
        long long differ = 0, varied = 0;  // window rows run bottom-up, frame rows top-down
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w * 4; ++x) {
            const unsigned char v = shot[static_cast<std::size_t>((h - 1 - y) * w * 4 + x)];
            differ += x % 4 != 3 && v != frame.rgba[static_cast<std::size_t>(y * w * 4 + x)];
            varied += v != shot[static_cast<std::size_t>(x % 4)];
          }
        std::printf("frame %d: %s, %d quads, %.2f ms; window %dx%d, %lld channel values differ\n",
                    i, frame.stats.kind == FrameKind::Warped ? "warped" : "keyframe",
                    frame.stats.quads, frame.stats.totalMs, w, h, differ);
        if (screenshot) {
          if (FILE* out = std::fopen(screenshot, "wb")) {
            std::fprintf(out, "P6 %d %d 255\n", w, h);
            for (int y = h - 1; y >= 0; --y)
              for (int x = 0; x < w; ++x)
                std::fwrite(&shot[static_cast<std::size_t>((y * w + x) * 4)], 1, 3, out);
            std::fclose(out);
          }
        }
        status = differ == 0 && varied > 0 ? 0 : 1;  // the frame, and not one flat colour
      }
      glfwSwapBuffers(window);
      glfwPollEvents();
    }
  }  // the renderer goes while its context is current
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}
