#include "core/gl/gl_api.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/gl/context.h"

namespace hwgl {
#define HW_GL_DEFINE(type, name) type name = nullptr;
HW_GL_FUNCTIONS(HW_GL_DEFINE)
#undef HW_GL_DEFINE
}  // namespace hwgl

namespace hw::gl {
namespace {

std::atomic<long long> gDebugErrors{0};
std::atomic<bool> gDebugInstalled{false};
constexpr long long kDebugMessagesPrinted = 5;

void APIENTRY debugCallback(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei,
                              const GLchar* message, const void*) {
  if (type != GL_DEBUG_TYPE_ERROR) return;
  const long long n = ++gDebugErrors;
  if (n <= kDebugMessagesPrinted)
    std::fprintf(stderr, "hybridwalk: OpenGL debug: error id %u severity 0x%04x: %s%s\n", id,
                 severity, message ? message : "?",
                 n == kDebugMessagesPrinted ? " (further errors only counted)" : "");
}

}  // namespace

void installDebugCallback() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // on the calling thread, during the bad call
  glDebugMessageCallback(&debugCallback, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  gDebugInstalled = true;
}

long long debugCallbackErrors() { return gDebugInstalled ? gDebugErrors.load() : -1; }

int drainGlErrors() {
  int n = 0;
  // Bounded: a lost context may report GL_CONTEXT_LOST forever.
  while (n < 1000 && glGetError() != GL_NO_ERROR) ++n;
  return n;
}

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
#ifdef NDEBUG
  const char* debug = std::getenv("HW_GL_DEBUG");
  if (debug && std::strcmp(debug, "1") == 0) installDebugCallback();
#else
  installDebugCallback();
#endif
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
    if (e == GL_OUT_OF_MEMORY) errs += " (out of memory; --max-memory refuses such input before it is uploaded)";
  }
  if (errs.empty()) return {};
  return makeError(std::string("OpenGL error in ") + where + ": " + errs);
}

}  // namespace hw::gl
