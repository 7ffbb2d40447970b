// The figure grid (render/figure_grid.h): its size follows the layout constants exactly, every
// panel lands where the layout says (its pixels are not all background), labels are drawn, and a
// malformed grid is an InputError.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure {
namespace {

using render::Image;

bool isWhite(const Image& image, int x, int y) {
  const auto p = image.pixel(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

// Pixels in the rectangle [left, left + width) × [top, top + height) that are not white.
int inkIn(const Image& image, int left, int top, int width, int height) {
  int count = 0;
  for (int y = top; y < top + height; ++y)
    for (int x = left; x < left + width; ++x) count += isWhite(image, x, y) ? 0 : 1;
  return count;
}

Image filled(int width, int height, std::uint8_t grey) {
  Image image;
  image.width = width;
  image.height = height;
  image.rgba.assign(static_cast<std::size_t>(4) * width * height, grey);
  for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;
  return image;
}

render::FigureGrid grid(int rows, int columns, const Image& panel) {
  render::FigureGrid g;
  g.title = "title";
  for (int r = 0; r < rows; ++r) {
    g.rowLabels.push_back("row " + std::to_string(r));
    g.panels.emplace_back(columns, panel);
    g.panelTitles.emplace_back(columns, "panel");
  }
  for (int c = 0; c < columns; ++c) g.columnLabels.push_back("column " + std::to_string(c));
  return g;
}

TEST(FigureGrid, SizeFollowsTheLayout) {
  // 110 + 3 (120 + 10) = 500 wide; 36 + 26 + 2 (22 + 80 + 10) = 286 high.
  const Image figure = render::composeFigureGrid(grid(2, 3, filled(120, 80, 40)));
  EXPECT_EQ(figure.width, 500);
  EXPECT_EQ(figure.height, 286);
  ASSERT_EQ(figure.rgba.size(), 4u * 500 * 286);
}

TEST(FigureGrid, EveryRenderedPanelIsInPlaceAndLabelsAreDrawn) {
  // Three reflection renders of a bowl, as `flexure compare` makes them, on a 1 × 3 grid.
  modeling::GeneratorOptions generator;
  generator.n = 8;
  modeling::Mesh bowl = modeling::generateMesh(generator);
  modeling::applyHeightField(modeling::PolynomialSurface::parse("quadratic:1,0,1"), bowl.positions);
  render::RenderOptions look;
  look.width = look.height = 96;
  render::OffscreenContext context;
  const Image panel = render::renderMesh(context, bowl, look);
  const Image figure = render::composeFigureGrid(grid(1, 3, panel));
  ASSERT_EQ(figure.width, 110 + 3 * (96 + 10));
  ASSERT_EQ(figure.height, 36 + 26 + 22 + 96 + 10);
  const int top =
      render::kGridTitleHeight + render::kGridColumnLabelHeight + render::kGridPanelTitleHeight;
  for (int c = 0; c < 3; ++c) {
    const int left = render::kGridRowLabelWidth + c * (96 + render::kGridGap);
    // The panel is copied pixel for pixel.
    int same = 0;
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x) same += figure.pixel(left + x, top + y) == panel.pixel(x, y);
    EXPECT_EQ(same, 96 * 96) << "panel " << c;
    EXPECT_GT(inkIn(figure, left, top, 96, 96), 96 * 96 / 4) << "panel " << c << " is empty";
    // Its title and its column label.
    EXPECT_GT(
        inkIn(figure, left, top - render::kGridPanelTitleHeight, 96, render::kGridPanelTitleHeight),
        10);
    EXPECT_GT(inkIn(figure, left, render::kGridTitleHeight, 96, render::kGridColumnLabelHeight),
              10);
  }
  EXPECT_GT(inkIn(figure, 0, top, render::kGridRowLabelWidth, 96), 10) << "no row label";
  EXPECT_GT(inkIn(figure, 0, 0, figure.width, render::kGridTitleHeight), 10) << "no title";
  // The gaps stay white.
  EXPECT_EQ(inkIn(figure, render::kGridRowLabelWidth + 96, top, render::kGridGap, 96), 0);
}

// Pixels on the image's border that are not white.
int inkOnBorder(const Image& image) {
  return inkIn(image, 0, 0, image.width, 1) + inkIn(image, 0, image.height - 1, image.width, 1) +
         inkIn(image, 0, 0, 1, image.height) + inkIn(image, image.width - 1, 0, 1, image.height);
}

// `flexure compare`'s texts at the smallest and the largest panel size it allows (64 and 4096
// pixels): every text stays inside the image and inside its panel's column (the gaps between
// columns stay white above the panels), and the title is still drawn.
TEST(FigureGrid, TextFitsAtTheSmallestAndLargestPanelSizes) {
  for (const auto& [size, columns] : {std::pair{64, 5}, std::pair{4096, 1}}) {
    render::FigureGrid g = grid(3, columns, filled(size, size, 40));
    g.title =
        "Linearized minimizers, boundary quadratic:0.3,-0.7,0.5, n = 16, reflection lines; "
        "C2 error = max |z - p| / max |p| over the free vertices";
    g.rowLabels = {"patch48", "stripe", "delaunay-with-a-long-name"};
    for (int c = 0; c < columns; ++c) {
      g.columnLabels[c] = "cotan:barycentric";
      for (int r = 0; r < 3; ++r) g.panelTitles[r][c] = "C2 1.23e-02 (not converged)";
    }
    const Image figure = render::composeFigureGrid(g);
    EXPECT_EQ(inkOnBorder(figure), 0) << "panel size " << size;
    const int firstPanelTop = figure.height - 3 * (size + render::kGridGap) -
                              2 * render::kGridPanelTitleHeight;  // below the title's band
    EXPECT_GT(inkIn(figure, 0, 0, figure.width,
                    firstPanelTop - render::kGridPanelTitleHeight - render::kGridColumnLabelHeight),
              10)
        << "no title at panel size " << size;
    for (int c = 0; c < columns; ++c) {
      const int gapLeft = render::kGridRowLabelWidth + c * (size + render::kGridGap) + size;
      EXPECT_EQ(
          inkIn(figure, gapLeft,
                0 + firstPanelTop - render::kGridPanelTitleHeight - render::kGridColumnLabelHeight,
                render::kGridGap, render::kGridColumnLabelHeight + render::kGridPanelTitleHeight),
          0)
          << "a label spills out of column " << c << " at panel size " << size;
    }
  }
}

TEST(FigureGrid, MalformedGridsAreInputErrors) {
  EXPECT_THROW(render::composeFigureGrid({}), InputError);
  render::FigureGrid ragged = grid(2, 2, filled(40, 40, 0));
  ragged.panels[1].pop_back();
  EXPECT_THROW(render::composeFigureGrid(ragged), InputError);
  render::FigureGrid sizes = grid(1, 2, filled(40, 40, 0));
  sizes.panels[0][1] = filled(40, 41, 0);
  EXPECT_THROW(render::composeFigureGrid(sizes), InputError);
  render::FigureGrid labels = grid(1, 2, filled(40, 40, 0));
  labels.columnLabels.pop_back();
  EXPECT_THROW(render::composeFigureGrid(labels), InputError);
}

}  // namespace
}  // namespace flexure
