#include "render/cairo_image.h"

#include <cstddef>
#include <cstdint>

namespace flexure::render {

void paintImage(const Image& image, cairo_surface_t* surface, int left, int top) {
  cairo_surface_flush(surface);
  unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  for (int y = 0; y < image.height; ++y) {
    auto* row =
        reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(top + y) * stride) +
        left;
    for (int x = 0; x < image.width; ++x) {
      const auto p = image.pixel(x, y);
      row[x] = (std::uint32_t{p[0]} << 16) | (std::uint32_t{p[1]} << 8) | std::uint32_t{p[2]};
    }
  }
  cairo_surface_mark_dirty(surface);
}

CairoSurface surfaceFromImage(const Image& image) {
  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, image.width, image.height),
                       &cairo_surface_destroy);
  paintImage(image, surface.get(), 0, 0);
  return surface;
}

Image imageFromSurface(cairo_surface_t* surface) {
  cairo_surface_flush(surface);
  Image image;
  image.width = cairo_image_surface_get_width(surface);
  image.height = cairo_image_surface_get_height(surface);
  image.rgba.resize(static_cast<std::size_t>(4) * image.width * image.height);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  for (int y = 0; y < image.height; ++y) {
    const auto* row =
        reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    for (int x = 0; x < image.width; ++x) {
      std::uint8_t* out = &image.rgba[4 * (static_cast<std::size_t>(y) * image.width + x)];
      out[0] = (row[x] >> 16) & 0xff;
      out[1] = (row[x] >> 8) & 0xff;
      out[2] = row[x] & 0xff;
      out[3] = 255;
    }
  }
  return image;
}

}  // namespace flexure::render
