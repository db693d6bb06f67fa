// The API's GL pieces (api/gl/glue.h).
#include "api/gl/glue.h"

#include "core/gl/gl_api.h"
#include "core/gl/shader.h"

namespace hybridwalk::detail {
namespace {

const char* kVs = R"(#version 450 core
out vec2 vUv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  vUv = vec2(p.x, 1.0 - p.y);  // texture row 0 is the frame's top row
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";
const char* kFs = R"(#version 450 core
in vec2 vUv;
uniform sampler2D frameTex;
out vec4 outColour;
void main() { outColour = vec4(texture(frameTex, vUv).rgb, 1.0); })";

class GlPresenter final : public Presenter {
 public:
  ~GlPresenter() override {
    if (tex_) glDeleteTextures(1, &tex_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
  }
  hw::Status init() {
    auto p = hw::gl::Program::build("present", kVs, kFs);
    if (!p) return p.error();
    program_ = std::move(*p);
    glGenVertexArrays(1, &vao_);
    glGenTextures(1, &tex_);
    glBindTexture(GL_TEXTURE_2D, tex_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return hw::gl::checkGlError("present: set-up");
  }
  hw::Status draw(const std::uint8_t* rgba, int width, int height, int viewportWidth,
                  int viewportHeight) override {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, viewportWidth, viewportHeight);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    if (width != texW_ || height != texH_) {
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
      texW_ = width;
      texH_ = height;
    } else {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    }
    program_.use();
    glUniform1i(program_.uniform("frameTex"), 0);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    return hw::gl::checkGlError("present");
  }

 private:
  hw::gl::Program program_;
  unsigned vao_ = 0, tex_ = 0;
  int texW_ = 0, texH_ = 0;
};

}  // namespace

hw::Result<std::string> adoptCurrentContext(void* (*getProc)(const char*)) {
  if (!getProc)
    return hw::makeError(
        "renderer: ContextKind::Current needs RendererDesc::getProcAddress (e.g. "
        "glfwGetProcAddress), got null");
  HW_TRY(hw::gl::loadGlFunctions(getProc));
  const GLubyte* r = glGetString(GL_RENDERER);
  if (!r)
    return hw::makeError(
        "renderer: ContextKind::Current: no OpenGL context is current on this thread (make "
        "an OpenGL 4.5 core context current first)");
  return std::string(reinterpret_cast<const char*>(r));
}

hw::Result<std::unique_ptr<Presenter>> Presenter::create() {
  auto p = std::make_unique<GlPresenter>();
  HW_TRY(p->init());
  return std::unique_ptr<Presenter>(std::move(p));
}

}  // namespace hybridwalk::detail
