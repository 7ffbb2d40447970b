// flexure._flexure.converge and compare_figure: the C1/C2 convergence study's records, refinement
// fits and summary as `flexure converge` writes them to results.json (same field names, same
// values), and the comparison figure `flexure compare` composes (render/figure_grid.h), as pixels.
//
// The study's tables (summary.md, results.csv) and plots are written by cli/study_outputs.cpp,
// which is not in the library: Python gets the data those files are made from.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "optimize/boundary_conditions.h"
#include "optimize/studies/convergence_study.h"
#include "python/bindings/bindings.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

using optimize::RecordKind;

// The study as Python names it (the CLI's flags without dashes).
struct StudyArguments {
  std::vector<std::string> energies;  // empty: the spec's seven rows
  std::vector<std::string> families = {"patch48", "stripe", "criss", "delaunay"};
  std::vector<std::uint64_t> seeds = {1};
  int n = 8, levels = 3, amplitudes = 4, threads = 2;
  std::vector<std::array<double, 3>> quadratics;      // empty: the default five
  std::string solution = optimize::kDefaultSolution;  // "" or "none": no refinement
  std::optional<double> poisson;
  std::string solver = "newton", hessian = "exact";
};

optimize::StudyOptions studyOptions(const StudyArguments& a) {
  optimize::StudyOptions s;
  s.energies.clear();
  if (a.energies.empty()) s.energies = optimize::defaultEnergyVariants(a.poisson);
  for (const std::string& spec : a.energies) {
    try {
      s.energies.push_back(optimize::parseEnergyVariant(spec, a.poisson));
    } catch (const InputError& e) {
      throw InputError(std::string("energies: ") + e.what());
    }
  }
  s.families.clear();
  for (const std::string& name : a.families) {
    try {
      s.families.push_back(modeling::parseMeshFamily(name));
    } catch (const InputError& e) {
      throw InputError(std::string("families: ") + e.what());
    }
  }
  s.seeds = a.seeds;
  s.baseN = a.n;
  s.levels = a.levels;
  if (!a.quadratics.empty()) {
    s.quadratics.clear();
    for (const auto& q : a.quadratics) s.quadratics.push_back({q[0], q[1], q[2]});
  }
  s.amplitudes = a.amplitudes;
  s.solution = a.solution == "none" ? "" : a.solution;
  s.threads = a.threads;
  if (a.solver == "newton")
    s.solver = optimize::Solver::Newton;
  else if (a.solver == "ceres")
    s.solver = optimize::Solver::Ceres;
  else
    throw InputError("solver " + a.solver + ": expected newton or ceres");
  if (a.hessian == "exact")
    s.hessian = optimize::HessianMode::Exact;
  else if (a.hessian == "projected")
    s.hessian = optimize::HessianMode::Projected;
  else
    throw InputError("hessian " + a.hessian + ": expected exact or projected");
  s.validate();
  return s;
}

py::object optional(const std::optional<double>& v) {
  return v ? py::object(py::float_(*v)) : py::object(py::none());
}

std::string refinementText(optimize::Refinement r) {
  return std::string(optimize::refinementName(r));
}

// results.json's "options" of an energy (cli/study_outputs.cpp's energyJson).
py::dict energyDict(const optimize::EnergyVariant& v) {
  const curvature::EnergyEntry& entry = curvature::energyEntry(v.bending.discretization);
  py::dict d;
  d["label"] = v.label;
  d["energy"] = std::string(curvature::discretizationName(v.bending.discretization));
  d["poisson"] = curvature::effectivePoisson(v.bending);
  d["stiffness"] = v.bending.stiffness;
  if (entry.readsVertexArea)
    d["vertex_area"] =
        v.bending.vertexArea == curvature::VertexArea::Barycentric ? "barycentric" : "voronoi";
  if (entry.readsHingeAngle)
    d["hinge_angle"] = v.bending.hingeAngle == curvature::HingeAngle::Tan ? "tan" : "theta";
  if (entry.restEdgeUnknowns)
    d["boundary_normals"] = v.normals == optimize::BoundaryNormals::Free ? "free" : "clamped";
  return d;
}

// One record of results.json's "records".
py::dict recordDict(const optimize::StudyOptions& o, const optimize::StudyRecord& r) {
  py::dict d;
  d["kind"] = std::string(optimize::recordKindName(r.kind));
  d["energy"] = o.energies[r.energy].label;
  d["options"] = energyDict(o.energies[r.energy]);
  d["family"] = r.family;
  d["seed"] = r.seed ? py::object(py::int_(*r.seed)) : py::object(py::none());
  d["n"] = r.n ? py::object(py::int_(*r.n)) : py::object(py::none());
  d["level"] = r.level;
  d["h"] = r.h;
  d["vertices"] = r.vertices;
  d["free_vertices"] = r.freeVertices;
  d["factorizations"] = r.factorizations;
  switch (r.kind) {
    case RecordKind::Quadratic:
      d["quadratic"] = r.data;
      d["energy_per_area"] = optional(r.energyPerArea);
      d["density"] = optional(r.density);
      d["c1"] = optional(r.c1Error);
      d["c1_verdict"] = r.c1Error ? py::object(py::str(std::string(optimize::reproductionName(
                                        optimize::classifyReproduction(*r.c1Error)))))
                                  : py::object(py::none());
      d["c2"] = r.c2Error;
      d["c2_verdict"] =
          std::string(optimize::reproductionName(optimize::classifyReproduction(r.c2Error)));
      break;
    case RecordKind::NonlinearC2:
      d["quadratic"] = r.data;
      d["amplitudes"] = r.nonlinear.amplitudes;
      d["errors"] = r.nonlinear.errors;
      d["order"] = optional(r.nonlinear.order);
      d["converged"] = r.nonlinear.converged;
      break;
    case RecordKind::Refinement:
      d["solution"] = r.data;
      d["error"] = r.solutionError;
      d["discrete_energy"] = r.discreteEnergy;
      d["exact_energy"] = r.exactEnergy;
      d["energy_error"] = r.energyError;
      d["order"] = optional(r.order);
      d["energy_order"] = optional(r.energyOrder);
      d["verdict"] = refinementText(r.verdict);
      d["energy_verdict"] = refinementText(r.energyVerdict);
      break;
  }
  return d;
}

py::list fitList(const optimize::StudyOptions& o, const optimize::StudyResults& results) {
  py::list fits;
  for (const optimize::RefinementFit& f : results.refinements) {
    py::dict d;
    d["energy"] = o.energies[f.energy].label;
    d["family"] = f.family;
    d["seed"] = f.seed ? py::object(py::int_(*f.seed)) : py::object(py::none());
    d["n"] = f.n;
    d["h"] = f.h;
    d["errors"] = f.solutionErrors;
    d["energy_errors"] = f.energyErrors;
    d["order"] = optional(f.order);
    d["energy_order"] = optional(f.energyOrder);
    d["verdict"] = refinementText(f.verdict);
    d["energy_verdict"] = refinementText(f.energyVerdict);
    fits.append(d);
  }
  return fits;
}

py::list summaryList(const optimize::StudySummary& s) {
  py::list table;
  for (size_t e = 0; e < s.energies.size(); ++e) {
    for (size_t f = 0; f < s.families.size(); ++f) {
      const optimize::SummaryCell& c = s.cells[e][f];
      py::dict d;
      d["energy"] = s.energies[e];
      d["family"] = s.families[f];
      d["c1"] = optional(c.worstC1);
      d["c1_verdict"] = c.c1 ? py::object(py::str(std::string(optimize::reproductionName(*c.c1))))
                             : py::object(py::none());
      d["c2"] = c.worstC2;
      d["c2_verdict"] = std::string(optimize::reproductionName(c.c2));
      d["nonlinear_c2_order"] = optional(c.nonlinearOrder);
      d["nonlinear_converged"] = c.nonlinearConverged;
      d["refinement_order"] = optional(c.refinementOrder);
      d["refinement_verdict"] = refinementText(c.refinement);
      d["energy_order"] = optional(c.energyOrder);
      d["energy_verdict"] = refinementText(c.energyRefinement);
      table.append(d);
    }
  }
  return table;
}

// {"records", "refinement", "summary"}: results.json's lists of the same names.
py::dict converge(const StudyArguments& a) {
  const optimize::StudyOptions options = studyOptions(a);
  optimize::StudyResults results;
  optimize::StudySummary summary;
  {
    py::gil_scoped_release release;
    results = optimize::runConvergenceStudy(options);
    summary = optimize::summarizeStudy(options, results);
  }
  py::list records;
  for (const optimize::StudyRecord& r : results.records) records.append(recordDict(options, r));
  py::dict d;
  d["records"] = records;
  d["refinement"] = fitList(options, results);
  d["summary"] = summaryList(summary);
  return d;
}

// The comparison figure as the CLI's runCompare composes it (cli/compare_command.cpp).
struct CompareArguments {
  std::vector<std::string> families = {"patch48", "stripe", "delaunay"};
  std::vector<std::string> energies = curvature::energyNameList();
  std::string boundary = "quadratic:0.3,-0.7,0.5";
  int n = 16;
  std::string solve = "linearized";
  std::string style = "reflection";
  int size = 400, stripes = 12, threads = 2;
};

std::string formatError(double error) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", error);
  return text;
}

render::FigureGrid compareGrid(const CompareArguments& a, render::OffscreenContext& context,
                               py::list& panels) {
  if (a.families.empty()) throw InputError("families: give at least one mesh family");
  if (a.energies.empty()) throw InputError("energies: give at least one energy");
  if (a.size < 64 || a.size > 4096)
    throw InputError("size " + std::to_string(a.size) + ": expected 64 .. 4096 pixels");
  if (a.solve != "linearized" && a.solve != "nonlinear")
    throw InputError("solve " + a.solve + ": expected linearized or nonlinear");
  if (a.n < 4) throw InputError("n " + std::to_string(a.n) + ": expected at least 4");
  std::vector<optimize::EnergyVariant> variants;
  for (const std::string& spec : a.energies) variants.push_back(optimize::parseEnergyVariant(spec));
  const modeling::PolynomialSurface surface = modeling::PolynomialSurface::parse(a.boundary);
  render::RenderOptions look;
  look.style = render::parseRenderStyle(a.style);
  look.width = look.height = a.size;
  look.stripeCount = a.stripes;
  if (look.style == render::RenderStyle::Error) {
    look.surface = surface;
    look.width += render::kLegendWidth;
  }
  optimize::MinimizeOptions solver;
  solver.threads = a.threads;
  render::FigureGrid grid;
  grid.title = std::string(a.solve == "linearized" ? "Linearized" : "Nonlinear") +
               " minimizers, boundary rings on z = p(x, y), p = " + a.boundary +
               " (n = " + std::to_string(a.n) + ", " +
               std::string(render::renderStyleName(look.style)) +
               "). Over each panel its C2 error: max |z - p| / max |p| over the free vertices";
  grid.columnLabels.push_back("exact p (reference)");
  for (const auto& v : variants) grid.columnLabels.push_back(v.label);
  for (const std::string& name : a.families) {
    modeling::GeneratorOptions generator;
    generator.family = modeling::parseMeshFamily(name);
    generator.n = a.n;
    const modeling::Mesh mesh = modeling::generateMesh(generator);
    const std::string familyName(modeling::meshFamilyName(generator.family));
    grid.rowLabels.push_back(familyName);
    grid.panels.emplace_back();
    grid.panelTitles.emplace_back();
    modeling::Mesh exact = mesh;
    modeling::applyHeightField(surface, exact.positions);
    grid.panels.back().push_back(render::renderMesh(context, exact, look));
    grid.panelTitles.back().push_back("C2 = 0 (z = p exactly)");
    for (const optimize::EnergyVariant& variant : variants) {
      const optimize::FlatPlateProblem problem(mesh, variant.bending);
      const optimize::MinimizeResult result = optimize::solveWithSurfaceBoundary(
          problem, surface, variant.normals, a.solve == "linearized", solver);
      const double error = optimize::reproductionError(problem.rest.positions, result.positions,
                                                       problem.boundary.fixedVertex, surface);
      modeling::Mesh minimizer = mesh;
      minimizer.positions = result.positions;
      grid.panels.back().push_back(render::renderMesh(context, minimizer, look));
      grid.panelTitles.back().push_back("C2 " + formatError(error) +
                                        (result.report.converged ? "" : " (not converged)"));
      py::dict panel;
      panel["family"] = familyName;
      panel["energy"] = variant.label;
      panel["c2_error"] = error;
      panel["converged"] = result.report.converged;
      panel["iterations"] = result.report.iterations;
      panel["final_energy"] = result.report.finalEnergy;
      panels.append(panel);
    }
  }
  return grid;
}

// (H × W × 3 uint8 figure, the panels' C2 errors as compare.json's "panels").
py::tuple compareFigure(const CompareArguments& a) {
  // A context of its own: the figure's panels are rendered and composed here, the GIL held
  // (OSMesa's current context is per thread).
  render::OffscreenContext context;
  context.makeCurrent();
  py::list panels;
  const render::Image figure = render::composeFigureGrid(compareGrid(a, context, panels));
  py::array_t<std::uint8_t> pixels(
      {py::ssize_t(figure.height), py::ssize_t(figure.width), py::ssize_t(3)});
  auto w = pixels.mutable_unchecked<3>();
  for (int y = 0; y < figure.height; ++y)
    for (int x = 0; x < figure.width; ++x) {
      const std::size_t i = 4 * (static_cast<std::size_t>(y) * figure.width + x);
      for (int c = 0; c < 3; ++c) w(y, x, c) = figure.rgba[i + c];
    }
  return py::make_tuple(pixels, panels);
}

}  // namespace

void bindStudy(py::module_& m) {
  py::class_<StudyArguments>(m, "StudyArguments")
      .def(py::init<>())
      .def_readwrite("energies", &StudyArguments::energies)
      .def_readwrite("families", &StudyArguments::families)
      .def_readwrite("seeds", &StudyArguments::seeds)
      .def_readwrite("n", &StudyArguments::n)
      .def_readwrite("levels", &StudyArguments::levels)
      .def_readwrite("amplitudes", &StudyArguments::amplitudes)
      .def_readwrite("threads", &StudyArguments::threads)
      .def_readwrite("quadratics", &StudyArguments::quadratics)
      .def_readwrite("solution", &StudyArguments::solution)
      .def_readwrite("poisson", &StudyArguments::poisson)
      .def_readwrite("solver", &StudyArguments::solver)
      .def_readwrite("hessian", &StudyArguments::hessian);
  m.def("converge", &converge, py::arg("arguments"));
  py::class_<CompareArguments>(m, "CompareArguments")
      .def(py::init<>())
      .def_readwrite("families", &CompareArguments::families)
      .def_readwrite("energies", &CompareArguments::energies)
      .def_readwrite("boundary", &CompareArguments::boundary)
      .def_readwrite("n", &CompareArguments::n)
      .def_readwrite("solve", &CompareArguments::solve)
      .def_readwrite("style", &CompareArguments::style)
      .def_readwrite("size", &CompareArguments::size)
      .def_readwrite("stripes", &CompareArguments::stripes)
      .def_readwrite("threads", &CompareArguments::threads);
  m.def("compare_figure", &compareFigure, py::arg("arguments"));
}

}  // namespace flexure::python
