#include "reports/comparison_figure.h"

#include <cctype>
#include <cstdio>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "optimize/studies/convergence_study.h"

namespace flexure::reports {
namespace {

std::string formatError(double error) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", error);
  return text;
}

// "patch48-midedge_free.png": the row and the energy spec, other characters as '_'.
std::string panelFileName(const std::string& rowName, const std::string& energySpec) {
  std::string name = rowName + "-" + energySpec;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
  return name + ".png";
}

template <typename Name>
void requireDistinct(const std::vector<Name>& items, const char* field,
                     const std::function<const std::string&(const Name&)>& name) {
  for (size_t i = 0; i < items.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (name(items[i]) == name(items[j]))
        throw InputError(std::string(field) + ": " + name(items[i]) +
                         " is given twice (its panels would overwrite each other)");
}

// The look every panel shares before the figure's colour scale is known.
render::RenderOptions baseLook(const ComparisonOptions& o,
                               const modeling::PolynomialSurface& surface) {
  render::RenderOptions look;
  look.style = o.style;
  look.width = look.height = o.size;
  look.stripeCount = o.stripes;
  if (look.style == render::RenderStyle::Error) look.surface = surface;
  if (look.style == render::RenderStyle::Curvature) look.scalarLabel = "mean curvature H";
  if (look.style == render::RenderStyle::Error || look.style == render::RenderStyle::Curvature)
    look.width += render::kLegendWidth;
  return look;
}

// The surfaces of the figure, [row][column]: p sampled on each row's mesh, then every energy's
// minimizer; their titles in `grid`, their panels in `out.panels`.
using Surfaces = std::vector<std::vector<modeling::Mesh>>;

Surfaces solvePanels(const ComparisonOptions& o, const modeling::PolynomialSurface& surface,
                     const std::function<void(const ComparisonPanel&)>& solved, Comparison& out,
                     std::vector<std::vector<std::string>>& fileNames) {
  std::vector<optimize::EnergyVariant> variants;
  for (const std::string& spec : o.energies) variants.push_back(optimize::parseEnergyVariant(spec));
  Surfaces surfaces;
  for (const ComparisonRow& row : o.rows) {
    out.grid.panelTitles.emplace_back();
    surfaces.emplace_back();
    fileNames.emplace_back();
    // The reference every panel is judged against: z = p(x, y) at the mesh's vertices.
    modeling::Mesh exact = row.mesh;
    modeling::applyHeightField(surface, exact.positions);
    out.grid.panelTitles.back().push_back("C2 = 0 (z = p exactly)");
    surfaces.back().push_back(std::move(exact));
    fileNames.back().push_back(row.name + "-exact.png");
    for (size_t k = 0; k < variants.size(); ++k) {
      const optimize::FlatPlateProblem problem(row.mesh, variants[k].bending);
      const optimize::MinimizeResult result = optimize::solveWithSurfaceBoundary(
          problem, surface, variants[k].normals, o.linearized, o.solver);
      ComparisonPanel panel;
      panel.row = row.name;
      panel.energy = variants[k].label;
      panel.image = panelFileName(row.name, o.energies[k]);
      panel.vertices = row.mesh.vertexCount();
      panel.converged = result.report.converged;
      panel.solver = result.report.solver;
      panel.iterations = result.report.iterations;
      panel.finalEnergy = result.report.finalEnergy;
      panel.c2Error = optimize::reproductionError(problem.rest.positions, result.positions,
                                                  problem.boundary.fixedVertex, surface);
      out.grid.panelTitles.back().push_back("C2 " + formatError(panel.c2Error) +
                                            (panel.converged ? "" : " (not converged)"));
      modeling::Mesh minimizer = row.mesh;
      minimizer.positions = result.positions;
      surfaces.back().push_back(std::move(minimizer));
      fileNames.back().push_back(panel.image);
      if (solved) solved(panel);
      out.panels.push_back(std::move(panel));
    }
  }
  return surfaces;
}

// One colour scale for the figure's scalar style: the error's (log when the panels span decades)
// or the mean curvature's (the percentile rule over every panel's values together).
render::RenderOptions sharedLook(render::RenderOptions look, const Surfaces& surfaces) {
  std::vector<std::vector<double>> fields;
  for (const auto& row : surfaces) {
    for (const modeling::Mesh& surface : row) {
      if (look.style == render::RenderStyle::Error)
        fields.push_back(render::vertexSurfaceErrors(surface, look.surface));
      else if (look.style == render::RenderStyle::Curvature)
        fields.push_back(curvature::defaultMeanCurvatureEnergy().meanCurvatureField(surface));
    }
  }
  if (look.style == render::RenderStyle::Error) {
    const render::ErrorScale scale = render::sharedErrorScale(fields);
    look.errorMax = scale.errorMax;
    look.errorLogFloor = scale.errorLogFloor;
    look.rangeNote = "all panels";
  } else if (look.style == render::RenderStyle::Curvature) {
    std::vector<double> all;
    for (const auto& values : fields) all.insert(all.end(), values.begin(), values.end());
    look.curvatureMax = render::curvatureRange(all);
    look.rangeNote = render::curvatureRangeRule(all) + ", all panels";
  }
  return look;
}

// Every panel rendered with the figure's look (the curvature style's values per panel).
void renderPanels(render::OffscreenContext& context, const render::RenderOptions& look,
                  const Surfaces& surfaces, const std::vector<std::vector<std::string>>& fileNames,
                  Comparison& out) {
  for (size_t r = 0; r < surfaces.size(); ++r) {
    out.grid.panels.emplace_back();
    for (size_t c = 0; c < surfaces[r].size(); ++c) {
      render::RenderOptions panelLook = look;
      if (look.style == render::RenderStyle::Curvature)
        panelLook.vertexScalars =
            curvature::defaultMeanCurvatureEnergy().meanCurvatureField(surfaces[r][c]);
      render::Image image = render::renderMesh(context, surfaces[r][c], panelLook);
      out.grid.panels.back().push_back(image);
      out.images.emplace_back(fileNames[r][c], std::move(image));
    }
  }
}

}  // namespace

bool parseComparisonSolve(std::string_view name) {
  if (name == "linearized") return true;
  if (name == "nonlinear") return false;
  throw InputError("ComparisonOptions.solve " + std::string(name) +
                   ": expected linearized or nonlinear");
}

namespace {

void requireCells(int cellsPerSide) {
  if (cellsPerSide < kMinComparisonCells)
    throw InputError("ComparisonOptions.cellsPerSide " + std::to_string(cellsPerSide) +
                     ": expected at least " + std::to_string(kMinComparisonCells));
}

}  // namespace

std::vector<ComparisonRow> familyRows(const std::vector<std::string>& families, int cellsPerSide) {
  requireCells(cellsPerSide);
  std::vector<ComparisonRow> rows;
  for (const std::string& name : families) {
    modeling::GeneratorOptions generator;
    generator.family = modeling::parsePlateFamily(name);
    generator.n = cellsPerSide;
    const std::string familyName(modeling::meshFamilyName(generator.family));
    rows.push_back({modeling::generateMesh(generator), familyName, familyName});
  }
  return rows;
}

void ComparisonOptions::validate() const {
  if (rows.empty()) throw InputError("ComparisonOptions.rows: give at least one mesh");
  if (energies.empty()) throw InputError("ComparisonOptions.energies: give at least one energy");
  requireDistinct<ComparisonRow>(
      rows, "ComparisonOptions.rows",
      [](const ComparisonRow& row) -> const std::string& { return row.name; });
  requireDistinct<std::string>(energies, "ComparisonOptions.energies",
                               [](const std::string& spec) -> const std::string& { return spec; });
  for (const std::string& spec : energies) {
    try {
      optimize::parseEnergyVariant(spec);
    } catch (const InputError& e) {
      throw InputError(std::string("ComparisonOptions.energies: ") + e.what());
    }
  }
  if (cellsPerSide) requireCells(*cellsPerSide);
  if (size < 64 || size > 4096)
    throw InputError("ComparisonOptions.size " + std::to_string(size) +
                     ": expected 64 .. 4096 pixels");
  if (style == render::RenderStyle::Displacement)
    throw InputError(
        "ComparisonOptions.style displacement: the panels have no reference mesh (use error, "
        "which measures them against p, or curvature)");
}

Comparison compareEnergies(const ComparisonOptions& o, render::OffscreenContext& context,
                           const std::function<void(const ComparisonPanel&)>& solved) {
  o.validate();
  const modeling::PolynomialSurface surface = modeling::PolynomialSurface::parse(o.boundary);
  const std::string styleName(render::renderStyleName(o.style));
  Comparison out;
  out.grid.title =
      std::string(o.linearized ? "Linearized" : "Nonlinear") +
      " minimizers, boundary rings on z = p(x, y), p = " + o.boundary + " (" +
      (o.cellsPerSide ? "n = " + std::to_string(*o.cellsPerSide) + ", " : std::string()) +
      styleName + "). Over each panel its C2 error: max |z - p| / max |p| over the free vertices";
  for (const ComparisonRow& row : o.rows) out.grid.rowLabels.push_back(row.label);
  out.grid.columnLabels.push_back("exact p (reference)");
  for (const std::string& spec : o.energies)
    out.grid.columnLabels.push_back(optimize::parseEnergyVariant(spec).label);
  std::vector<std::vector<std::string>> fileNames;
  const Surfaces surfaces = solvePanels(o, surface, solved, out, fileNames);
  renderPanels(context, sharedLook(baseLook(o, surface), surfaces), surfaces, fileNames, out);
  return out;
}

}  // namespace flexure::reports
