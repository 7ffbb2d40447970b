// The legend of the scalar styles: tick positions (linear steps of 1, 2 or 5 × 10^k, or whole
// decades on a log scale), their labels, and the colour bar drawn with Cairo beside the mesh.
#include "render/legend.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "render/cairo_image.h"

namespace flexure::render {
namespace {

constexpr const char* kFont = "DejaVu Sans";

// A tick's label: fixed-point with as many decimals as the tick step needs (0.2 → "0.4"), or
// %g for very small or large steps; a round-off zero prints as "0".
std::string tickLabel(double value, double step) {
  char label[32];
  if (std::abs(value) < 1e-9 * step) value = 0.0;
  if (step >= 1e-4 && step < 1e5) {
    const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
    std::snprintf(label, sizeof label, "%.*f", decimals, value);
  } else {
    std::snprintf(label, sizeof label, "%.3g", value);
  }
  return label;
}

// Whole decades in [minimum, maximum] (decimal logarithms), every one or every k-th so that there
// are at most eight.
std::vector<double> decadeTicks(double minimum, double maximum) {
  const double first = std::ceil(minimum - 1e-9), last = std::floor(maximum + 1e-9);
  const double stride = std::max(1.0, std::ceil((last - first + 1.0) / 8.0));
  std::vector<double> ticks;
  for (double k = first; k <= last; k += stride) ticks.push_back(k);
  return ticks;
}

std::string decadeLabel(double exponent) {
  char label[16];
  std::snprintf(label, sizeof label, "1e%d", static_cast<int>(std::lround(exponent)));
  return label;
}

}  // namespace

std::vector<double> legendTicks(double minimum, double maximum) {
  const double span = maximum - minimum;
  if (!(span > 0.0) || !std::isfinite(span)) return {minimum};
  // The largest step 1, 2 or 5 × 10^k with at least kMinimumTicks multiples in the range.
  constexpr int kMinimumTicks = 4;
  double decade = std::pow(10.0, std::ceil(std::log10(span)));
  for (;; decade /= 10.0) {
    for (const double mantissa : {5.0, 2.0, 1.0}) {
      const double step = mantissa * decade;
      const double first = std::ceil(minimum / step - 1e-9),
                   last = std::floor(maximum / step + 1e-9);
      if (last - first + 1.0 >= kMinimumTicks) {
        std::vector<double> ticks;
        for (double k = first; k <= last; k += 1.0) ticks.push_back(k * step);
        return ticks;
      }
    }
  }
}

Image withLegend(const Image& meshImage, const RenderOptions& o, double minimum, double maximum,
                 const ColourMap& map, const std::string& title, const std::string& range,
                 bool logarithmic) {
  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, o.width, o.height),
                       &cairo_surface_destroy);
  CairoContext cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_set_source_rgb(cr.get(), o.background.r, o.background.g, o.background.b);
  cairo_paint(cr.get());
  const CairoSurface meshSurface = surfaceFromImage(meshImage);
  cairo_set_source_surface(cr.get(), meshSurface.get(), 0.0, 0.0);
  cairo_paint(cr.get());

  const double luminance =
      0.2126 * o.background.r + 0.7152 * o.background.g + 0.0722 * o.background.b;
  const double ink = luminance > 0.5 ? 0.0 : 1.0;
  const double barLeft = meshImage.width + 14.0, barWidth = 18.0;
  const double barTop = std::round(0.18 * o.height), barBottom = std::round(0.82 * o.height);
  for (double y = barTop; y < barBottom; y += 1.0) {
    const Rgb c = map.at((barBottom - (y + 0.5)) / (barBottom - barTop));
    cairo_set_source_rgb(cr.get(), c.r, c.g, c.b);
    cairo_rectangle(cr.get(), barLeft, y, barWidth, 1.0);
    cairo_fill(cr.get());
  }
  cairo_set_source_rgb(cr.get(), ink, ink, ink);
  cairo_set_line_width(cr.get(), 1.0);
  cairo_rectangle(cr.get(), barLeft + 0.5, barTop + 0.5, barWidth - 1.0, barBottom - barTop - 1.0);
  cairo_stroke(cr.get());
  cairo_select_font_face(cr.get(), kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double textSize = std::clamp(0.022 * o.height, 10.0, 15.0);
  const std::vector<double> ticks =
      logarithmic ? decadeTicks(minimum, maximum) : legendTicks(minimum, maximum);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : maximum - minimum;
  const double labelLeft = barLeft + barWidth + 8.0;
  const double labelWidth = o.width - kTextMargin - labelLeft;
  for (const double tick : ticks) {
    const double y = barBottom - (tick - minimum) / (maximum - minimum) * (barBottom - barTop);
    cairo_move_to(cr.get(), barLeft + barWidth, std::round(y) + 0.5);
    cairo_rel_line_to(cr.get(), 5.0, 0.0);
    cairo_stroke(cr.get());
    const std::string label = logarithmic ? decadeLabel(tick) : tickLabel(tick, step);
    const double size =
        std::min(textSize, textSize * labelWidth / textWidth(cr.get(), label, textSize));
    cairo_set_font_size(cr.get(), size);
    cairo_move_to(cr.get(), labelLeft, y + 0.35 * size);
    cairo_show_text(cr.get(), label.c_str());
  }
  // The title and the range line in the band above the bar, centred on the legend strip.
  const double legendLeft = meshImage.width, legendWidth = o.width - meshImage.width;
  const double bandHeight = (barTop - 0.5 * textSize) / 2.0;
  const TextLayout titleText =
      layOutText(cr.get(), title, textSize, legendWidth - 2.0 * kTextMargin, bandHeight);
  const TextLayout rangeText =
      layOutText(cr.get(), range, textSize, legendWidth - 2.0 * kTextMargin, bandHeight);
  showCentred(cr.get(), titleText, legendLeft + legendWidth / 2.0, bandHeight / 2.0);
  showCentred(cr.get(), rangeText, legendLeft + legendWidth / 2.0, 1.5 * bandHeight);
  return imageFromSurface(surface.get());
}

}  // namespace flexure::render
