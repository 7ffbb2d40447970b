// An OpenGL 4.5 core-profile context without a window or X server: Mesa's OSMesa (llvmpipe),
// loaded at run time with dlopen so that a missing or broken OSMesa is a clear error instead of a
// failure to start, and so that tests can point the loader at a bogus library.
//
// The context is not forward-compatible (OSMesa does not ask for it); rendering happens into
// framebuffer objects, so the client buffer OSMesa is made current on is only a few pixels.
#pragma once

#include <GL/glcorearb.h>

#include <memory>
#include <string>

#include "modeling/errors.h"

namespace flexure::render {

// OSMesa could not be loaded, could not create a GL 4.5 core context, lacks a GL function, or GL
// failed while rendering. An environment problem rather than a numerical one: it derives from
// InputError, so the CLI reports it with exit code 2; the message always names OSMesa and what
// failed.
class RenderError : public InputError {
 public:
  using InputError::InputError;
};

// The GL 4.5 entry points the renderer uses, as (Name, NAME): glName of type PFNGLNAMEPROC.
#define FLEXURE_GL_FUNCTIONS(X)                                     \
  X(AttachShader, ATTACHSHADER)                                     \
  X(BindBuffer, BINDBUFFER)                                         \
  X(BindFramebuffer, BINDFRAMEBUFFER)                               \
  X(BindRenderbuffer, BINDRENDERBUFFER)                             \
  X(BindVertexArray, BINDVERTEXARRAY)                               \
  X(BlitFramebuffer, BLITFRAMEBUFFER)                               \
  X(BufferData, BUFFERDATA)                                         \
  X(CheckFramebufferStatus, CHECKFRAMEBUFFERSTATUS)                 \
  X(Clear, CLEAR)                                                   \
  X(ClearColor, CLEARCOLOR)                                         \
  X(CompileShader, COMPILESHADER)                                   \
  X(CreateProgram, CREATEPROGRAM)                                   \
  X(CreateShader, CREATESHADER)                                     \
  X(DeleteBuffers, DELETEBUFFERS)                                   \
  X(DeleteFramebuffers, DELETEFRAMEBUFFERS)                         \
  X(DeleteProgram, DELETEPROGRAM)                                   \
  X(DeleteRenderbuffers, DELETERENDERBUFFERS)                       \
  X(DeleteShader, DELETESHADER)                                     \
  X(DeleteVertexArrays, DELETEVERTEXARRAYS)                         \
  X(Disable, DISABLE)                                               \
  X(DrawArrays, DRAWARRAYS)                                         \
  X(Enable, ENABLE)                                                 \
  X(EnableVertexAttribArray, ENABLEVERTEXATTRIBARRAY)               \
  X(Finish, FINISH)                                                 \
  X(FramebufferRenderbuffer, FRAMEBUFFERRENDERBUFFER)               \
  X(GenBuffers, GENBUFFERS)                                         \
  X(GenFramebuffers, GENFRAMEBUFFERS)                               \
  X(GenRenderbuffers, GENRENDERBUFFERS)                             \
  X(GenVertexArrays, GENVERTEXARRAYS)                               \
  X(GetError, GETERROR)                                             \
  X(GetIntegerv, GETINTEGERV)                                       \
  X(GetProgramInfoLog, GETPROGRAMINFOLOG)                           \
  X(GetProgramiv, GETPROGRAMIV)                                     \
  X(GetShaderInfoLog, GETSHADERINFOLOG)                             \
  X(GetShaderiv, GETSHADERIV)                                       \
  X(GetString, GETSTRING)                                           \
  X(GetUniformLocation, GETUNIFORMLOCATION)                         \
  X(LinkProgram, LINKPROGRAM)                                       \
  X(PixelStorei, PIXELSTOREI)                                       \
  X(ReadBuffer, READBUFFER)                                         \
  X(ReadPixels, READPIXELS)                                         \
  X(RenderbufferStorage, RENDERBUFFERSTORAGE)                       \
  X(RenderbufferStorageMultisample, RENDERBUFFERSTORAGEMULTISAMPLE) \
  X(ShaderSource, SHADERSOURCE)                                     \
  X(Uniform1f, UNIFORM1F)                                           \
  X(Uniform1i, UNIFORM1I)                                           \
  X(Uniform2f, UNIFORM2F)                                           \
  X(Uniform3f, UNIFORM3F)                                           \
  X(Uniform3fv, UNIFORM3FV)                                         \
  X(UniformMatrix3fv, UNIFORMMATRIX3FV)                             \
  X(UniformMatrix4fv, UNIFORMMATRIX4FV)                             \
  X(UseProgram, USEPROGRAM)                                         \
  X(VertexAttribPointer, VERTEXATTRIBPOINTER)                       \
  X(Viewport, VIEWPORT)

// One pointer per entry point, filled through OSMesaGetProcAddress: gl.Clear(...) calls glClear.
struct GlFunctions {
#define FLEXURE_GL_DECLARE(Name, NAME) PFNGL##NAME##PROC Name = nullptr;
  FLEXURE_GL_FUNCTIONS(FLEXURE_GL_DECLARE)
#undef FLEXURE_GL_DECLARE
};

// The library dlopen() loads: $FLEXURE_OSMESA_LIBRARY when set (tests of a missing OSMesa
// through the CLI use it), otherwise "libOSMesa.so.8" (Debian's libosmesa6).
std::string defaultOSMesaLibrary();

// Loads `library`, creates an OSMesa GL 4.5 core context (RGBA, 24-bit depth) and makes it
// current on the calling thread; the destructor destroys it and unloads the library. Throws
// RenderError naming the library and the step that failed. Not copyable; one thread at a time.
class OffscreenContext {
 public:
  explicit OffscreenContext(const std::string& library = defaultOSMesaLibrary());
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  const GlFunctions& gl() const { return gl_; }
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa".
  std::string description() const;
  // Makes this context current again (after another context was used on this thread).
  void makeCurrent();

 private:
  struct Library;
  std::unique_ptr<Library> library_;
  GlFunctions gl_;
};

// Throws RenderError "OSMesa: GL error 0x0505 while WHAT" when glGetError reports one.
void throwOnGlError(const GlFunctions& gl, const char* what);

}  // namespace flexure::render
