#pragma once
// A linked GLSL program (RAII). Compile/link failures are returned as errors
// carrying the shader's name and the driver's log.
#include <string>

#include "core/result.h"

namespace hw::gl {

// A vertex shader drawing one triangle that covers the viewport (glDrawArrays
// of 3 vertices, no attributes), for full-screen passes.
inline constexpr const char* kFullScreenTriangleVertex = R"(#version 450 core
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

class Program {
 public:
  Program() = default;
  ~Program();
  Program(Program&& o) noexcept : id_(o.id_) { o.id_ = 0; }
  Program& operator=(Program&& o) noexcept;
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  static Result<Program> build(const std::string& name, const char* vertexSrc,
                               const char* fragmentSrc);
  unsigned id() const { return id_; }
  void use() const;
  int uniform(const char* name) const;  // -1 when absent (optimised away)

 private:
  unsigned id_ = 0;
};

}  // namespace hw::gl
