#pragma once
// OpenGL 4.5 core entry points as function pointers, filled from the current
// context's get-proc-address (OSMesaGetProcAddress headless, glfwGetProcAddress
// windowed). NOTES-GL.md: libepoxy/GLEW/glbinding resolve through libGL and
// silently do nothing under OSMesa, and libOSMesa does not export the 4.5
// functions, so every call goes through this table. Include only from gl/ files.
#include <GL/glcorearb.h>  // types and PFN typedefs only (no GL_GLEXT_PROTOTYPES)

#include "core/result.h"

// X(PFN type, name)
#define HW_GL_FUNCTIONS(X)                                               \
  X(PFNGLGETSTRINGPROC, glGetString)                                     \
  X(PFNGLGETINTEGERVPROC, glGetIntegerv)                                 \
  X(PFNGLGETERRORPROC, glGetError)                                       \
  X(PFNGLENABLEPROC, glEnable)                                           \
  X(PFNGLDISABLEPROC, glDisable)                                         \
  X(PFNGLVIEWPORTPROC, glViewport)                                       \
  X(PFNGLSCISSORPROC, glScissor)                                         \
  X(PFNGLCLEARPROC, glClear)                                             \
  X(PFNGLCLEARCOLORPROC, glClearColor)                                   \
  X(PFNGLCLEARDEPTHPROC, glClearDepth)                                   \
  X(PFNGLDEPTHFUNCPROC, glDepthFunc)                                     \
  X(PFNGLDEPTHMASKPROC, glDepthMask)                                     \
  X(PFNGLCOLORMASKPROC, glColorMask)                                     \
  X(PFNGLCULLFACEPROC, glCullFace)                                       \
  X(PFNGLFRONTFACEPROC, glFrontFace)                                     \
  X(PFNGLBLENDFUNCPROC, glBlendFunc)                                     \
  X(PFNGLPOLYGONMODEPROC, glPolygonMode)                                 \
  X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset)                             \
  X(PFNGLLINEWIDTHPROC, glLineWidth)                                     \
  X(PFNGLPIXELSTOREIPROC, glPixelStorei)                                 \
  X(PFNGLREADPIXELSPROC, glReadPixels)                                   \
  X(PFNGLREADBUFFERPROC, glReadBuffer)                                   \
  X(PFNGLDRAWBUFFERSPROC, glDrawBuffers)                                 \
  X(PFNGLFINISHPROC, glFinish)                                           \
  X(PFNGLFLUSHPROC, glFlush)                                             \
  X(PFNGLGENTEXTURESPROC, glGenTextures)                                 \
  X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                           \
  X(PFNGLBINDTEXTUREPROC, glBindTexture)                                 \
  X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                                   \
  X(PFNGLTEXSUBIMAGE2DPROC, glTexSubImage2D)                             \
  X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                             \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                             \
  X(PFNGLGENERATEMIPMAPPROC, glGenerateMipmap)                           \
  X(PFNGLGENBUFFERSPROC, glGenBuffers)                                   \
  X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                             \
  X(PFNGLBINDBUFFERPROC, glBindBuffer)                                   \
  X(PFNGLBUFFERDATAPROC, glBufferData)                                   \
  X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)                             \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)                   \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                         \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)         \
  X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)                 \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays)                                   \
  X(PFNGLDRAWELEMENTSPROC, glDrawElements)                               \
  X(PFNGLCREATESHADERPROC, glCreateShader)                               \
  X(PFNGLSHADERSOURCEPROC, glShaderSource)                               \
  X(PFNGLCOMPILESHADERPROC, glCompileShader)                             \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv)                                 \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                       \
  X(PFNGLDELETESHADERPROC, glDeleteShader)                               \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                             \
  X(PFNGLATTACHSHADERPROC, glAttachShader)                               \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram)                                 \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)                     \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                             \
  X(PFNGLUSEPROGRAMPROC, glUseProgram)                                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)                   \
  X(PFNGLUNIFORM1IPROC, glUniform1i)                                     \
  X(PFNGLUNIFORM1FPROC, glUniform1f)                                     \
  X(PFNGLUNIFORM2FPROC, glUniform2f)                                     \
  X(PFNGLUNIFORM3FPROC, glUniform3f)                                     \
  X(PFNGLUNIFORM4FPROC, glUniform4f)                                     \
  X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv)                       \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                         \
  X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)                   \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                         \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)               \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, glFramebufferRenderbuffer)         \
  X(PFNGLGENRENDERBUFFERSPROC, glGenRenderbuffers)                       \
  X(PFNGLDELETERENDERBUFFERSPROC, glDeleteRenderbuffers)                 \
  X(PFNGLBINDRENDERBUFFERPROC, glBindRenderbuffer)                       \
  X(PFNGLRENDERBUFFERSTORAGEPROC, glRenderbufferStorage)                 \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)           \
  X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer)                         \
  X(PFNGLISFRAMEBUFFERPROC, glIsFramebuffer)                             \
  X(PFNGLGETFRAMEBUFFERATTACHMENTPARAMETERIVPROC, glGetFramebufferAttachmentParameteriv)\
  X(PFNGLGETTEXLEVELPARAMETERIVPROC, glGetTexLevelParameteriv)           \
  X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv)                             \
  X(PFNGLCLIPCONTROLPROC, glClipControl)                                 \
  X(PFNGLSTENCILFUNCPROC, glStencilFunc)                                 \
  X(PFNGLSTENCILOPPROC, glStencilOp)                                     \
  X(PFNGLSTENCILMASKPROC, glStencilMask)                                 \
  X(PFNGLCLEARSTENCILPROC, glClearStencil)                               \
  X(PFNGLGENQUERIESPROC, glGenQueries)                                   \
  X(PFNGLDELETEQUERIESPROC, glDeleteQueries)                             \
  X(PFNGLBEGINQUERYPROC, glBeginQuery)                                   \
  X(PFNGLENDQUERYPROC, glEndQuery)                                       \
  X(PFNGLGETQUERYOBJECTUIVPROC, glGetQueryObjectuiv)                     \
  X(PFNGLDEBUGMESSAGECALLBACKPROC, glDebugMessageCallback)               \
  X(PFNGLDEBUGMESSAGECONTROLPROC, glDebugMessageControl)

namespace hwgl {
#define HW_GL_DECLARE(type, name) extern type name;
HW_GL_FUNCTIONS(HW_GL_DECLARE)
#undef HW_GL_DECLARE
}  // namespace hwgl

// GL code calls glFoo(...) as usual; the names resolve to the table above
// (namespaced so they never interpose on libOSMesa's exported symbols).
using namespace hwgl;  // NOLINT(google-build-using-namespace)

namespace hw::gl {

using GetProcAddress = void* (*)(const char* name);

// Fills the table from `getProc`; an error names every missing entry point.
// In debug builds (no NDEBUG), or with HW_GL_DEBUG=1 in the environment, it
// then installs the KHR_debug callback (installDebugCallback) in the current
// context.
Status loadGlFunctions(GetProcAddress getProc);

// KHR_debug (core since 4.3): synchronous debug output into a callback that
// counts GL_DEBUG_TYPE_ERROR messages (debugCallbackErrors in context.h) and
// prints the first few to stderr. Needs a current context.
void installDebugCallback();

// glGetError drained into one message naming `where`; ok when no error.
Status checkGlError(const char* where);

}  // namespace hw::gl
