#include "core/gl/gl_api.h"

#include <string>

namespace hwgl {
#define HW_GL_DEFINE(type, name) type name = nullptr;
HW_GL_FUNCTIONS(HW_GL_DEFINE)
#undef HW_GL_DEFINE
}  // namespace hwgl

namespace hw::gl {

Status loadGlFunctions(GetProcAddress getProc) {
  std::string missing;
#define HW_GL_LOAD(type, name)                                  \
  hwgl::name = reinterpret_cast<type>(getProc(#name));          \
  if (!hwgl::name) missing += std::string(missing.empty() ? "" : ", ") + #name;
  HW_GL_FUNCTIONS(HW_GL_LOAD)
#undef HW_GL_LOAD
  if (!missing.empty())
    return makeError("OpenGL context lacks required entry points: " + missing +
                     " (need OpenGL 4.5 core)");
  return {};
}

Status checkGlError(const char* where) {
  std::string errs;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%04x", e);
    errs += std::string(errs.empty() ? "" : " ") + buf;
  }
  if (errs.empty()) return {};
  return makeError(std::string("OpenGL error in ") + where + ": " + errs);
}

}  // namespace hw::gl
