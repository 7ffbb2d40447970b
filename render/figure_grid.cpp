#include "render/figure_grid.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "modeling/errors.h"
#include "render/cairo_image.h"

namespace flexure::render {
namespace {

constexpr const char* kFont = "DejaVu Sans";
constexpr double kTitleSize = 17.0, kLabelSize = 15.0, kPanelTitleSize = 12.5;
constexpr double kTitleBandPadding = 6.0;  // above and below the title's lines
constexpr double kMaxTitleLines = 4;       // then the title shrinks

void checkGrid(const FigureGrid& grid) {
  const auto fail = [](const std::string& what) { throw InputError("figure grid: " + what); };
  if (grid.panels.empty() || grid.panels.front().empty()) fail("no panels");
  const size_t rows = grid.panels.size(), columns = grid.panels.front().size();
  const int w = grid.panels.front().front().width, h = grid.panels.front().front().height;
  if (w <= 0 || h <= 0) fail("empty panel image");
  for (const auto& row : grid.panels) {
    if (row.size() != columns) fail("rows of different lengths");
    for (const Image& panel : row)
      if (panel.width != w || panel.height != h) fail("panels of different sizes");
  }
  if (grid.rowLabels.size() != rows || grid.columnLabels.size() != columns)
    fail("the row and column labels do not match the grid");
  if (!grid.panelTitles.empty()) {
    if (grid.panelTitles.size() != rows) fail("the panel titles do not match the grid");
    for (const auto& row : grid.panelTitles)
      if (row.size() != columns) fail("the panel titles do not match the grid");
  }
}

}  // namespace

Image composeFigureGrid(const FigureGrid& grid) {
  checkGrid(grid);
  const int rows = static_cast<int>(grid.panels.size());
  const int columns = static_cast<int>(grid.panels.front().size());
  const int w = grid.panels.front().front().width, h = grid.panels.front().front().height;
  const int width = kGridRowLabelWidth + columns * (w + kGridGap);

  // The texts are laid out first: the title's lines decide the height of its band.
  CairoSurface measure(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1),
                       &cairo_surface_destroy);
  CairoContext measuring(cairo_create(measure.get()), &cairo_destroy);
  cairo_select_font_face(measuring.get(), kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
  const TextLayout title =
      layOutText(measuring.get(), grid.title, kTitleSize, width - 2.0 * kTextMargin,
                 kMaxTitleLines * kLineSpacing * kTitleSize);
  const int titleHeight = std::max(
      kGridTitleHeight, static_cast<int>(std::ceil(title.height() + 2.0 * kTitleBandPadding)));
  const int height =
      titleHeight + kGridColumnLabelHeight + rows * (kGridPanelTitleHeight + h + kGridGap);

  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height),
                       &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw InputError("figure grid: Cairo cannot make a " + std::to_string(width) + " x " +
                     std::to_string(height) + " image");
  CairoContext context(cairo_create(surface.get()), &cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);
  cairo_surface_flush(surface.get());

  const auto panelLeft = [&](int c) { return kGridRowLabelWidth + c * (w + kGridGap); };
  const auto panelTop = [&](int r) {
    return titleHeight + kGridColumnLabelHeight + r * (kGridPanelTitleHeight + h + kGridGap) +
           kGridPanelTitleHeight;
  };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c)
      paintImage(grid.panels[r][c], surface.get(), panelLeft(c), panelTop(r));
  cairo_surface_mark_dirty(surface.get());

  cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
  showCentred(cr, title, width / 2.0, titleHeight / 2.0);
  for (int c = 0; c < columns; ++c) {
    showCentred(cr,
                layOutText(cr, grid.columnLabels[c], kLabelSize, w - 2.0 * kTextMargin,
                           kGridColumnLabelHeight - 2.0),
                panelLeft(c) + w / 2.0, titleHeight + kGridColumnLabelHeight / 2.0);
  }
  for (int r = 0; r < rows; ++r) {
    showCentred(
        cr,
        layOutText(cr, grid.rowLabels[r], kLabelSize, kGridRowLabelWidth - 2.0 * kTextMargin, h),
        kGridRowLabelWidth / 2.0, panelTop(r) + h / 2.0);
  }
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  for (size_t r = 0; r < grid.panelTitles.size(); ++r) {
    for (int c = 0; c < columns; ++c) {
      showCentred(cr,
                  layOutText(cr, grid.panelTitles[r][c], kPanelTitleSize, w - 2.0 * kTextMargin,
                             kGridPanelTitleHeight - 2.0),
                  panelLeft(c) + w / 2.0,
                  panelTop(static_cast<int>(r)) - kGridPanelTitleHeight / 2.0);
    }
  }
  return imageFromSurface(surface.get());
}

}  // namespace flexure::render
