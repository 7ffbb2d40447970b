// Images in and out of Cairo image surfaces (internal to render/). Cairo's RGB24 pixels are
// native-endian 0x00RRGGBB words; images are opaque, so alpha is dropped on the way in and 255
// on the way out.
#pragma once

#include <cairo.h>

#include <memory>
#include <string>
#include <vector>

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

// Text that fits a band: the font size and the lines, for the current font face of a context.
inline constexpr double kSmallestTextSize = 7.0;  // the smallest a wrapped text is set
inline constexpr double kLineSpacing = 1.25;      // line height / font size
inline constexpr double kTextMargin = 4.0;        // kept free on each side of a text's band

struct TextLayout {
  double size = 0.0;
  std::vector<std::string> lines;
  double height() const { return static_cast<double>(lines.size()) * kLineSpacing * size; }
};

// The advance width of `text` at font `size`.
double textWidth(cairo_t* cr, const std::string& text, double size);

// How `text` is set in a band maxWidth × maxHeight: at the largest size from `size` down to
// kSmallestTextSize (in steps of ½) at which its words, wrapped at spaces, fit the band; when
// none does, on one line shrunk to the band's width.
TextLayout layOutText(cairo_t* cr, const std::string& text, double size, double maxWidth,
                      double maxHeight);

// The lines of `layout` centred horizontally on `centreX`, the block vertically on `centreY`.
void showCentred(cairo_t* cr, const TextLayout& layout, double centreX, double centreY);

}  // namespace flexure::render
