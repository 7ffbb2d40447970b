// The slides' experiment as one figure: every energy's minimizer of the flat-plate test problem
// (rings 0 and 1 of a flat mesh lifted onto z = p(x, y), height mode, midedge's boundary normals
// clamped; linearized, as condition C2 judges it, or nonlinear) on every mesh, rendered alike
// beside the exact sample of p and composed into one labelled grid, with one colour scale over
// the figure for a scalar style. The command-line tool writes it as files; Python returns its
// pixels.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "modeling/mesh.h"
#include "optimize/solvers/minimize.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure::reports {

// One row of the figure: a flat mesh (z = 0), the name its panel files start with and the label
// the figure shows.
struct ComparisonRow {
  modeling::Mesh mesh;
  std::string name;   // "patch48", "mesh-<file stem>"
  std::string label;  // "patch48", "<file name>"
};

struct ComparisonOptions {
  std::vector<ComparisonRow> rows;
  std::vector<std::string> energies;  // the columns after p: specs as parseEnergyVariant reads
  std::string boundary = "quadratic:0.3,-0.7,0.5";  // p, as PolynomialSurface::parse reads it
  bool linearized = true;  // the linearized minimizer (C2's) or the nonlinear one
  render::RenderStyle style = render::RenderStyle::Reflection;
  int size = 400;                   // pixels per panel side, 64 … 4096
  int stripes = 12;                 // the reflection style's stripes
  std::optional<int> cellsPerSide;  // said in the title when the rows are generated families
  optimize::MinimizeOptions solver;

  // InputError naming the field: no row or energy, a row or energy given twice, a size out of
  // range, fewer than kMinComparisonCells cells per side, the displacement style (the panels have
  // no reference mesh).
  void validate() const;
};

// "linearized" | "nonlinear": ComparisonOptions::linearized; InputError naming
// ComparisonOptions.solve otherwise.
bool parseComparisonSolve(std::string_view name);
// The fewest cells per side of a generated row (its rings 0 and 1 held, the rest free).
inline constexpr int kMinComparisonCells = 4;
// One row per plate family (modeling::parsePlateFamily's names), generated at `cellsPerSide`.
// InputError naming ComparisonOptions.cellsPerSide below kMinComparisonCells, or the family.
std::vector<ComparisonRow> familyRows(const std::vector<std::string>& families, int cellsPerSide);

// One minimizer's panel, as compare.json lists it.
struct ComparisonPanel {
  std::string row, energy, image;  // the row's name, the energy's label, the panel's file name
  int vertices = 0;
  bool converged = false;
  std::string solver;
  int iterations = 0;
  double finalEnergy = 0.0;
  double c2Error = 0.0;  // max over the free vertices of |z − p(x, y)| / max |p(x, y)|
};

struct Comparison {
  render::FigureGrid grid;                                    // panels rendered, labelled
  std::vector<ComparisonPanel> panels;                        // the minimizers', row by row
  std::vector<std::pair<std::string, render::Image>> images;  // every panel by its file name
};

// Solves every panel, then renders them with one look; `solved` (when given) hears of each
// panel as its solve ends. `context` must be current on this thread.
Comparison compareEnergies(const ComparisonOptions& options, render::OffscreenContext& context,
                           const std::function<void(const ComparisonPanel&)>& solved = {});

}  // namespace flexure::reports
