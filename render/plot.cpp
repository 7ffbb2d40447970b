#include "render/plot.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "modeling/atomic_write.h"

namespace flexure::render {
namespace {

struct Rgb {
  double r, g, b;
};

// Tableau 10 (the first eight): distinct in hue and in grey value.
constexpr Rgb kPalette[] = {{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
                            {0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                            {0.890, 0.467, 0.761}, {0.498, 0.498, 0.498}};
constexpr int kMarkerKinds = 8;
constexpr size_t kMostMarkers = 60;  // longer series (time histories) are drawn as lines only

constexpr const char* kFont = "DejaVu Sans";
constexpr double kTextSize = 13.0, kTitleSize = 16.0, kExponentScale = 0.72;

using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;
using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

// An axis from lo to hi: log10 (both ends of the form m × 10^k, m in {1, 2, 5}) or linear (both
// ends multiples of the tick step).
struct Axis {
  bool log = true;
  double lo = 0.1, hi = 1.0;
  double step = 0.1;                    // linear: the tick spacing
  double pixelLo = 0.0, pixelHi = 1.0;  // where lo and hi land

  double pixel(double value) const {
    const double t =
        log ? (std::log10(value) - std::log10(lo)) / std::log10(hi / lo) : (value - lo) / (hi - lo);
    return pixelLo + t * (pixelHi - pixelLo);
  }
  bool drawable(double value) const { return std::isfinite(value) && (!log || value > 0.0); }
  bool contains(double value) const {
    const double slack = 1e-9 * (log ? 1.0 : hi - lo);
    return log ? value >= lo * (1 - 1e-9) && value <= hi * (1 + 1e-9)
               : value >= lo - slack && value <= hi + slack;
  }
  int firstDecade() const { return static_cast<int>(std::floor(std::log10(lo) + 1e-9)); }
  int lastDecade() const { return static_cast<int>(std::floor(std::log10(hi) + 1e-9)); }
  // At most two decades: the 2 and 5 ticks are labelled too.
  bool labelsMinor() const { return hi / lo <= 100.0 * (1 + 1e-9); }
};

// The largest m × 10^k (m in {1, 2, 5}) not above v, and the smallest not below.
double niceBelow(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= v * (1 + 1e-9)) return m * decade;
  return decade / 2;
}
double niceAbove(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= v * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

Axis axisAround(double minimum, double maximum) {
  Axis axis;
  if (!(minimum > 0.0) || !(maximum >= minimum)) return axis;  // no data: [0.1, 1]
  // A margin of 15 % keeps markers on the extreme values clear of the frame.
  axis.lo = niceBelow(minimum / 1.15);
  axis.hi = niceAbove(maximum * 1.15);
  if (axis.hi <= axis.lo * (1 + 1e-9)) axis.hi = niceAbove(axis.lo * 1.5);
  return axis;
}

// A linear axis over [minimum, maximum] with 4 to 10 ticks at 1, 2 or 5 × 10^k.
Axis linearAxisAround(double minimum, double maximum) {
  Axis axis;
  axis.log = false;
  if (!std::isfinite(minimum) || !std::isfinite(maximum) || maximum < minimum) {
    axis.lo = 0.0, axis.hi = 1.0, axis.step = 0.2;
    return axis;
  }
  if (maximum == minimum) {
    const double pad = minimum != 0.0 ? 0.5 * std::abs(minimum) : 1.0;
    minimum -= pad;
    maximum += pad;
  }
  axis.step = niceAbove((maximum - minimum) / 8.0);
  axis.lo = std::floor(minimum / axis.step + 1e-9) * axis.step;
  axis.hi = std::ceil(maximum / axis.step - 1e-9) * axis.step;
  return axis;
}

// A tick value's label on a linear axis: as few digits as the step needs.
std::string linearLabel(double value, double step) {
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  char text[32];
  if (std::abs(value) < 1e-12 * step) value = 0.0;
  if (std::abs(value) >= 1e5 || (value != 0.0 && std::abs(value) < 1e-3))
    std::snprintf(text, sizeof text, "%.2g", value);
  else
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
  std::string label = text;
  if (label[0] == '-') label = "−" + label.substr(1);  // a true minus sign
  return label;
}

double textWidth(cairo_t* cr, const std::string& text, double size) {
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  return extents.x_advance;
}

// Tick labels "m×10^k" (m = 1: "10^k"), the exponent raised and smaller, with a true minus sign.
std::string mantissaText(int mantissa) {
  return mantissa == 1 ? "10" : std::to_string(mantissa) + "×10";
}
std::string exponentText(int exponent) {
  return exponent < 0 ? "−" + std::to_string(-exponent) : std::to_string(exponent);
}

double powerLabelWidth(cairo_t* cr, int mantissa, int exponent) {
  return textWidth(cr, mantissaText(mantissa), kTextSize) +
         textWidth(cr, exponentText(exponent), kTextSize * kExponentScale);
}

void drawPowerLabel(cairo_t* cr, int mantissa, int exponent, double x, double baseline) {
  const std::string prefix = mantissaText(mantissa), power = exponentText(exponent);
  cairo_set_font_size(cr, kTextSize);
  cairo_move_to(cr, x, baseline);
  cairo_show_text(cr, prefix.c_str());
  cairo_set_font_size(cr, kTextSize * kExponentScale);
  cairo_rel_move_to(cr, 0.0, -0.45 * kTextSize);
  cairo_show_text(cr, power.c_str());
}

void drawMarker(cairo_t* cr, int kind, double x, double y, double r) {
  const double pi = std::acos(-1.0);
  switch (kind % kMarkerKinds) {
    case 0:  // circle
      cairo_arc(cr, x, y, r, 0.0, 2.0 * pi);
      cairo_fill(cr);
      break;
    case 1:  // square
      cairo_rectangle(cr, x - 0.85 * r, y - 0.85 * r, 1.7 * r, 1.7 * r);
      cairo_fill(cr);
      break;
    case 2:  // triangle up
      cairo_move_to(cr, x, y - 1.15 * r);
      cairo_line_to(cr, x + r, y + 0.75 * r);
      cairo_line_to(cr, x - r, y + 0.75 * r);
      cairo_close_path(cr);
      cairo_fill(cr);
      break;
    case 3:  // diamond
      cairo_move_to(cr, x, y - 1.2 * r);
      cairo_line_to(cr, x + r, y);
      cairo_line_to(cr, x, y + 1.2 * r);
      cairo_line_to(cr, x - r, y);
      cairo_close_path(cr);
      cairo_fill(cr);
      break;
    case 4:  // triangle down
      cairo_move_to(cr, x, y + 1.15 * r);
      cairo_line_to(cr, x + r, y - 0.75 * r);
      cairo_line_to(cr, x - r, y - 0.75 * r);
      cairo_close_path(cr);
      cairo_fill(cr);
      break;
    case 5:  // plus
      cairo_move_to(cr, x - 1.2 * r, y);
      cairo_line_to(cr, x + 1.2 * r, y);
      cairo_move_to(cr, x, y - 1.2 * r);
      cairo_line_to(cr, x, y + 1.2 * r);
      cairo_stroke(cr);
      break;
    case 6:  // cross
      cairo_move_to(cr, x - r, y - r);
      cairo_line_to(cr, x + r, y + r);
      cairo_move_to(cr, x - r, y + r);
      cairo_line_to(cr, x + r, y - r);
      cairo_stroke(cr);
      break;
    default:  // hollow circle
      cairo_arc(cr, x, y, r, 0.0, 2.0 * pi);
      cairo_stroke(cr);
      break;
  }
}

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// The axes around the drawable points of `plot`, and (for the reference slopes) the mean of their
// log10 x and log10 y.
struct PlotData {
  Axis x, y;
  double sumLogX = 0.0, sumLogY = 0.0;
  int drawn = 0;  // drawable points
  bool drawable(double px, double py) const { return x.drawable(px) && y.drawable(py); }
};

PlotData plotData(const LogLogPlot& plot, bool logarithmic) {
  PlotData data;
  data.x.log = data.y.log = logarithmic;
  const double infinity = std::numeric_limits<double>::infinity();
  double minX = infinity, maxX = -infinity, minY = infinity, maxY = -infinity;
  for (const PlotSeries& s : plot.series) {
    for (size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k) {
      if (!data.drawable(s.x[k], s.y[k])) continue;
      minX = std::min(minX, s.x[k]);
      maxX = std::max(maxX, s.x[k]);
      minY = std::min(minY, s.y[k]);
      maxY = std::max(maxY, s.y[k]);
      if (logarithmic) {
        data.sumLogX += std::log10(s.x[k]);
        data.sumLogY += std::log10(s.y[k]);
      }
      ++data.drawn;
    }
  }
  if (logarithmic) {
    data.x = axisAround(minX, maxX);
    data.y = axisAround(minY, maxY);
  } else {
    data.x = linearAxisAround(minX, maxX);
    data.y = linearAxisAround(minY, maxY);
  }
  return data;
}

// The plot area in pixels, and the width of the legend column right of it (0: no legend).
struct PlotFrame {
  double left = 0.0, right = 0.0, top = 0.0, bottom = 0.0;
  double legendWidth = 0.0;
};

// Layout: title band, legend column on the right, tick labels and axis labels left and below.
// Sets the axes' pixel ends.
PlotFrame plotFrame(cairo_t* cr, const LogLogPlot& plot, PlotData& data) {
  PlotFrame frame;
  for (const PlotSeries& s : plot.series)
    frame.legendWidth = std::max(frame.legendWidth, textWidth(cr, s.label, kTextSize));
  for (const ReferenceSlope& r : plot.referenceSlopes)
    frame.legendWidth = std::max(frame.legendWidth, textWidth(cr, r.label, kTextSize));
  frame.legendWidth = frame.legendWidth > 0.0 ? frame.legendWidth + 56.0 : 0.0;
  const Axis& yAxis = data.y;
  double tickLabelWidth = 0.0;
  if (yAxis.log) {
    for (int k = yAxis.firstDecade(); k <= yAxis.lastDecade(); ++k)
      tickLabelWidth =
          std::max(tickLabelWidth, powerLabelWidth(cr, yAxis.labelsMinor() ? 5 : 1, k));
  } else {
    for (double v = yAxis.lo; v <= yAxis.hi + 1e-9 * yAxis.step; v += yAxis.step)
      tickLabelWidth =
          std::max(tickLabelWidth, textWidth(cr, linearLabel(v, yAxis.step), kTextSize));
  }
  frame.left = tickLabelWidth + 46.0, frame.top = 44.0, frame.bottom = plot.height - 58.0;
  frame.right = std::max(frame.left + 60.0, plot.width - 16.0 - frame.legendWidth);
  data.x.pixelLo = frame.left;
  data.x.pixelHi = frame.right;
  data.y.pixelLo = frame.bottom;
  data.y.pixelHi = frame.top;
  return frame;
}

void drawTitleAndAxisLabels(cairo_t* cr, const LogLogPlot& plot, const PlotFrame& f) {
  cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
  cairo_set_font_size(cr, kTitleSize);
  cairo_move_to(
      cr, std::max(8.0, (f.left + f.right) / 2 - textWidth(cr, plot.title, kTitleSize) / 2), 26.0);
  cairo_show_text(cr, plot.title.c_str());
  cairo_set_font_size(cr, kTextSize);
  cairo_move_to(cr, (f.left + f.right) / 2 - textWidth(cr, plot.xLabel, kTextSize) / 2,
                plot.height - 12.0);
  cairo_show_text(cr, plot.xLabel.c_str());
  cairo_save(cr);
  cairo_move_to(cr, 18.0, (f.top + f.bottom) / 2 + textWidth(cr, plot.yLabel, kTextSize) / 2);
  cairo_rotate(cr, -std::acos(-1.0) / 2);
  cairo_show_text(cr, plot.yLabel.c_str());
  cairo_restore(cr);
}

// A linear axis: a labelled grid line at every step.
void drawLinearGrid(cairo_t* cr, const Axis& axis, bool vertical, const PlotFrame& f) {
  const long count = std::lround((axis.hi - axis.lo) / axis.step);
  for (long k = 0; k <= count; ++k) {
    const double value = axis.lo + k * axis.step;
    const double p = std::round(axis.pixel(value)) + 0.5;
    cairo_set_source_rgb(cr, 0.87, 0.87, 0.87);
    cairo_move_to(cr, vertical ? p : f.left, vertical ? f.top : p);
    cairo_line_to(cr, vertical ? p : f.right, vertical ? f.bottom : p);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    const std::string label = linearLabel(value, axis.step);
    cairo_set_font_size(cr, kTextSize);
    cairo_move_to(cr,
                  vertical ? p - textWidth(cr, label, kTextSize) / 2
                           : f.left - 10.0 - textWidth(cr, label, kTextSize),
                  vertical ? f.bottom + 20.0 : p + 4.5);
    cairo_show_text(cr, label.c_str());
  }
}

// A log axis: grid lines and ticks at m × 10^k, decades labelled, and 2 and 5 on short axes.
void drawLogGrid(cairo_t* cr, const Axis& axis, bool vertical, const PlotFrame& f) {
  for (int k = axis.firstDecade(); k <= axis.lastDecade(); ++k) {
    for (int m = 1; m <= 9; ++m) {
      const double value = m * std::pow(10.0, k);
      if (!axis.contains(value)) continue;
      const double p = std::round(axis.pixel(value)) + 0.5;
      const double grey = m == 1 ? 0.82 : 0.93;
      const double tick = m == 1 ? 7.0 : 4.0;
      cairo_set_source_rgb(cr, grey, grey, grey);
      if (vertical) {
        cairo_move_to(cr, p, f.top);
        cairo_line_to(cr, p, f.bottom);
      } else {
        cairo_move_to(cr, f.left, p);
        cairo_line_to(cr, f.right, p);
      }
      cairo_stroke(cr);
      cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
      if (vertical) {
        cairo_move_to(cr, p, f.bottom);
        cairo_line_to(cr, p, f.bottom + tick);
      } else {
        cairo_move_to(cr, f.left - tick, p);
        cairo_line_to(cr, f.left, p);
      }
      cairo_stroke(cr);
      if (m == 1 || (axis.labelsMinor() && (m == 2 || m == 5))) {
        if (vertical) {
          drawPowerLabel(cr, m, k, p - powerLabelWidth(cr, m, k) / 2, f.bottom + 24.0);
        } else {
          drawPowerLabel(cr, m, k, f.left - 10.0 - powerLabelWidth(cr, m, k), p + 4.5);
        }
      }
    }
  }
}

// The grids (all linear ones first), the frame, and a note when nothing is drawable.
void drawGridAndFrame(cairo_t* cr, const PlotData& data, const PlotFrame& f) {
  cairo_set_line_width(cr, 1.0);
  for (const bool vertical : {true, false}) {
    const Axis& axis = vertical ? data.x : data.y;
    if (!axis.log) drawLinearGrid(cr, axis, vertical, f);
  }
  for (const bool vertical : {true, false}) {
    const Axis& axis = vertical ? data.x : data.y;
    if (axis.log) drawLogGrid(cr, axis, vertical, f);
  }
  cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
  cairo_set_line_width(cr, 1.2);
  cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  cairo_stroke(cr);
  if (data.drawn == 0) {
    const char* empty = data.x.log ? "no positive values to plot" : "no values to plot";
    cairo_set_font_size(cr, kTextSize);
    cairo_move_to(cr, (f.left + f.right) / 2 - textWidth(cr, empty, kTextSize) / 2,
                  (f.top + f.bottom) / 2);
    cairo_show_text(cr, empty);
  }
}

// Reference slopes (log-log only): dashed lines of slope p through the data's centre in log
// coordinates.
void drawReferenceSlopes(cairo_t* cr, const LogLogPlot& plot, const PlotData& data) {
  const Axis &xAxis = data.x, &yAxis = data.y;
  const double centreX = data.sumLogX / data.drawn, centreY = data.sumLogY / data.drawn;
  const double dashes[] = {6.0, 4.0};
  for (size_t r = 0; r < plot.referenceSlopes.size(); ++r) {
    const double slope = plot.referenceSlopes[r].slope;
    const double grey = 0.35 + 0.2 * static_cast<double>(r % 2);
    cairo_set_source_rgb(cr, grey, grey, grey);
    cairo_set_dash(cr, dashes, 2, 0.0);
    cairo_set_line_width(cr, 1.3);
    const double x0 = std::log10(xAxis.lo), x1 = std::log10(xAxis.hi);
    cairo_move_to(cr, xAxis.pixel(xAxis.lo),
                  yAxis.pixel(std::pow(10.0, centreY + slope * (x0 - centreX))));
    cairo_line_to(cr, xAxis.pixel(xAxis.hi),
                  yAxis.pixel(std::pow(10.0, centreY + slope * (x1 - centreX))));
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0.0);
}

// Series s: a line through its drawable points (broken at the others) and its markers.
void drawSeries(cairo_t* cr, const PlotSeries& series, size_t s, const PlotData& data) {
  const Rgb colour = kPalette[s % (sizeof kPalette / sizeof kPalette[0])];
  cairo_set_source_rgb(cr, colour.r, colour.g, colour.b);
  cairo_set_line_width(cr, 2.0);
  bool penDown = false;
  for (size_t k = 0; k < std::min(series.x.size(), series.y.size()); ++k) {
    if (!data.drawable(series.x[k], series.y[k])) {
      penDown = false;
      continue;
    }
    const double px = data.x.pixel(series.x[k]), py = data.y.pixel(series.y[k]);
    if (penDown) {
      cairo_line_to(cr, px, py);
    } else {
      cairo_move_to(cr, px, py);
    }
    penDown = true;
  }
  cairo_stroke(cr);
  cairo_set_line_width(cr, 1.8);
  for (size_t k = 0;
       series.x.size() <= kMostMarkers && k < std::min(series.x.size(), series.y.size()); ++k) {
    if (data.drawable(series.x[k], series.y[k]))
      drawMarker(cr, static_cast<int>(s), data.x.pixel(series.x[k]), data.y.pixel(series.y[k]),
                 4.5);
  }
}

// Legend: a sample line with the marker per series, a dashed sample per reference slope.
void drawLegend(cairo_t* cr, const LogLogPlot& plot, const PlotFrame& f) {
  const double x = f.right + 14.0, rowHeight = 20.0;
  double y = f.top + 14.0;
  cairo_set_font_size(cr, kTextSize);
  for (size_t s = 0; s < plot.series.size(); ++s, y += rowHeight) {
    const Rgb colour = kPalette[s % (sizeof kPalette / sizeof kPalette[0])];
    cairo_set_source_rgb(cr, colour.r, colour.g, colour.b);
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, x, y);
    cairo_line_to(cr, x + 30.0, y);
    cairo_stroke(cr);
    cairo_set_line_width(cr, 1.8);
    drawMarker(cr, static_cast<int>(s), x + 15.0, y, 4.5);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    cairo_move_to(cr, x + 38.0, y + 4.5);
    cairo_show_text(cr, plot.series[s].label.c_str());
  }
  const double dashes[] = {6.0, 4.0};
  for (size_t r = 0; r < plot.referenceSlopes.size(); ++r, y += rowHeight) {
    const double grey = 0.35 + 0.2 * static_cast<double>(r % 2);
    cairo_set_source_rgb(cr, grey, grey, grey);
    cairo_set_dash(cr, dashes, 2, 0.0);
    cairo_set_line_width(cr, 1.3);
    cairo_move_to(cr, x, y);
    cairo_line_to(cr, x + 30.0, y);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0.0);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    cairo_move_to(cr, x + 38.0, y + 4.5);
    cairo_show_text(cr, plot.referenceSlopes[r].label.c_str());
  }
}

std::string encodePng(cairo_surface_t* surface) {
  cairo_surface_flush(surface);
  std::string png;
  const cairo_status_t status = cairo_surface_write_to_png_stream(surface, appendToString, &png);
  if (status != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(std::string("render plot: cairo could not encode the PNG: ") +
                             cairo_status_to_string(status));
  }
  return png;
}

// The common drawing of both kinds: `plot` with log or linear axes (reference slopes only on
// log-log ones).
std::string renderPlot(const LogLogPlot& plot, bool logarithmic) {
  if (plot.width < 200 || plot.height < 150) {
    throw std::invalid_argument("render plot: a plot needs at least 200 × 150 pixels (got " +
                                std::to_string(plot.width) + " × " + std::to_string(plot.height) +
                                ")");
  }
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, plot.width, plot.height),
                  cairo_surface_destroy);
  Context context(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = context.get();
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);

  PlotData data = plotData(plot, logarithmic);
  const PlotFrame frame = plotFrame(cr, plot, data);
  drawTitleAndAxisLabels(cr, plot, frame);
  drawGridAndFrame(cr, data, frame);
  // Reference slopes (dashed, clipped to the plot area), then the series on top.
  cairo_save(cr);
  cairo_rectangle(cr, frame.left, frame.top, frame.right - frame.left, frame.bottom - frame.top);
  cairo_clip(cr);
  if (data.drawn > 0 && logarithmic) drawReferenceSlopes(cr, plot, data);
  for (size_t s = 0; s < plot.series.size(); ++s) drawSeries(cr, plot.series[s], s, data);
  cairo_restore(cr);
  if (frame.legendWidth > 0.0) drawLegend(cr, plot, frame);
  return encodePng(surface.get());
}

}  // namespace

std::string renderLogLogPlot(const LogLogPlot& plot) {
  return renderPlot(plot, true);
}

std::string renderLinePlot(const LinePlot& plot) {
  LogLogPlot common;
  common.title = plot.title;
  common.xLabel = plot.xLabel;
  common.yLabel = plot.yLabel;
  common.series = plot.series;
  common.width = plot.width;
  common.height = plot.height;
  return renderPlot(common, false);
}

void writeLinePlot(const LinePlot& plot, const std::string& path) {
  modeling::writeFileAtomically(path, renderLinePlot(plot));
}

void writeLogLogPlot(const LogLogPlot& plot, const std::string& path) {
  modeling::writeFileAtomically(path, renderLogLogPlot(plot));
}

}  // namespace flexure::render
