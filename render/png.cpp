// Images as PNG: encoded with Cairo into bytes, and written to a file atomically.
#include <cairo.h>

#include <string>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "render/cairo_image.h"
#include "render/mesh_renderer.h"

namespace flexure::render {
namespace {

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

std::string encodePng(const Image& image) {
  const CairoSurface surface = surfaceFromImage(image);
  std::string png;
  if (cairo_surface_write_to_png_stream(surface.get(), appendToString, &png) !=
      CAIRO_STATUS_SUCCESS) {
    throw InputError("render: Cairo could not encode the PNG");
  }
  return png;
}

void writePng(const std::string& path, const Image& image) {
  modeling::writeFileAtomically(path, encodePng(image));
}

}  // namespace flexure::render
