// flexure modes: the vibration modes of a plate or shell about its rest state for one or more
// bending energies (optimize/modes/vibration_modes.h), with the Chladni figure (mode shapes with
// their nodal lines), a JSON report and, for the square plate, the errors against exact or
// tabulated frequencies.
#include <Eigen/SVD>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/modes_command.h"

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "curvature/bending_energy.h"
#include "curvature/energy_registry.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/rest_state.h"
#include "modeling/vertex_quantities.h"
#include "optimize/boundary_conditions.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/problem.h"
#include "optimize/studies/convergence_study.h"
#include "optimize/studies/spectrum_study.h"
#include "render/field_map.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"

namespace flexure::cli {
namespace {

// The files modes writes into its folder.
bool isModesFile(const std::string& name) {
  return name == "modes.json" || name == "chladni.png" || name == "rest.obj" ||
         (name.rfind("mode-", 0) == 0 && name.size() > 4 && name.substr(name.size() - 4) == ".obj");
}

struct EnergyRun {
  std::string spec;
  curvature::BendingOptions bending;
  optimize::Clamp clamp = optimize::Clamp::Rings;
  bool edgeUnknowns = false;  // midedge's ξ
  optimize::ModesResult result;
};

std::string lambdaText(double lambda) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", lambda);
  return text;
}

// The command's flags mapped to the library's spec of a modes run, validated (optimize::ModesSpec
// holds the rules, and its messages name fields that withFlagNames turns back into these flags).
optimize::ModesSpec modesSpec(const ModesOptions& o) {
  if (o.meshFile.empty() == o.family.empty())
    throw InputError("give the plate as --mesh FILE or as --family F --n N (one of the two)");
  if (o.energies.empty()) throw InputError("--energy: give at least one energy");
  for (size_t i = 0; i < o.energies.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (o.energies[i] == o.energies[j])
        throw InputError("--energy: " + o.energies[i] + " is given twice");
  optimize::ModesWords words;
  words.count = o.count;
  words.support = o.support;
  words.mass = o.mass;
  words.density = o.density;
  words.bendingStiffness = o.stiffness;
  words.length = o.length;
  words.dof = o.dof;
  words.clamp = o.clamp;
  words.membrane = !o.membrane.model.empty();
  return optimize::modesSpec(words);
}

// One run per --energy, with its bending options and its clamp (ModesSpec::forEnergy).
std::vector<EnergyRun> energyRuns(const ModesOptions& o, const optimize::ModesSpec& spec) {
  std::vector<EnergyRun> runs;
  for (const std::string& name : o.energies) {
    const curvature::EnergyEntry* entry = curvature::findEnergy(name.substr(0, name.find(':')));
    if (name.find(':') != std::string::npos && entry && entry->hasEdgeUnknowns())
      throw InputError("--energy " + name + ": " + entry->name +
                       "'s boundary normals follow --support and --clamp; give " + entry->name);
    EnergyRun run;
    run.spec = name;
    try {
      run.bending = optimize::parseEnergyVariant(name, o.poisson).bending;
    } catch (const InputError& e) {
      throw InputError(std::string("--energy: ") + e.what());
    }
    run.bending.stiffness = o.stiffness;
    curvature::effectivePoisson(run.bending);  // a ν the energy does not take fails here
    run.edgeUnknowns = curvature::energyEntry(run.bending.discretization).hasEdgeUnknowns();
    run.clamp = spec.forEnergy(run.bending).clamp;
    runs.push_back(std::move(run));
  }
  return runs;
}

void checkReferenceName(const std::string& reference, optimize::Support support) {
  if (!reference.empty() && reference != "square-simply-supported" && reference != "square-clamped")
    throw InputError("--reference " + reference +
                     ": expected square-simply-supported or square-clamped");
  if (reference == "square-simply-supported" && support != optimize::Support::SimplySupported)
    throw InputError("--reference square-simply-supported needs --support simply-supported");
  if (reference == "square-clamped" && support != optimize::Support::Clamped)
    throw InputError("--reference square-clamped needs --support clamped");
}

struct Plate {
  modeling::Mesh mesh;
  std::string source;  // the file, or the family and n
};

Plate readOrGeneratePlate(const ModesOptions& o) {
  Plate plate;
  if (!o.meshFile.empty()) {
    plate.mesh = modeling::readMesh(o.meshFile);
    plate.source = o.meshFile;
    return plate;
  }
  modeling::GeneratorOptions generator;
  generator.family = modeling::parsePlateFamily(o.family);
  generator.n = o.n;
  generator.seed = o.seed;
  plate.mesh = modeling::generateMesh(generator);
  plate.source =
      std::string(modeling::meshFamilyName(generator.family)) + " n = " + std::to_string(o.n);
  return plate;
}

// What the rest surface rules out (height mode off a flat plate, a normals clamp on a shell), for
// every run before the first solve; midedge's default normals clamp is named as the default.
void checkRunsOnRest(const std::vector<EnergyRun>& runs, const optimize::ModesOptions& base,
                     const ModesOptions& o, const modeling::RestState& rest) {
  optimize::ModesOptions options = base;
  options.clamp = optimize::Clamp::Rings;  // the rest and the dof alone first
  optimize::checkModesRest(options, rest.positions, false);
  for (const EnergyRun& run : runs) {
    options.clamp = run.clamp;
    try {
      optimize::checkModesRest(options, rest.positions, run.edgeUnknowns);
    } catch (const InputError& e) {
      if (!o.clamp.empty() || run.clamp != optimize::Clamp::Normals) throw;
      throw InputError("--energy " + run.spec +
                       " clamps its boundary normals by default (--clamp normals): " + e.what());
    }
  }
}

// The tabulated references are for a flat square plate of side L.
void checkReferencePlate(const ModesOptions& o, const Plate& plate) {
  if (o.reference.empty()) return;
  const Eigen::Vector3d extent =
      plate.mesh.positions.colwise().maxCoeff() - plate.mesh.positions.colwise().minCoeff();
  if (extent.z() != 0.0 || std::abs(extent.x() - extent.y()) > 1e-9 * extent.maxCoeff())
    throw InputError("--reference " + o.reference + ": " + plate.source +
                     " is not a flat square plate (bounding box " + std::to_string(extent.x()) +
                     " x " + std::to_string(extent.y()) + " x " + std::to_string(extent.z()) + ")");
  if (o.length > 0.0 && std::abs(o.length - extent.x()) > 1e-9 * extent.x())
    throw InputError("--reference " + o.reference + ": --length must be the square's side");
}

// The flexible modes that move a small share of the mass (optimize::kLocalizedParticipation).
void printLocalizedModes(const EnergyRun& run, const std::string& commandName) {
  std::string list;
  int index = 0, localized = 0;
  for (const optimize::VibrationMode& mode : run.result.modes) {
    if (mode.zero) continue;
    ++index;
    if (!mode.localized) continue;
    char entry[64];
    std::snprintf(entry, sizeof entry, "%s%d (%.3g)", localized++ > 0 ? ", " : "", index,
                  mode.participation);
    list += entry;
  }
  if (localized == 0) return;
  std::cerr << commandName << ": warning: " << run.spec << ": "
            << (localized == 1 ? "mode " : "modes ") << list << (localized == 1 ? " is" : " are")
            << " localized on a few vertices (participation "
            << "ratio below " << optimize::kLocalizedParticipation
            << "; a smooth plate mode has about 0.4): a few free or weakly attached vertices "
               "vibrate alone\n";
}

void printSolveLine(const EnergyRun& run, const std::string& commandName) {
  const optimize::ModesResult& r = run.result;
  std::cerr << commandName << ": " << run.spec << ": " << counted(r.flexibleModes, "mode") << " in "
            << lambdaText(r.totalSeconds) << " s (" << counted(r.operations, "solve")
            << " with one factor)";
  if (r.rigidModes > 0) std::cerr << ", " << counted(r.rigidModes, "rigid mode");
  if (r.spuriousZeroModes > 0)
    std::cerr << ", " << counted(r.spuriousZeroModes, "spurious zero mode");
  std::cerr << '\n';
}

// Each run's modes, through one problem per energy with nothing held and no boundary values: the
// support and the clamp are ModesOptions'.
void solveRuns(std::vector<EnergyRun>& runs, const modeling::Stencils& stencils,
               const modeling::RestState& rest, const optimize::ModesOptions& base,
               const ModesOptions& o, const GlobalOptions& global, const std::string& commandName) {
  optimize::ProblemOptions problemOptions;
  problemOptions.dof = base.dof;
  if (!o.membrane.model.empty()) problemOptions.membrane = membraneOptions(o.membrane);
  problemOptions.fixedRings = 0;
  problemOptions.boundaryNormals = optimize::BoundaryNormals::Free;
  for (EnergyRun& run : runs) {
    problemOptions.bending = run.bending;
    const optimize::Problem problem = optimize::buildProblem(stencils, rest, problemOptions);
    optimize::ModesOptions options = base;
    options.clamp = run.clamp;
    run.result = optimize::vibrationModes(problem.termPointers(), problem.stencils, problem.rest,
                                          problem.restXi, options);
    if (!global.quiet) printSolveLine(run, commandName);
    printLocalizedModes(run, commandName);  // a warning: printed when quiet too
  }
}

// What the runs add up to: the figure, the λ table (a row per flexible mode, a column per
// energy), the shapes to write and the per-energy reports.
struct ModesOutputs {
  render::FigureGrid grid;
  std::vector<std::vector<double>> table;
  std::vector<std::pair<std::string, modeling::Mesh>> shapes;
  nlohmann::json energies = nlohmann::json::array();
};

// What every mode's outputs need besides the mode.
struct ModeContext {
  const ModesOptions& o;
  const Plate& plate;
  const modeling::Stencils& stencils;
  const modeling::RestState& rest;
  const Eigen::MatrixX3d& normals;  // the rest vertex normals
  const std::vector<double>& reference;
  double length;  // L
  bool flat;      // the rest mesh is a flat plate: a Chladni map seen from above; else a 3-D view
};

// Whether the rest positions lie in a plane: the smallest principal extent (the singular values of
// the centred positions) at most 1e-9 of the largest.
bool isFlatPlate(const modeling::Positions& rest) {
  const Eigen::MatrixX3d centred = rest.rowwise() - rest.colwise().mean();
  const Eigen::Vector3d extents = Eigen::JacobiSVD<Eigen::MatrixX3d>(centred).singularValues();
  return extents(2) <= 1e-9 * extents(0);
}

// What a closed or curved mesh is, for the figure's title.
std::string surfaceKind(const modeling::Stencils& stencils) {
  const auto& flaps = stencils.faceFlaps;
  const bool closed = (flaps.array() >= 0).all();
  return closed ? "closed surface" : "shell";
}

int modePanelWidth(const ModeContext& c) {
  return c.o.size + (c.flat ? 0 : render::kLegendWidth);
}

// A curved or closed mesh's mode in 3-D: the rest mesh displaced along the mode as its shape file
// is (largest displacement scale × L), coloured by the normal component w = u·n of the mode on a
// diverging map (its own largest |w|), the nodal lines w = 0 drawn black on the surface.
render::Image shellModePanel(const optimize::VibrationMode& mode, const std::vector<double>& w,
                             const ModeContext& c) {
  const modeling::Positions& rest = c.plate.mesh.positions;
  modeling::Mesh shaped = c.plate.mesh;
  shaped.positions += (c.o.scale * c.length / mode.shape.rowwise().norm().maxCoeff()) * mode.shape;
  render::RenderOptions look;
  look.style = render::RenderStyle::Curvature;
  look.width = modePanelWidth(c);
  look.height = c.o.size;
  look.azimuthDegrees = 25.0;
  look.elevationDegrees = 30.0;
  look.vertexScalars = w;
  look.zeroContour = true;
  double largest = 0.0;
  for (const double value : w) largest = std::max(largest, std::abs(value));
  look.curvatureMax = std::max(largest, 1e-300);
  look.rangeNote = "largest";
  look.scalarLabel = "normal component of the mode";
  look.scalarSymbol = "w";
  look.framingPoints.resize(2 * rest.rows(), 3);
  look.framingPoints << rest, shaped.positions;
  return render::renderMesh(shaped, look);
}

// The normal displacement, whose zero set the nodal lines are, with the lines: a map seen from
// above for a flat plate, a 3-D view of the displaced shape otherwise.
render::Image modePanel(const optimize::VibrationMode& mode, const ModeContext& c) {
  std::vector<double> w;
  for (int v = 0; v < c.plate.mesh.vertexCount(); ++v)
    w.push_back(mode.shape.row(v).dot(c.normals.row(v)));
  if (!c.flat) return shellModePanel(mode, w, c);
  render::FieldMap map;
  map.mesh = &c.plate.mesh;
  map.values = std::move(w);
  map.lines = optimize::nodalSegments(c.stencils, c.rest, mode.shape);
  map.size = c.o.size;
  return render::renderFieldMap(map);
}

// The rest mesh displaced by the mode, its largest displacement scale × L; returns its file name.
std::string addShape(const optimize::VibrationMode& mode, const std::string& spec, int index,
                     const ModeContext& c, ModesOutputs& out) {
  // The spec as a file-name part: "hinge:tan" → "hinge_tan".
  std::string stem = spec;
  for (char& ch : stem)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  const std::string name = "mode-" + stem + "-" + std::to_string(index) + ".obj";
  modeling::Mesh shaped = c.plate.mesh;
  const double largest = mode.shape.rowwise().norm().maxCoeff();
  shaped.positions += (c.o.scale * c.length / largest) * mode.shape;
  out.shapes.emplace_back(name, std::move(shaped));
  return name;
}

// The flexible mode `index` (from 1): its column of the table, its panel, its shape.
void addFlexibleMode(const optimize::VibrationMode& mode, int index, const EnergyRun& run,
                     const ModeContext& c, nlohmann::json& m, ModesOutputs& out) {
  m["kind"] = "flexible";
  m["index"] = index;
  out.table[index - 1].push_back(mode.lambda);
  if (index <= static_cast<int>(c.reference.size())) {
    m["reference"] = c.reference[index - 1];
    m["relative_error"] = mode.lambda / c.reference[index - 1] - 1.0;
  }
  out.grid.panels.back().push_back(modePanel(mode, c));
  out.grid.panelTitles.back().push_back(
      "λ" + std::to_string(index) + " = " + lambdaText(mode.lambda) +
      (mode.multiplicity > 1 ? " (×" + std::to_string(mode.multiplicity) + ")" : ""));
  if (c.o.writeShapes) m["shape"] = addShape(mode, run.spec, index, c, out);
}

nlohmann::json energyReport(const EnergyRun& run, optimize::Support support,
                            const nlohmann::json& modes) {
  const optimize::ModesResult& r = run.result;
  return {{"energy", run.spec},
          {"poisson", curvature::effectivePoisson(run.bending)},
          {"clamp", support == optimize::Support::Clamped
                        ? nlohmann::json(optimize::clampName(run.clamp))
                        : nlohmann::json(nullptr)},
          {"rigid_modes", r.rigidModes},
          {"spurious_zero_modes", r.spuriousZeroModes},
          {"zero_modes", r.zeroModes},
          {"unknowns", r.unknowns},
          {"vertex_unknowns", r.massUnknowns},
          {"fixed_vertices", r.fixedVertices},
          {"lanczos", {{"solves", r.operations}, {"restarts", r.restarts}}},
          {"seconds",
           {{"assembly", r.assemblySeconds},
            {"factorization", r.factorSeconds},
            {"eigensolve", r.eigenSeconds},
            {"total", r.totalSeconds}}},
          {"modes", modes}};
}

// One energy's row of the figure and column of the table, its shapes and its report.
void addRun(const EnergyRun& run, optimize::Support support, const ModeContext& c,
            ModesOutputs& out) {
  const optimize::ModesResult& r = run.result;
  nlohmann::json modes = nlohmann::json::array();
  out.grid.rowLabels.push_back(run.spec);
  out.grid.panels.emplace_back();
  out.grid.panelTitles.emplace_back();
  int flexible = 0, zero = 0;
  for (const optimize::VibrationMode& mode : r.modes) {
    nlohmann::json m = {{"lambda", mode.lambda},
                        {"omega", mode.omega},
                        {"omega_squared", mode.omegaSquared},
                        {"multiplicity", mode.multiplicity},
                        {"residual", mode.residual},
                        {"nodal_length", mode.nodalLength},
                        {"participation", mode.participation},
                        {"localized", mode.localized}};
    if (mode.zero) {
      m["kind"] = ++zero <= r.rigidModes ? "rigid" : "spurious zero";
      modes.push_back(m);
      continue;
    }
    if (flexible == c.o.count) continue;
    addFlexibleMode(mode, ++flexible, run, c, m, out);
    modes.push_back(m);
  }
  for (int k = flexible; k < c.o.count; ++k) {  // spurious zero modes took these places
    out.table[k].push_back(std::nan(""));
    render::Image blank;
    blank.width = modePanelWidth(c);
    blank.height = c.o.size;
    blank.rgba.assign(4 * static_cast<size_t>(blank.width) * blank.height, 255);
    out.grid.panels.back().push_back(blank);
    out.grid.panelTitles.back().push_back("(not computed)");
  }
  out.energies.push_back(energyReport(run, support, modes));
}

// The reference λ₁ … λ_K (Leissa tabulates six for the clamped square), or none.
std::vector<double> referenceLambdas(const ModesOptions& o, optimize::Support support) {
  if (o.reference.empty()) return {};
  return optimize::squarePlateLambdas(
      support, support == optimize::Support::Clamped ? std::min(o.count, 6) : o.count);
}

// "free plate, patch48 n = 16: …" for a flat plate; for a curved or closed mesh what it is and
// how its modes are drawn ("sphere.off, a free closed surface: …").
std::string figureTitle(const optimize::ModesOptions& base, const Plate& plate, bool flat,
                        const modeling::Stencils& stencils) {
  const long held = std::count(base.extraFixed.begin(), base.extraFixed.end(), true);
  const std::string heldText = held > 0 ? " held at " + counted(held, "vertex", "vertices") : "";
  if (!flat) {
    return plate.source + ", a " + std::string(optimize::supportName(base.support)) + " " +
           surfaceKind(stencils) + heldText +
           ": vibration modes in 3-D, the rest shape displaced along each mode, coloured by its "
           "normal component, nodal lines black";
  }
  return std::string(optimize::supportName(base.support)) + " plate" + heldText + ", " +
         plate.source + ": vibration modes, nodal lines black";
}

void printTableHeader(const std::vector<EnergyRun>& runs, bool withReference) {
  std::printf("%-10s", "mode");
  for (const EnergyRun& run : runs) std::printf(" %12s", run.spec.c_str());
  if (withReference) std::printf(" %12s", "reference");
  std::printf("\n");
}

void printTableRows(const std::vector<std::vector<double>>& table,
                    const std::vector<double>& reference) {
  for (size_t k = 0; k < table.size(); ++k) {
    std::printf("%-10d", static_cast<int>(k + 1));
    for (double lambda : table[k]) std::printf(" %12.6g", lambda);
    if (k < reference.size()) {
      std::printf(" %12.6g", reference[k]);
      for (double lambda : table[k]) std::printf("  %+.2e", lambda / reference[k] - 1.0);
    }
    std::printf("\n");
  }
}

nlohmann::json modesReport(const ModesOptions& o, const optimize::ModesOptions& base,
                           const Plate& plate, const optimize::ModesResult& first,
                           const nlohmann::json& energies) {
  nlohmann::json report = {
      {"plate", plate.source},
      {"vertices", plate.mesh.vertexCount()},
      {"faces", plate.mesh.faceCount()},
      {"support", optimize::supportName(base.support)},
      {"dof", o.dof},
      {"mass", optimize::massLumpingName(base.mass)},
      {"density", o.density},
      {"bending_stiffness", o.stiffness},
      {"length", first.length},
      {"flexural_rigidity", first.flexuralRigidity},
      {"shift", first.shift},
      {"lambda", "omega L^2 sqrt(rho h / D), D = 2 k_B"},
      {"residual", "|K v - omega^2 M v| / |K v| (zero modes: |K v| / (|K|_inf |v|))"},
      {"participation", "(sum m_v |v_v|^2)^2 / (M sum m_v |v_v|^4), M the total mass"},
      {"localized_below", optimize::kLocalizedParticipation},
      {"figure", "chladni.png"},
      {"energies", energies}};
  if (!o.fix.empty()) report["fix"] = o.fix;
  if (o.writeShapes) report["rest"] = "rest.obj";
  if (!o.reference.empty()) {
    report["reference"] = {{"name", o.reference},
                           {"source", optimize::squarePlateSource(base.support)}};
  }
  return report;
}

}  // namespace

void runModes(const ModesOptions& o, const GlobalOptions& global, const std::string& commandName) {
  namespace fs = std::filesystem;
  // Every option and input is checked before the first solve.
  const optimize::ModesSpec spec = modesSpec(o);
  optimize::ModesOptions base = spec.modes;
  std::vector<EnergyRun> runs = energyRuns(o, spec);
  checkReferenceName(o.reference, base.support);
  const fs::path restCopy = fs::path(o.outputDir) / "rest.obj";
  std::error_code error;
  if (o.writeShapes && !o.meshFile.empty() && fs::equivalent(o.meshFile, restCopy, error))
    throw InputError("-o " + o.outputDir + ": --write-shapes writes " + restCopy.string() +
                     ", which is the input --mesh " + o.meshFile + "; give another folder");
  const Plate plate = readOrGeneratePlate(o);
  const modeling::Stencils stencils = modeling::compileStencils(plate.mesh);
  const modeling::RestState rest = modeling::precomputeRestState(stencils, plate.mesh.positions);
  if (!o.fix.empty())
    base.extraFixed = optimize::parseFixedSet("--fix", o.fix, stencils, rest.positions);
  checkReferencePlate(o, plate);
  checkRunsOnRest(runs, base, o, rest);

  solveRuns(runs, stencils, rest, base, o, global, commandName);

  // The report, the table and the figure.
  const std::vector<double> reference = referenceLambdas(o, base.support);
  ModesOutputs out;
  const bool flat = isFlatPlate(rest.positions);
  out.grid.title = figureTitle(base, plate, flat, stencils);
  for (int k = 1; k <= o.count; ++k) out.grid.columnLabels.push_back("mode " + std::to_string(k));
  out.table.resize(o.count);
  printTableHeader(runs, !reference.empty());
  const Eigen::MatrixX3d normals = modeling::vertexNormals(rest.positions, stencils.faces);
  const ModeContext context{
      o, plate, stencils, rest, normals, reference, runs.front().result.length, flat};
  for (const EnergyRun& run : runs) addRun(run, base.support, context, out);
  printTableRows(out.table, reference);
  const render::Image figure = render::composeFigureGrid(out.grid);

  const fs::path dir(o.outputDir);
  modeling::createOutputDirectory(dir.string());
  render::writePng((dir / "chladni.png").string(), figure);
  for (const auto& [name, shaped] : out.shapes) modeling::writeMesh((dir / name).string(), shaped);
  // The rest mesh beside the shapes, written alike: a shape minus it is the mode (flexure view).
  if (o.writeShapes) modeling::writeMesh((dir / "rest.obj").string(), plate.mesh);
  writeJsonFile((dir / "modes.json").string(),
                modesReport(o, base, plate, runs.front().result, out.energies));
  if (!global.quiet) {
    std::cerr << commandName << ": wrote " << (dir / "chladni.png").string() << " (" << figure.width
              << " x " << figure.height << "), modes.json"
              << (out.shapes.empty() ? "" : " and " + counted(out.shapes.size(), "mode shape"))
              << '\n';
  }
}

void registerModesCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<ModesOptions>();
  ModesOptions& o = *options;
  CLI::App* sub = app.add_subcommand(
      "modes", "Vibration modes of a plate or shell (Chladni figures) for each bending energy");
  auto files = CommandFiles::of(*sub);
  files->input("--mesh", o.meshFile, "Rest mesh (a flat plate or a shell)");
  sub->add_option("--family", o.family,
                  "Or a generated plate: patch48 | stripe | criss | delaunay");
  sub->add_option("-n,--n", o.n, "Cells per side of the generated plate")
      ->capture_default_str()
      ->check(inRange(2, 2048));
  sub->add_option("--seed", o.seed, "Random seed of the delaunay plate")
      ->capture_default_str()
      ->check(seedValue());
  sub->add_option("--energy", o.energies,
                  "Energies, comma-separated: " + optimize::energyVariantSpecs(false, ", "))
      ->delimiter(',')
      ->required();
  sub->add_option("--poisson", o.poisson,
                  "ν for " +
                      curvature::energyNamesWhere(
                          [](const curvature::EnergyEntry& e) {
                            return e.poissonRule == curvature::PoissonRule::Koiter;
                          },
                          ", ", " and ") +
                      " (0.3)");
  sub->add_option("--stiffness", o.stiffness, "Bending stiffness k_B (D = 2 k_B)")
      ->capture_default_str()
      ->check(positive());
  sub->add_option("--support", o.support, "clamped | simply-supported | free")
      ->capture_default_str();
  const std::string edgeUnknowns =
      curvature::energyNamesWhere(&curvature::EnergyEntry::hasEdgeUnknowns);
  sub->add_option("--clamp", o.clamp,
                  "How a clamp holds the slope: rings (rings 0 and 1 fixed) | normals (ring 0 "
                  "fixed, " +
                      edgeUnknowns + " boundary normals held); default normals for " +
                      edgeUnknowns + ", rings otherwise");
  sub->add_option("--fix", o.fix,
                  "Vertices held in addition: vertices:FILE (e.g. the centre point) | rings:K | "
                  "box:X0,X1,Y0,Y1,Z0,Z1");
  sub->add_option("--count", o.count, "Flexible modes per energy")
      ->capture_default_str()
      ->check(inRange(1, 200));
  sub->add_option("--mass", o.mass,
                  "Lumped mass: barycentric (ρh/3 Σ incident face areas) | voronoi")
      ->capture_default_str();
  sub->add_option("--density", o.density, "ρh, mass per unit area")
      ->capture_default_str()
      ->check(positive());
  sub->add_option("--length", o.length,
                  "L of λ = ω L² √(ρh/D) (default: the bounding box's largest side)")
      ->check(positive());
  sub->add_option("--dof", o.dof, "height (transverse vibration of a plate) | xyz (a shell)")
      ->capture_default_str();
  addMembraneArguments(*sub, o.membrane, "--dof xyz: stvk | springs | conformal");
  sub->add_option("--reference", o.reference,
                  "Compare with square-simply-supported (exact) or square-clamped (Leissa 1973)");
  sub->add_flag("--write-shapes", o.writeShapes,
                "Also write mode-<energy>-<k>.obj: the rest mesh displaced by each mode, and the "
                "rest mesh as rest.obj (flexure view DIR animates them)");
  sub->add_option("--scale", o.scale,
                  "The largest displacement of the --write-shapes meshes and of a shell's 3-D "
                  "figure, as a fraction of L")
      ->capture_default_str()
      ->check(positive());
  sub->add_option("--size", o.size, "Panel size of the figure in pixels")
      ->capture_default_str()
      ->check(inRange(64, 2048));
  files
      ->output("-o,--output", o.outputDir,
               "Output directory (created if missing; a previous modes run's files in it are "
               "removed)",
               OutputKind::Directory, isModesFile)
      ->required();
  sub->footer(
      "Writes DIR/modes.json (per energy: λ, ω, multiplicity, residual, nodal-line length of "
      "each mode; rigid and spurious zero modes named), DIR/chladni.png (rows = energies, "
      "columns = modes, nodal lines black) and with --write-shapes DIR/mode-<energy>-<k>.obj and "
      "DIR/rest.obj; "
      "prints the λ table.\n"
      "Example: flexure modes --family patch48 --n 32 --energy midedge,cotan "
      "--support simply-supported --reference square-simply-supported -o modes");
  files->onRun(global, [options, &global] { runModes(*options, global, "flexure modes"); });
}

}  // namespace flexure::cli
