#include "render/figure_grid.h"

#include <cairo.h>

#include <cstdint>
#include <memory>

#include "modeling/errors.h"
#include "render/cairo_image.h"

namespace flexure::render {
namespace {

constexpr const char* kFont = "DejaVu Sans";
constexpr double kTitleSize = 17.0, kLabelSize = 15.0, kPanelTitleSize = 12.5;

// `text` centred horizontally on `centreX`, baseline at `baseline`.
void showCentred(cairo_t* cr, const std::string& text, double size, double centreX,
                 double baseline) {
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  cairo_move_to(cr, centreX - extents.x_advance / 2.0, baseline);
  cairo_show_text(cr, text.c_str());
}

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
  const int height =
      kGridTitleHeight + kGridColumnLabelHeight + rows * (kGridPanelTitleHeight + h + kGridGap);
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
    return kGridTitleHeight + kGridColumnLabelHeight + r * (kGridPanelTitleHeight + h + kGridGap) +
           kGridPanelTitleHeight;
  };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c)
      paintImage(grid.panels[r][c], surface.get(), panelLeft(c), panelTop(r));
  cairo_surface_mark_dirty(surface.get());

  cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
  showCentred(cr, grid.title, kTitleSize, width / 2.0, kGridTitleHeight - 12.0);
  for (int c = 0; c < columns; ++c) {
    showCentred(cr, grid.columnLabels[c], kLabelSize, panelLeft(c) + w / 2.0,
                kGridTitleHeight + kGridColumnLabelHeight - 8.0);
  }
  for (int r = 0; r < rows; ++r) {
    showCentred(cr, grid.rowLabels[r], kLabelSize, kGridRowLabelWidth / 2.0,
                panelTop(r) + h / 2.0 + 0.35 * kLabelSize);
  }
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  for (size_t r = 0; r < grid.panelTitles.size(); ++r) {
    for (int c = 0; c < columns; ++c) {
      showCentred(cr, grid.panelTitles[r][c], kPanelTitleSize, panelLeft(c) + w / 2.0,
                  panelTop(static_cast<int>(r)) - 7.0);
    }
  }
  return imageFromSurface(surface.get());
}

}  // namespace flexure::render
