// A labelled grid of equally sized images (Cairo): a title on top, column labels above the
// columns, row labels left of the rows, and a title above every panel. PNG out through
// encodePng / writePng (mesh_renderer.h), written atomically.
//
// Layout (pixels; w × h the panel size, R rows, C columns, T the title band's height):
//   width  = kGridRowLabelWidth + C · (w + kGridGap)
//   height = T + kGridColumnLabelHeight + R · (kGridPanelTitleHeight + h + kGridGap)
// Panel (r, c) has its top-left corner at
//   x = kGridRowLabelWidth + c · (w + kGridGap),
//   y = T + kGridColumnLabelHeight + r · (kGridPanelTitleHeight + h + kGridGap)
//       + kGridPanelTitleHeight,
// the panel title in the kGridPanelTitleHeight band above it. The background is white.
//
// Every text fits its band (the figure's width less a margin for the title, the panel's width for
// column labels and panel titles, kGridRowLabelWidth for row labels): set at the largest size, from
// its nominal size down to 7 pt, at which its words wrapped at spaces fit, else shrunk on one line.
// T is kGridTitleHeight, or more when the title wraps (at most 4 lines; it shrinks beyond).
#pragma once

#include <string>
#include <vector>

#include "render/mesh_renderer.h"

namespace flexure::render {

inline constexpr int kGridRowLabelWidth = 110;
inline constexpr int kGridTitleHeight = 36;
inline constexpr int kGridColumnLabelHeight = 26;
inline constexpr int kGridPanelTitleHeight = 22;
inline constexpr int kGridGap = 10;

struct FigureGrid {
  std::string title;
  std::vector<std::string> rowLabels, columnLabels;   // R and C labels
  std::vector<std::vector<Image>> panels;             // [row][column]: R × C images of one size
  std::vector<std::vector<std::string>> panelTitles;  // [row][column], or empty: no titles
};

// The composed figure. Throws InputError when the grid is empty, the rows are ragged, the panels
// differ in size, or the label or title counts do not match the grid.
Image composeFigureGrid(const FigureGrid& grid);

}  // namespace flexure::render
