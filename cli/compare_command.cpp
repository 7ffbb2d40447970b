// flexure compare: the slides' experiment. Every energy's minimizer of the flat-plate test problem
// (two fixed rings lifted onto a quadratic, height mode, midedge boundary normals clamped;
// linearized by default, as condition C2 judges it, or nonlinear) on every mesh family, rendered
// the same way beside the exact sample of p and composed into one labelled grid.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/compare_command.h"
#include "cli/mesh_json.h"
#include "curvature/mean_curvature_field.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "optimize/studies/convergence_study.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure::cli {
namespace {

std::string formatError(double error) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", error);
  return text;
}

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
  if (o.energies.empty()) throw InputError("--energies: give at least one energy");
  if (o.size < 64 || o.size > 4096)
    throw InputError("--size " + std::to_string(o.size) + ": expected 64 .. 4096 pixels");
  if (o.solve != "linearized" && o.solve != "nonlinear")
    throw InputError("--solve " + o.solve + ": expected linearized or nonlinear");
  if (o.n < 4) throw InputError("--n " + std::to_string(o.n) + ": expected at least 4");
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
      generator.family = modeling::parseMeshFamily(name);
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

std::vector<optimize::EnergyVariant> parseVariants(const CompareOptions& o) {
  std::vector<optimize::EnergyVariant> variants;
  for (const std::string& spec : o.energies) {
    try {
      variants.push_back(optimize::parseEnergyVariant(spec));
    } catch (const InputError& e) {
      throw InputError(std::string("--energies: ") + e.what());
    }
  }
  return variants;
}

// Panels are named <family>-<energy spec>.png: a repeated row or column would overwrite one.
void requireDistinct(const CompareOptions& o, const std::vector<std::string>& familyNames) {
  for (size_t i = 0; i < familyNames.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (familyNames[i] == familyNames[j])
        throw InputError((i < o.families.size() ? "--families: " : "--mesh: ") + familyNames[i] +
                         " is given twice");
  for (size_t i = 0; i < o.energies.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (o.energies[i] == o.energies[j])
        throw InputError("--energies: " + o.energies[i] + " is given twice");
}

render::RenderOptions compareLook(const CompareOptions& o,
                                  const modeling::PolynomialSurface& surface) {
  render::RenderOptions look;
  try {
    look.style = render::parseRenderStyle(o.style);
  } catch (const InputError& e) {
    throw InputError(std::string("--style: ") + e.what());
  }
  if (look.style == render::RenderStyle::Displacement)
    throw InputError(
        "--style displacement: compare's panels have no reference mesh (use error, "
        "which measures them against p, or curvature)");
  look.width = look.height = o.size;
  look.stripeCount = o.stripes;
  if (look.style == render::RenderStyle::Error) look.surface = surface;
  if (look.style == render::RenderStyle::Curvature) look.scalarLabel = "mean curvature H";
  if (look.style == render::RenderStyle::Error || look.style == render::RenderStyle::Curvature)
    look.width += render::kLegendWidth;
  return look;
}

// "patch48-midedge_free.png": the family and the energy spec, other characters as '_'.
std::string panelFileName(const std::string& familyName, const std::string& energySpec) {
  std::string name = familyName + "-" + energySpec;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
  return name + ".png";
}

// What the grid, the panel files and compare.json collect, row by row: the surfaces are solved
// first and rendered together, so that a scalar style has one colour scale for the figure.
struct CompareOutputs {
  render::FigureGrid grid;
  nlohmann::json panels = nlohmann::json::array();
  std::vector<std::vector<modeling::Mesh>> surfaces;  // [row][column], as grid.panelTitles
  std::vector<std::vector<std::string>> fileNames;    // [row][column]
  std::vector<std::pair<std::string, render::Image>> files;
};

// What every panel of the grid shares.
struct PanelSettings {
  const std::vector<optimize::EnergyVariant>& variants;  // the columns after the reference
  const modeling::PolynomialSurface& surface;            // the boundary data p
  const optimize::MinimizeOptions& solver;
};

// One row: the exact sample of p, then every energy's minimizer on the family's mesh.
void compareRow(const CompareOptions& o, const GlobalOptions& global,
                const std::string& commandName, const modeling::Mesh& mesh,
                const std::string& familyName, const PanelSettings& settings, CompareOutputs& out) {
  const auto& [variants, surface, solver] = settings;
  const bool linearized = o.solve == "linearized";
  out.grid.panelTitles.emplace_back();
  out.surfaces.emplace_back();
  out.fileNames.emplace_back();
  // The reference every panel is judged against: p sampled at the mesh's vertices, z = p(x, y).
  modeling::Mesh exact = mesh;
  modeling::applyHeightField(surface, exact.positions);
  out.grid.panelTitles.back().push_back("C2 = 0 (z = p exactly)");
  out.surfaces.back().push_back(std::move(exact));
  out.fileNames.back().push_back(familyName + "-exact.png");
  for (size_t k = 0; k < variants.size(); ++k) {
    const optimize::EnergyVariant& variant = variants[k];
    const optimize::FlatPlateProblem problem(mesh, variant.bending);
    const optimize::MinimizeResult result =
        optimize::solveWithSurfaceBoundary(problem, surface, variant.normals, linearized, solver);
    const double error = optimize::reproductionError(problem.rest.positions, result.positions,
                                                     problem.boundary.fixedVertex, surface);
    modeling::Mesh minimizer = mesh;
    minimizer.positions = result.positions;
    const std::string name = panelFileName(familyName, o.energies[k]);
    out.panels.push_back({{"family", familyName},
                          {"energy", variant.label},
                          {"n", o.n},
                          {"vertices", minimizer.vertexCount()},
                          {"converged", result.report.converged},
                          {"solver", result.report.solver},
                          {"iterations", result.report.iterations},
                          {"final_energy", result.report.finalEnergy},
                          {"c2_error", error},
                          {"image", name}});
    out.grid.panelTitles.back().push_back("C2 " + formatError(error) +
                                          (result.report.converged ? "" : " (not converged)"));
    out.surfaces.back().push_back(std::move(minimizer));
    out.fileNames.back().push_back(name);
    if (!global.quiet) {
      std::cerr << commandName << ": " << familyName << " " << variant.label << ": C2 "
                << formatError(error) << ", " << counted(result.report.iterations, "iteration")
                << '\n';
    }
  }
}

// One colour scale for the figure's scalar style: the error's (log when the panels span decades)
// or the mean curvature's (the percentile rule over every panel's values together).
render::RenderOptions sharedLook(render::RenderOptions look, const CompareOutputs& out) {
  std::vector<std::vector<double>> fields;
  for (const auto& row : out.surfaces) {
    for (const modeling::Mesh& surface : row) {
      if (look.style == render::RenderStyle::Error)
        fields.push_back(render::vertexSurfaceErrors(surface, look.surface));
      else if (look.style == render::RenderStyle::Curvature)
        fields.push_back(curvature::cotanVertexMeanCurvature(surface));
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
                  CompareOutputs& out) {
  for (size_t r = 0; r < out.surfaces.size(); ++r) {
    out.grid.panels.emplace_back();
    for (size_t c = 0; c < out.surfaces[r].size(); ++c) {
      render::RenderOptions panelLook = look;
      if (look.style == render::RenderStyle::Curvature)
        panelLook.vertexScalars = curvature::cotanVertexMeanCurvature(out.surfaces[r][c]);
      render::Image image = render::renderMesh(context, out.surfaces[r][c], panelLook);
      out.grid.panels.back().push_back(image);
      out.files.emplace_back(out.fileNames[r][c], std::move(image));
    }
  }
}

void writeCompareFiles(const CompareOptions& o, const std::string& styleName,
                       const std::vector<std::string>& familyNames, const CompareOutputs& out,
                       const render::Image& figure) {
  namespace fs = std::filesystem;
  const fs::path dir(o.outputDir);
  nlohmann::json references = nlohmann::json::array();
  for (const std::string& family : familyNames)
    references.push_back({{"family", family}, {"image", family + "-exact.png"}});
  modeling::createOutputDirectory(dir.string());
  for (const auto& [name, image] : out.files) render::writePng((dir / name).string(), image);
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
                 {"panels", out.panels}});
}

}  // namespace

void runCompare(const CompareOptions& o, const GlobalOptions& global,
                const std::string& commandName) {
  // Every option is checked, and every mesh generated, before anything is written.
  checkCompareOptions(o);
  const CompareFamilies families = generateFamilies(o);
  const std::vector<optimize::EnergyVariant> variants = parseVariants(o);
  requireDistinct(o, families.names);
  const modeling::PolynomialSurface surface = modeling::PolynomialSurface::parse(o.boundary);
  const render::RenderOptions look = compareLook(o, surface);
  const std::string styleName(render::renderStyleName(look.style));

  optimize::MinimizeOptions solver;
  solver.threads = o.threads;
  applySolverArguments(o.solver, solver);
  solver.progress = global.verbose && !global.quiet;  // each solve's Newton iterations
  render::OffscreenContext context;  // a missing OSMesa fails here, before any solve
  const PanelSettings settings{variants, surface, solver};
  CompareOutputs out;
  out.grid.title = std::string(o.solve == "linearized" ? "Linearized" : "Nonlinear") +
                   " minimizers, boundary rings on z = p(x, y), p = " + o.boundary + " (" +
                   (o.families.empty() ? std::string() : "n = " + std::to_string(o.n) + ", ") +
                   styleName +
                   "). Over each panel its C2 error: max |z - p| / max |p| over the free vertices";
  out.grid.rowLabels = families.labels;
  out.grid.columnLabels.push_back("exact p (reference)");
  for (const auto& v : variants) out.grid.columnLabels.push_back(v.label);
  for (size_t f = 0; f < families.meshes.size(); ++f) {
    compareRow(o, global, commandName, families.meshes[f], families.names[f], settings, out);
  }
  renderPanels(context, sharedLook(look, out), out);
  const render::Image figure = render::composeFigureGrid(out.grid);
  writeCompareFiles(o, styleName, families.names, out, figure);
  if (!global.quiet) {
    const std::filesystem::path dir(o.outputDir);
    std::cerr << commandName << ": wrote " << (dir / "compare.png").string() << " (" << figure.width
              << " x " << figure.height << "), compare.json and " << out.files.size()
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
                      energyNames([](const auto&) { return true; }, ", ", ", ") + ", ...")
      ->delimiter(',')
      ->capture_default_str();
  sub->add_option("--boundary", o.boundary,
                  "Boundary data: rings 0 and 1 lifted onto z = p(x, y) (quadratic:a,b,c or "
                  "polynomial:EXPR)")
      ->capture_default_str();
  sub->add_option("--n", o.n, "Cells per side of the meshes")
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
