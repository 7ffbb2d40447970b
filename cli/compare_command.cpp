// flexure compare: the slides' experiment. Every energy's minimizer of the flat-plate test problem
// (two fixed rings lifted onto a quadratic, height mode, midedge boundary normals clamped;
// linearized by default, as condition C2 judges it, or nonlinear) on every mesh family, rendered
// the same way beside the exact sample of p and composed into one labelled grid.
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/compare_command.h"
#include "cli/mesh_json.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "optimize/studies/convergence_study.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"
#include "reports/comparison_figure.h"

namespace flexure::cli {
namespace {

// The files compare writes: compare.png, compare.json and the panels <family>-<energy>.png.
bool isCompareFile(const std::string& name) {
  if (name == "compare.png" || name == "compare.json") return true;
  const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
  for (const char* family : {"patch48-", "stripe-", "criss-", "delaunay-", "mesh-"})
    if (png && name.rfind(family, 0) == 0) return true;
  return false;
}

// The options that need no mesh: both lists given, the sizes and the solve kind.
void checkCompareOptions(const CompareOptions& o) {
  if (o.families.empty() && o.meshFiles.empty())
    throw InputError("--families: give at least one mesh family (or --mesh FILE)");
  reports::parseComparisonSolve(o.solve);
}

// The rows: one generated mesh per family, with the family's name, then the user's meshes, named
// mesh-<file stem> (the row label the file name).
struct CompareFamilies {
  std::vector<modeling::Mesh> meshes;
  std::vector<std::string> names, labels;
};

// A user's mesh for the test problem: flat, z = 0 at every vertex (the rings are lifted onto p).
modeling::Mesh readFlatMesh(const std::string& path) {
  modeling::Mesh mesh = modeling::readMesh(path);
  const double height = mesh.positions.col(2).cwiseAbs().maxCoeff();
  const double extent =
      (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).maxCoeff();
  if (height > 1e-12 * extent) {
    char text[64];
    std::snprintf(text, sizeof text, "%.3g", height);
    throw InputError("--mesh " + path +
                     ": the test problem lifts a flat mesh (z = 0 at every vertex) onto z = p(x, "
                     "y); this one has |z| up to " +
                     text);
  }
  return mesh;
}

CompareFamilies generateFamilies(const CompareOptions& o) {
  CompareFamilies families;
  for (const std::string& name : o.families) {
    modeling::GeneratorOptions generator;
    try {
      generator.family = modeling::parsePlateFamily(name);
    } catch (const InputError& e) {
      throw InputError(std::string("--families: ") + e.what());
    }
    generator.n = o.n;
    families.meshes.push_back(modeling::generateMesh(generator));
    families.names.push_back(std::string(modeling::meshFamilyName(generator.family)));
    families.labels.push_back(families.names.back());
  }
  for (const std::string& path : o.meshFiles) {
    families.meshes.push_back(readFlatMesh(path));
    families.names.push_back("mesh-" + std::filesystem::path(path).stem().string());
    families.labels.push_back(std::filesystem::path(path).filename().string());
  }
  return families;
}

render::RenderStyle compareStyle(const CompareOptions& o) {
  try {
    return render::parseRenderStyle(o.style);
  } catch (const InputError& e) {
    throw InputError(std::string("--style: ") + e.what());
  }
}

void writeCompareFiles(const CompareOptions& o, const std::string& styleName,
                       const std::vector<std::string>& familyNames,
                       const reports::Comparison& comparison, const render::Image& figure) {
  namespace fs = std::filesystem;
  const fs::path dir(o.outputDir);
  nlohmann::json references = nlohmann::json::array(), panels = nlohmann::json::array();
  for (const std::string& family : familyNames)
    references.push_back({{"family", family}, {"image", family + "-exact.png"}});
  for (const reports::ComparisonPanel& p : comparison.panels)
    panels.push_back({{"family", p.row},
                      {"energy", p.energy},
                      {"n", o.n},
                      {"vertices", p.vertices},
                      {"converged", p.converged},
                      {"solver", p.solver},
                      {"iterations", p.iterations},
                      {"final_energy", p.finalEnergy},
                      {"c2_error", p.c2Error},
                      {"image", p.image}});
  modeling::createOutputDirectory(dir.string());
  for (const auto& [name, image] : comparison.images)
    render::writePng((dir / name).string(), image);
  render::writePng((dir / "compare.png").string(), figure);
  writeJsonFile((dir / "compare.json").string(),
                {{"boundary", o.boundary},
                 {"n", o.n},
                 {"solve", o.solve},
                 {"style", styleName},
                 {"references", references},
                 {"size", o.size},
                 {"error", "c2: max over the free vertices of |z - p(x, y)| / max |p(x, y)|"},
                 {"figure", "compare.png"},
                 {"panels", panels}});
}

}  // namespace

void runCompare(const CompareOptions& o, const GlobalOptions& global,
                const std::string& commandName) {
  // Every option is checked, and every mesh generated, before anything is written.
  checkCompareOptions(o);
  const CompareFamilies families = generateFamilies(o);
  reports::ComparisonOptions comparison;
  for (size_t f = 0; f < families.meshes.size(); ++f)
    comparison.rows.push_back({families.meshes[f], families.names[f], families.labels[f]});
  comparison.energies = o.energies;
  comparison.boundary = o.boundary;
  comparison.linearized = reports::parseComparisonSolve(o.solve);
  comparison.style = compareStyle(o);
  comparison.size = o.size;
  comparison.stripes = o.stripes;
  if (!o.families.empty()) comparison.cellsPerSide = o.n;
  comparison.solver.threads = o.threads;
  applySolverArguments(o.solver, comparison.solver);
  comparison.solver.progress = global.verbose && !global.quiet;  // each solve's Newton iterations
  comparison.validate();
  render::OffscreenContext context;  // a missing OSMesa fails here, before any solve
  const auto progress = [&](const reports::ComparisonPanel& p) {
    if (global.quiet) return;
    std::cerr << commandName << ": " << p.row << " " << p.energy << ": C2 " << std::scientific
              << std::setprecision(2) << p.c2Error << std::defaultfloat << ", "
              << counted(p.iterations, "iteration") << '\n';
  };
  const reports::Comparison result = reports::compareEnergies(comparison, context, progress);
  const render::Image figure = render::composeFigureGrid(result.grid);
  writeCompareFiles(o, std::string(render::renderStyleName(comparison.style)), families.names,
                    result, figure);
  if (!global.quiet) {
    const std::filesystem::path dir(o.outputDir);
    std::cerr << commandName << ": wrote " << (dir / "compare.png").string() << " (" << figure.width
              << " x " << figure.height << "), compare.json and " << result.images.size()
              << " panels\n";
  }
}

void registerCompareCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<CompareOptions>();
  CompareOptions& o = *options;
  CLI::App* sub = app.add_subcommand(
      "compare",
      "Minimize every energy on every mesh family and render the minimizers side by side");
  auto files = CommandFiles::of(*sub);
  files
      ->output("-o,--output", o.outputDir,
               "Output directory (created if missing; a previous compare's other files in it are "
               "removed)",
               OutputKind::Directory, isCompareFile)
      ->capture_default_str();
  sub->add_option("--families", o.families,
                  "Mesh families (rows): patch48, stripe, criss, delaunay")
      ->delimiter(',')
      ->capture_default_str();
  files->inputs("--mesh", o.meshFiles,
                "A flat mesh of yours (z = 0) as a row after the families (repeatable; without "
                "--families, the only rows); panels mesh-<stem>-<energy>.png");
  sub->add_option("--energies", o.energies,
                  "Energies (columns): " +
                      curvature::energyNamesWhere([](const auto&) { return true; }, ", ", ", ") +
                      ", ...")
      ->delimiter(',')
      ->capture_default_str();
  sub->add_option("--boundary", o.boundary,
                  "Boundary data: rings 0 and 1 lifted onto z = p(x, y) (quadratic:a,b,c or "
                  "polynomial:EXPR)")
      ->capture_default_str()
      ->check(surfaceSpec());
  sub->add_option("-n,--n", o.n, "Cells per side of the meshes")
      ->capture_default_str()
      ->check(inRange(4, 256));
  sub->add_option("--solve", o.solve,
                  "linearized (the minimizer of E_lin, as condition C2 judges it) | nonlinear (the "
                  "full energy's minimizer at amplitude 1)")
      ->capture_default_str();
  sub->add_option("--style", o.style,
                  "Render style of every panel (see flexure render; error and curvature share one "
                  "colour scale over the figure)")
      ->capture_default_str();
  sub->add_option("--size", o.size, "Panel size in pixels (square)")
      ->capture_default_str()
      ->check(inRange(64, 4096));
  sub->add_option("--stripes", o.stripes, "Stripes per panel")
      ->capture_default_str()
      ->check(inRange(1, 1000));
  sub->add_option("--threads", o.threads, "Solver threads")
      ->capture_default_str()
      ->check(inRange(1, maxThreads()));
  addSolverArguments(*sub, o.solver);
  sub->footer(
      "Writes DIR/compare.png (rows = families; columns = the exact sample of p, then the "
      "energies, each panel titled with its C2 error), DIR/<family>-exact.png, "
      "DIR/<family>-<energy>.png and DIR/compare.json.\n"
      "Example: flexure compare -o cmp --families patch48,delaunay --energies hinge,midedge");
  files->onRun(global, [options, &global, sub] {
    if (!options->meshFiles.empty() && sub->count("--families") == 0) options->families.clear();
    runCompare(*options, global, "flexure compare");
  });
}

}  // namespace flexure::cli
