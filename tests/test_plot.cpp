// Log-log and line plots (render/plot.h): a valid PNG of the requested size, read back with Cairo,
// with the series drawn in the plot area; atomic writes; degenerate input.
#include <cairo.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "modeling/errors.h"
#include "render/plot.h"

namespace flexure {
namespace {

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

struct PngReader {
  const std::string* bytes;
  size_t offset = 0;
};

cairo_status_t readFromString(void* closure, unsigned char* data, unsigned int length) {
  auto* reader = static_cast<PngReader*>(closure);
  if (reader->offset + length > reader->bytes->size()) return CAIRO_STATUS_READ_ERROR;
  std::memcpy(data, reader->bytes->data() + reader->offset, length);
  reader->offset += length;
  return CAIRO_STATUS_SUCCESS;
}

Surface decode(const std::string& png) {
  PngReader reader{&png};
  return Surface(cairo_image_surface_create_from_png_stream(readFromString, &reader),
                 cairo_surface_destroy);
}

// Pixels in the rectangle [x0, x1) × [y0, y1) whose colour is saturated (not white, grey or black):
// the series, which alone are drawn in colour.
int colouredPixels(cairo_surface_t* image, int x0, int y0, int x1, int y1) {
  cairo_surface_flush(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  int count = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      std::uint32_t pixel;
      std::memcpy(&pixel, data + y * stride + 4 * x, 4);
      const int r = (pixel >> 16) & 0xff, g = (pixel >> 8) & 0xff, b = pixel & 0xff;
      count += std::max({r, g, b}) - std::min({r, g, b}) > 60;
    }
  }
  return count;
}

render::LogLogPlot refinementPlot() {
  render::LogLogPlot plot;
  plot.title = "Refinement";
  plot.xLabel = "h = 1/n";
  plot.yLabel = "error";
  const std::vector<double> h = {1.0 / 8, 1.0 / 16, 1.0 / 32, 1.0 / 64};
  render::PlotSeries second{"order 2", h, {}}, stalled{"stalls", h, {}};
  for (double x : h) {
    second.y.push_back(0.3 * x * x);
    stalled.y.push_back(0.1);
  }
  plot.series = {second, stalled};
  plot.referenceSlopes = {{2.0, "slope 2"}};
  plot.width = 640;
  plot.height = 420;
  return plot;
}

TEST(LogLogPlot, IsAPngOfTheRequestedSizeWithTheSeriesInThePlotArea) {
  const std::string png = render::renderLogLogPlot(refinementPlot());
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const Surface image = decode(png);
  ASSERT_EQ(cairo_surface_status(image.get()), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(image.get()), 640);
  EXPECT_EQ(cairo_image_surface_get_height(image.get()), 420);
  // The plot area (left of the legend, between title and tick labels) holds coloured curves; the
  // background corners stay white.
  EXPECT_GT(colouredPixels(image.get(), 100, 50, 460, 350), 300);
  EXPECT_EQ(colouredPixels(image.get(), 0, 0, 60, 20), 0);
}

TEST(LogLogPlot, WithoutSeriesThereIsNoColourAndTheAxesStillDraw) {
  render::LogLogPlot plot = refinementPlot();
  for (render::PlotSeries& s : plot.series) s.y.assign(s.y.size(), 0.0);  // nothing drawable
  plot.referenceSlopes.clear();
  const Surface image = decode(render::renderLogLogPlot(plot));
  ASSERT_EQ(cairo_surface_status(image.get()), CAIRO_STATUS_SUCCESS);
  // Only the legend's sample lines are coloured (right of the plot area).
  EXPECT_EQ(colouredPixels(image.get(), 100, 50, 440, 350), 0);
  EXPECT_GT(colouredPixels(image.get(), 440, 40, 640, 120), 0);
}

TEST(LogLogPlot, SameInputSameBytes) {
  EXPECT_EQ(render::renderLogLogPlot(refinementPlot()), render::renderLogLogPlot(refinementPlot()));
}

// A time history on linear axes: negative values are drawn (a log plot would drop them), the
// axes start at the data (t = 0 on the frame's left edge, not a step before), and a long series
// has no markers, only its line.
TEST(LinePlot, DrawsSignedHistoriesOnLinearAxes) {
  render::LinePlot plot;
  plot.title = "Energies";
  plot.xLabel = "time";
  plot.yLabel = "energy";
  render::PlotSeries negative{"gravity", {}, {}};
  for (int k = 0; k <= 400; ++k) {
    negative.x.push_back(k / 400.0);
    negative.y.push_back(-0.02 * (1.0 - std::exp(-5.0 * k / 400.0)));
  }
  plot.series = {negative};
  plot.width = 640;
  plot.height = 420;
  const Surface image = decode(render::renderLinePlot(plot));
  ASSERT_EQ(cairo_surface_status(image.get()), CAIRO_STATUS_SUCCESS);
  EXPECT_GT(colouredPixels(image.get(), 60, 40, 520, 370), 400);
  // The line starts at (0, 0), the frame's top-left corner region: coloured pixels there.
  int firstColumn = 640;
  for (int x = 0; x < 640 && firstColumn == 640; ++x)
    if (colouredPixels(image.get(), x, 40, x + 1, 370) > 0) firstColumn = x;
  EXPECT_LT(firstColumn, 120);
  EXPECT_EQ(render::renderLinePlot(plot), render::renderLinePlot(plot));
}

TEST(LogLogPlot, TooSmallIsRefused) {
  render::LogLogPlot plot = refinementPlot();
  plot.width = 100;
  EXPECT_THROW(render::renderLogLogPlot(plot), std::invalid_argument);
}

TEST(LogLogPlot, WrittenAtomicallyOrNotAtAll) {
  const std::filesystem::path dir = std::filesystem::path(FLEXURE_TEST_TMP) / "plot_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "refinement.png").string();
  render::writeLogLogPlot(refinementPlot(), path);
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_EQ(bytes.str(), render::renderLogLogPlot(refinementPlot()));
  try {
    render::writeLogLogPlot(refinementPlot(), (dir / "no" / "such" / "x.png").string());
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("no/such"));
  }
}

}  // namespace
}  // namespace flexure
