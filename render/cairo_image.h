// Images in and out of Cairo image surfaces (internal to render/). Cairo's RGB24 pixels are
// native-endian 0x00RRGGBB words; images are opaque, so alpha is dropped on the way in and 255
// on the way out.
#pragma once

#include <cairo.h>

#include <memory>

#include "render/image.h"

namespace flexure::render {

using CairoSurface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using CairoContext = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

// Copies `image` into the RGB24 `surface` with its top-left corner at (left, top).
void paintImage(const Image& image, cairo_surface_t* surface, int left, int top);

// A new RGB24 surface holding `image`.
CairoSurface surfaceFromImage(const Image& image);

// The pixels of an RGB24 surface.
Image imageFromSurface(cairo_surface_t* surface);

}  // namespace flexure::render
