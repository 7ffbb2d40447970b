#include "render/cairo_image.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>

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

double textWidth(cairo_t* cr, const std::string& text, double size) {
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  return extents.x_advance;
}

namespace {

// `text` broken at spaces into lines at most `maxWidth` wide at font `size` (greedy; a word wider
// than maxWidth makes a line of its own).
std::vector<std::string> wrapWords(cairo_t* cr, const std::string& text, double size,
                                   double maxWidth) {
  std::vector<std::string> lines;
  std::istringstream words(text);
  std::string word, line;
  while (words >> word) {
    const std::string longer = line.empty() ? word : line + " " + word;
    if (!line.empty() && textWidth(cr, longer, size) > maxWidth) {
      lines.push_back(line);
      line = word;
    } else {
      line = longer;
    }
  }
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

}  // namespace

TextLayout layOutText(cairo_t* cr, const std::string& text, double size, double maxWidth,
                      double maxHeight) {
  for (double s = size; s >= kSmallestTextSize; s -= 0.5) {
    TextLayout layout{s, wrapWords(cr, text, s, maxWidth)};
    bool fits = layout.height() <= maxHeight;
    for (const std::string& line : layout.lines) fits = fits && textWidth(cr, line, s) <= maxWidth;
    if (fits) return layout;
  }
  const double width = textWidth(cr, text, size);
  return {std::min(size, size * maxWidth / width), {text}};
}

void showCentred(cairo_t* cr, const TextLayout& layout, double centreX, double centreY) {
  cairo_set_font_size(cr, layout.size);
  cairo_font_extents_t font;
  cairo_font_extents(cr, &font);
  const double lineHeight = kLineSpacing * layout.size;
  // Baseline of the first line: the block of lines centred, each line's ink (ascent above the
  // baseline, descent below) centred in its line height.
  double baseline =
      centreY - layout.height() / 2.0 + lineHeight / 2.0 + (font.ascent - font.descent) / 2.0;
  for (const std::string& line : layout.lines) {
    cairo_move_to(cr, centreX - textWidth(cr, line, layout.size) / 2.0, baseline);
    cairo_show_text(cr, line.c_str());
    baseline += lineHeight;
  }
}

}  // namespace flexure::render
