#include "core/gl/shader.h"

#include <vector>

#include "core/gl/gl_api.h"

namespace hw::gl {

Program::~Program() {
  if (id_) glDeleteProgram(id_);
}

Program& Program::operator=(Program&& o) noexcept {
  if (this != &o) {
    if (id_) glDeleteProgram(id_);
    id_ = o.id_;
    o.id_ = 0;
  }
  return *this;
}

static Result<GLuint> compile(const std::string& name, GLenum type, const char* src) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    std::vector<char> log(static_cast<size_t>(len > 1 ? len : 1), '\0');
    glGetShaderInfoLog(s, len, nullptr, log.data());
    glDeleteShader(s);
    return makeError("shader " + name + (type == GL_VERTEX_SHADER ? " (vertex)" : " (fragment)") +
                     " failed to compile: " + log.data());
  }
  return s;
}

Result<Program> Program::build(const std::string& name, const char* vertexSrc,
                               const char* fragmentSrc) {
  auto vs = compile(name, GL_VERTEX_SHADER, vertexSrc);
  if (!vs) return vs.error();
  auto fs = compile(name, GL_FRAGMENT_SHADER, fragmentSrc);
  if (!fs) {
    glDeleteShader(*vs);
    return fs.error();
  }
  Program p;
  p.id_ = glCreateProgram();
  glAttachShader(p.id_, *vs);
  glAttachShader(p.id_, *fs);
  glLinkProgram(p.id_);
  glDeleteShader(*vs);
  glDeleteShader(*fs);
  GLint ok = 0;
  glGetProgramiv(p.id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(p.id_, GL_INFO_LOG_LENGTH, &len);
    std::vector<char> log(static_cast<size_t>(len > 1 ? len : 1), '\0');
    glGetProgramInfoLog(p.id_, len, nullptr, log.data());
    return makeError("shader program " + name + " failed to link: " + log.data());
  }
  return p;
}

void Program::use() const { glUseProgram(id_); }
int Program::uniform(const char* name) const { return glGetUniformLocation(id_, name); }

}  // namespace hw::gl
