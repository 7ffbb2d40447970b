#include "render/offscreen_context.h"

#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

// Only OSMesa's types and constants: its functions are looked up with dlsym.
#include <GL/osmesa.h>

namespace flexure::render {
namespace {

using CreateContextAttribs = OSMesaContext (*)(const int* attributes, OSMesaContext sharelist);
using MakeCurrent = GLboolean (*)(OSMesaContext, void* buffer, GLenum type, GLsizei width,
                                  GLsizei height);
using DestroyContext = void (*)(OSMesaContext);
using GetProcAddress = OSMESAproc (*)(const char* name);

// The client buffer the context is current on: rendering goes to framebuffer objects instead.
constexpr int kClientBufferSide = 4;

}  // namespace

struct OffscreenContext::Library {
  std::string path;
  void* handle = nullptr;
  OSMesaContext context = nullptr;
  MakeCurrent makeCurrent = nullptr;
  DestroyContext destroyContext = nullptr;
  std::vector<unsigned char> clientBuffer =
      std::vector<unsigned char>(4 * kClientBufferSide * kClientBufferSide);

  ~Library() {
    if (context && destroyContext) destroyContext(context);
    if (handle) dlclose(handle);
  }

  template <typename Function>
  Function symbol(const char* name) {
    void* address = dlsym(handle, name);
    if (!address) {
      throw RenderError("OSMesa: " + path + " does not export " + name +
                        " (not an OSMesa library, or too old: flexure needs Mesa's libOSMesa.so.8 "
                        "from libosmesa6)");
    }
    return reinterpret_cast<Function>(address);
  }
};

std::string defaultOSMesaLibrary() {
  const char* overridden = std::getenv("FLEXURE_OSMESA_LIBRARY");
  return overridden && *overridden ? overridden : "libOSMesa.so.8";
}

OffscreenContext::OffscreenContext(const std::string& library)
    : library_(std::make_unique<Library>()) {
  Library& lib = *library_;
  lib.path = library;
  lib.handle = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib.handle) {
    const char* reason = dlerror();
    throw RenderError("OSMesa: cannot load " + library + " (" +
                      (reason ? reason : "dlopen failed") +
                      "); install the Debian package libosmesa6 (scripts/install-deps) to render");
  }
  const auto createContext = lib.symbol<CreateContextAttribs>("OSMesaCreateContextAttribs");
  lib.makeCurrent = lib.symbol<MakeCurrent>("OSMesaMakeCurrent");
  lib.destroyContext = lib.symbol<DestroyContext>("OSMesaDestroyContext");
  const auto getProcAddress = lib.symbol<GetProcAddress>("OSMesaGetProcAddress");

  // A GL 4.5 core profile (not forward-compatible), RGBA colour, 24-bit depth, no stencil.
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            4,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            5,
                            0};
  lib.context = createContext(attributes, nullptr);
  if (!lib.context) {
    throw RenderError("OSMesa: " + library +
                      " could not create an OpenGL 4.5 core-profile context (Mesa 20 or newer "
                      "with llvmpipe is needed)");
  }
  makeCurrent();

  std::string missing;
#define FLEXURE_GL_LOAD(Name, NAME)                                           \
  gl_.Name = reinterpret_cast<PFNGL##NAME##PROC>(getProcAddress("gl" #Name)); \
  if (!gl_.Name) missing += std::string(missing.empty() ? "" : ", ") + "gl" #Name;
  FLEXURE_GL_FUNCTIONS(FLEXURE_GL_LOAD)
#undef FLEXURE_GL_LOAD
  if (!missing.empty()) {
    throw RenderError("OSMesa: " + library + " lacks the OpenGL functions " + missing);
  }
}

OffscreenContext::~OffscreenContext() = default;

void OffscreenContext::makeCurrent() {
  Library& lib = *library_;
  if (!lib.makeCurrent(lib.context, lib.clientBuffer.data(), GL_UNSIGNED_BYTE, kClientBufferSide,
                       kClientBufferSide)) {
    throw RenderError("OSMesa: OSMesaMakeCurrent failed for " + lib.path);
  }
}

std::string OffscreenContext::description() const {
  const auto text = [this](GLenum name) {
    const GLubyte* value = gl_.GetString(name);
    return value ? std::string(reinterpret_cast<const char*>(value)) : std::string("?");
  };
  return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

void throwOnGlError(const GlFunctions& gl, const char* what) {
  const GLenum error = gl.GetError();
  if (error == GL_NO_ERROR) return;
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(error));
  throw RenderError(std::string("OSMesa: GL error ") + code + " while " + what);
}

}  // namespace flexure::render
