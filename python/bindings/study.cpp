// flexure._flexure.converge, spectrum and compare_figure: the C1/C2 convergence study and the
// spectrum study with the files `flexure converge` writes (results.json's or spectrum.json's
// content as JSON text, the text tables, the output folder) through the same writers
// (reports/), and the comparison figure `flexure compare` composes (render/figure_grid.h), as
// pixels.
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
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "optimize/boundary_conditions.h"
#include "optimize/studies/convergence_study.h"
#include "optimize/studies/spectrum_study.h"
#include "python/bindings/bindings.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"
#include "reports/comparison_figure.h"
#include "reports/output_files.h"
#include "reports/spectrum_outputs.h"
#include "reports/study_outputs.h"

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
  s.energies = a.energies.empty() ? optimize::defaultEnergyVariants(a.poisson)
                                  : optimize::parseEnergyVariants(a.energies, a.poisson);
  s.families = optimize::parseStudyFamilies(a.families);
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
  s.solver = optimize::parseSolver(a.solver);
  s.hessian = optimize::parseHessianMode(a.hessian);
  s.validate();
  return s;
}

// The spectrum study as Python names it (the CLI's flags of its modes measure without dashes).
struct SpectrumArguments {
  std::vector<std::string> energies;  // empty: the five discretizations once
  std::vector<std::string> families;  // empty: SpectrumStudyOptions' default
  std::vector<std::uint64_t> seeds = {1};
  int n = 8, levels = 3, count = 6;
  std::string support = "simply-supported";
  std::optional<double> poisson;
};

optimize::SpectrumStudyOptions spectrumOptions(const SpectrumArguments& a) {
  optimize::SpectrumStudyOptions s;
  s.energies =
      reports::spectrumEnergies(optimize::parseEnergyVariants(a.energies, a.poisson), a.poisson);
  if (!a.families.empty()) s.families = optimize::parseStudyFamilies(a.families);
  s.seeds = a.seeds;
  s.baseN = a.n;
  s.levels = a.levels;
  s.count = a.count;
  s.support = optimize::parseSupport(a.support);
  s.validate();
  return s;
}

// Writes into `dir` as one batch, all the files or none (modeling::OutputBatch); the files of an
// earlier study there that this one did not write are removed at the commit, as the CLI does.
template <typename Write>
void writeOutputFolder(const std::string& dir, const Write& write) {
  modeling::OutputBatch batch;
  write(dir);
  reports::removeStaleOutputs(dir, [](const std::string& name) {
    return reports::isStudyFile(name) || reports::isSpectrumFile(name);
  });
  batch.commit();
}

// (results.json's text, {"results.csv", "summary.md"} or None); with `outDir` (not empty) the
// files are written there too. The GIL is released during the study and the writes.
py::tuple converge(const StudyArguments& a, bool tables, const std::string& outDir) {
  const optimize::StudyOptions options = studyOptions(a);
  std::string json, csv, markdown;
  {
    py::gil_scoped_release release;
    const optimize::StudyResults results = optimize::runConvergenceStudy(options);
    const optimize::StudySummary summary = optimize::summarizeStudy(options, results);
    json = reports::studyResultsJson(options, results, summary).dump();
    if (tables) {
      csv = reports::studyResultsCsv(options, results);
      markdown = reports::studySummaryMarkdown(options, results, summary);
    }
    if (!outDir.empty()) {
      writeOutputFolder(outDir, [&](const std::string& dir) {
        reports::writeStudyOutputs(options, results, summary, dir);
      });
    }
  }
  py::object files = py::none();
  if (tables) {
    py::dict d;
    d["results.csv"] = csv;
    d["summary.md"] = markdown;
    files = d;
  }
  return py::make_tuple(json, files);
}

// (spectrum.json's text, {"spectrum.csv", "spectrum.md"} or None); `outDir` as converge's.
py::tuple spectrum(const SpectrumArguments& a, bool tables, const std::string& outDir) {
  const optimize::SpectrumStudyOptions options = spectrumOptions(a);
  std::string json, csv, markdown;
  {
    py::gil_scoped_release release;
    const std::vector<optimize::SpectrumSeries> series = optimize::runSpectrumStudy(options);
    json = reports::spectrumJson(options, series).dump();
    if (tables) {
      csv = reports::spectrumCsv(options, series);
      markdown = reports::spectrumMarkdown(options, series);
    }
    if (!outDir.empty()) {
      writeOutputFolder(outDir, [&](const std::string& dir) {
        reports::writeSpectrumOutputs(options, series, dir);
      });
    }
  }
  py::object files = py::none();
  if (tables) {
    py::dict d;
    d["spectrum.csv"] = csv;
    d["spectrum.md"] = markdown;
    files = d;
  }
  return py::make_tuple(json, files);
}

// The comparison figure's arguments (reports/comparison_figure.h composes it).
struct CompareArguments {
  std::vector<std::string> families = {"patch48", "stripe", "delaunay"};
  std::vector<std::string> energies = curvature::energyNameList();
  std::string boundary = "quadratic:0.3,-0.7,0.5";
  int n = 16;
  std::string solve = "linearized";
  std::string style = "reflection";
  int size = 400, stripes = 12, threads = 2;
};

// The figure's options from Python's arguments; the families' meshes generated.
reports::ComparisonOptions comparisonOptions(const CompareArguments& a) {
  reports::ComparisonOptions o;
  o.rows = reports::familyRows(a.families, a.n);
  o.energies = a.energies;
  o.boundary = a.boundary;
  o.linearized = reports::parseComparisonSolve(a.solve);
  o.style = render::parseRenderStyle(a.style);
  o.size = a.size;
  o.stripes = a.stripes;
  o.cellsPerSide = a.n;
  o.solver.threads = a.threads;
  return o;
}

// (H × W × 3 uint8 figure, the panels' C2 errors as compare.json's "panels").
py::tuple compareFigure(const CompareArguments& a) {
  // A context of its own: the figure's panels are rendered and composed here, the GIL held
  // (OSMesa's current context is per thread).
  render::OffscreenContext context;
  context.makeCurrent();
  const reports::Comparison comparison = reports::compareEnergies(comparisonOptions(a), context);
  const render::Image figure = render::composeFigureGrid(comparison.grid);
  py::list panels;
  for (const reports::ComparisonPanel& p : comparison.panels) {
    py::dict panel;
    panel["family"] = p.row;
    panel["energy"] = p.energy;
    panel["c2_error"] = p.c2Error;
    panel["converged"] = p.converged;
    panel["iterations"] = p.iterations;
    panel["final_energy"] = p.finalEnergy;
    panels.append(panel);
  }
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
  m.def("converge", &converge, py::arg("arguments"), py::arg("tables"), py::arg("out_dir"));
  py::class_<SpectrumArguments>(m, "SpectrumArguments")
      .def(py::init<>())
      .def_readwrite("energies", &SpectrumArguments::energies)
      .def_readwrite("families", &SpectrumArguments::families)
      .def_readwrite("seeds", &SpectrumArguments::seeds)
      .def_readwrite("n", &SpectrumArguments::n)
      .def_readwrite("levels", &SpectrumArguments::levels)
      .def_readwrite("count", &SpectrumArguments::count)
      .def_readwrite("support", &SpectrumArguments::support)
      .def_readwrite("poisson", &SpectrumArguments::poisson);
  m.def("spectrum", &spectrum, py::arg("arguments"), py::arg("tables"), py::arg("out_dir"));
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
