// flexure fair: fairing a region of a real mesh — flexure's nonlinear bending-energy fairing, or
// CGAL's linear fair on the same region — with a report that sets the input, CGAL's fair and
// flexure's result side by side, and a reflection-line render of the three with the region
// outlined.
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "cli/solver_arguments.h"
#include "modeling/boundary_rings.h"
#include "modeling/errors.h"
#include "modeling/fairing_region.h"
#include "modeling/hole_filling.h"
#include "modeling/mesh_io.h"
#include "modeling/region_remeshing.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "modeling/vertex_quantities.h"
#include "modeling/vertex_sets.h"
#include "optimize/fairing/fairing.h"
#include "optimize/fairing/fairing_spec.h"
#include "optimize/modes/vibration_modes.h"
#include "render/figure_grid.h"
#include "render/mesh_renderer.h"
#include "render/offscreen_context.h"

namespace flexure::cli {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
// The smallest panel: the signed-distance panel keeps render::kLegendWidth of it for its legend.
constexpr int kMinRenderSize = 200;

// The smallest-angle rule (#15, optimize::SliverCheck): a result below its limit exits 3 (the
// report, no mesh) unless --allow-slivers.
using optimize::kSliverToleranceDegrees;

struct FairCommandOptions {
  std::string input, region, output, reportFile, renderFile, cgalOutput;
  optimize::FairingSpec spec;  // the flags map one to one onto its fields; it holds the rules
  int renderSize = 700;
  SolverArguments solverArguments;
};

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The mesh to fair and its region: the input and its --region, or for "holes[:N]" the input with
// its holes (loops of at most N edges) filled and the patches' new vertices as the region.
struct RegionChoice {
  modeling::Mesh mesh;
  std::vector<bool> region;
  std::optional<modeling::FilledMesh> filled;  // holes only (its mesh moved into `mesh`)
};

// "the loop of 90 edges at vertex 12: CGAL's fill …"
std::string skippedHoleText(const modeling::SkippedHole& h) {
  return "the loop of " + std::to_string(h.boundaryEdges) + " edges at vertex " +
         std::to_string(h.loopVertex) + ": " + h.reason;
}

// The loops left open, in one notice: the loop and its reason when it is one, else the count, the
// first loop and where the others are listed (a mesh with many cracks had a line per loop).
void printSkippedHoles(const modeling::FilledMesh& filled, const std::string& reportFile) {
  const size_t skipped = filled.skipped.size();
  if (skipped == 0) return;
  if (skipped == 1) {
    std::cerr << "flexure fair: skipped " << skippedHoleText(filled.skipped.front())
              << "; the other loops are filled\n";
    return;
  }
  std::cerr << "flexure fair: skipped " << skipped << " of " << skipped + filled.holes.size()
            << " loops, which CGAL cannot fill cleanly (the first: "
            << skippedHoleText(filled.skipped.front()) << "); the other " << filled.holes.size()
            << " are filled; "
            << (reportFile.empty() ? "--report FILE lists" : reportFile + " lists")
            << " each skipped loop and why\n";
}

RegionChoice chooseRegion(const FairCommandOptions& o, modeling::Mesh input,
                          const modeling::Stencils& stencils, bool quiet) {
  RegionChoice choice;
  if (o.region == "holes" || o.region.rfind("holes:", 0) == 0) {
    int maxEdges = 0;
    if (o.region != "holes") {
      const std::string n = o.region.substr(6);
      std::size_t used = 0;
      try {
        maxEdges = std::stoi(n, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != n.size() || maxEdges < 3)
        throw InputError("--region " + o.region + ": expected holes:N with N >= 3 boundary edges");
    }
    if (!stencils.vertexOnBoundary.any())
      throw InputError(o.input + ": the mesh is closed: it has no hole to fill");
    modeling::FilledMesh filled = modeling::fillHoles(input, maxEdges);
    if (filled.holes.empty() && !filled.skipped.empty()) {
      std::string loops;
      for (const modeling::SkippedHole& h : filled.skipped) loops += "\n  " + skippedHoleText(h);
      throw InputError("--region " + o.region + ": no boundary loop of " + o.input +
                       " can be filled cleanly by CGAL:" + loops +
                       "\nchoose the loops by size with --region holes:N (the loops of at most N "
                       "edges), or fair a region of the surface (--region sphere:x,y,z,r)");
    }
    if (!quiet) printSkippedHoles(filled, o.reportFile);
    if (filled.holes.empty()) {
      throw InputError("--region " + o.region + ": no boundary loop of " + o.input +
                       " has at most " + std::to_string(maxEdges) + " edges");
    }
    choice.mesh = std::move(filled.mesh);
    choice.region = filled.newVertex;
    choice.filled = std::move(filled);
    return choice;
  }
  try {
    choice.region = modeling::parseRegion(o.region, input, stencils);
  } catch (const InputError& e) {
    // The library names the text ("region sphere:…: …"); the user gave it as --region.
    const std::string message = e.what();
    if (message.rfind("region " + o.region + ":", 0) == 0) throw InputError("--" + message);
    throw;
  }
  choice.mesh = std::move(input);
  return choice;
}

nlohmann::json energiesJson(const std::vector<optimize::EnergyMeasure>& measures) {
  nlohmann::json energies = nlohmann::json::object();
  for (const optimize::EnergyMeasure& e : measures)
    energies[e.energy] = e.error.empty() ? nlohmann::json(e.value) : nlohmann::json(nullptr);
  return energies;
}

nlohmann::json measuresJson(const optimize::FairingMeasures& m) {
  return {{"bending_energy", energiesJson(m.bending)},
          {"bending_energy_current_metric", energiesJson(m.bendingCurrent)},
          {"triangle_quality",
           {{"min_angle_degrees", m.quality.minAngleDegrees},
            {"mean_shape", m.quality.meanShape},
            {"min_shape", m.quality.minShape}}},
          {"max_displacement", m.maxDisplacement}};
}

// One column of the side-by-side comparison: the report's key, a heading, the measures.
struct MeasureColumn {
  std::string key, heading;
  optimize::FairingMeasures measures;
};

// The comparison as a table on stderr: a row per energy (E_bend, flat rest, the input's metric),
// then the triangle quality of the faces touching the region and the largest displacement.
void printSideBySide(const std::vector<MeasureColumn>& columns) {
  constexpr int kLabelWidth = 18, kColumnWidth = 17;
  std::string text =
      "flexure fair: side by side (E_bend flat rest, input metric; faces touching "
      "the region)\n";
  const auto pad = [](std::string cell, int width) {
    cell.resize(std::max<std::size_t>(cell.size(), static_cast<std::size_t>(width)), ' ');
    return cell;
  };
  text += pad("", kLabelWidth);
  for (const MeasureColumn& c : columns) text += pad(c.heading, kColumnWidth);
  text += '\n';
  const auto row = [&](const std::string& label, const auto& value) {
    text += pad(label, kLabelWidth);
    for (const MeasureColumn& c : columns) text += pad(value(c.measures), kColumnWidth);
    text += '\n';
  };
  const auto number = [](double x, const char* format) {
    char cell[48];
    std::snprintf(cell, sizeof cell, format, x);
    return std::string(cell);
  };
  for (std::size_t e = 0; e < columns.front().measures.bending.size(); ++e) {
    row("E_" + columns.front().measures.bending[e].energy, [&](const optimize::FairingMeasures& m) {
      return m.bending[e].error.empty() ? number(m.bending[e].value, "%.5g") : std::string("-");
    });
  }
  row("smallest angle", [&](const optimize::FairingMeasures& m) {
    return number(m.quality.minAngleDegrees, "%.3g deg");
  });
  row("mean shape",
      [&](const optimize::FairingMeasures& m) { return number(m.quality.meanShape, "%.4f"); });
  row("smallest shape",
      [&](const optimize::FairingMeasures& m) { return number(m.quality.minShape, "%.4f"); });
  row("max displacement",
      [&](const optimize::FairingMeasures& m) { return number(m.maxDisplacement, "%.4g"); });
  std::cerr << text;
}

// The checks of optimize::FairingChecks, each with its verdict and threshold; at most
// kListedFaces faces of each kind are listed.
nlohmann::json checksJson(const optimize::FairingChecks& c) {
  constexpr std::size_t kListedFaces = 10;
  nlohmann::json degenerate = nlohmann::json::array(), inverted = nlohmann::json::array();
  for (std::size_t i = 0; i < std::min(c.degenerateFaces.size(), kListedFaces); ++i) {
    const optimize::DegenerateFace& f = c.degenerateFaces[i];
    degenerate.push_back(
        {{"vertices", {f.vertices[0], f.vertices[1], f.vertices[2]}}, {"flatness", f.flatness}});
  }
  for (std::size_t i = 0; i < std::min(c.invertedFaces.size(), kListedFaces); ++i) {
    const optimize::InvertedFace& f = c.invertedFaces[i];
    inverted.push_back({{"vertices", {f.vertices[0], f.vertices[1], f.vertices[2]}},
                        {"input_turn_degrees", f.inputTurnDegrees},
                        {"neighbour_turn_degrees", f.neighbourTurnDegrees}});
  }
  nlohmann::json gradient = nullptr;
  if (c.gradientChecked) {
    gradient = {{"passed", c.gradientPassed()},
                {"start_norm", c.startGradientNorm},
                {"final_norm", c.finalGradientNorm},
                {"ratio", c.finalGradientNorm / c.startGradientNorm},
                {"max_ratio", optimize::kFairingGradientReduction}};
  }
  return {{"gradient", gradient},
          {"triangles",
           {{"passed", c.trianglesPassed()},
            {"degenerate", c.degenerateFaces.size()},
            {"inverted", c.invertedFaces.size()},
            {"degenerate_faces", degenerate},
            {"inverted_faces", inverted},
            {"max_flatness", optimize::kDegenerateFlatness}}},
          {"min_angle_degrees",
           {{"input", c.inputMinAngleDegrees}, {"result", c.resultMinAngleDegrees}}}};
}

double measuredEnergy(const optimize::FairingMeasures& m, const std::string& energy) {
  for (const optimize::EnergyMeasure& e : m.bending)
    if (e.energy == energy) return e.value;
  return std::nan("");
}

// One panel of the figure: the mesh's positions (all vertices), a column label and a title; with
// `vertexScalars` (#V) it is a signed map of them (the renderer's curvature style, titled
// `scalarLabel`) instead of reflection lines.
struct FigurePanel {
  std::string label, title;
  modeling::Positions positions;
  std::vector<double> vertexScalars;
  std::string scalarLabel, scalarSymbol;
};

// The region's outline (modeling::regionOutlineEdges) as render segments: #2S by 3, segment s
// from row 2s to row 2s + 1 (RenderOptions).
modeling::Positions regionOutline(const modeling::Mesh& mesh, const modeling::Stencils& stencils,
                                  const std::vector<bool>& region) {
  const std::vector<std::pair<int, int>> edges = modeling::regionOutlineEdges(stencils, region);
  modeling::Positions segments(2 * static_cast<Eigen::Index>(edges.size()), 3);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    segments.row(2 * static_cast<Eigen::Index>(i)) = mesh.positions.row(edges[i].first);
    segments.row(2 * static_cast<Eigen::Index>(i) + 1) = mesh.positions.row(edges[i].second);
  }
  return segments;
}

// The region's vertices (of the mesh faired: for holes, the filled one), ascending: what
// `flexure view` outlines on the input, CGAL's fair and the result.
std::vector<int> regionIndices(const std::vector<bool>& region) {
  std::vector<int> indices;
  for (std::size_t v = 0; v < region.size(); ++v)
    if (region[v]) indices.push_back(static_cast<int>(v));
  return indices;
}

// The signed distance of flexure's result from CGAL's fair at every mesh vertex,
// d_v = (x_v − y_v) · n̄_v, x flexure's and y CGAL's positions, n̄_v the area-weighted vertex
// normal of CGAL's patch (modeling::vertexNormals): to first order in |x − y| the distance of
// x_v from CGAL's surface, positive on the side the faces' normals point to; 0 off the region
// (the held rings and the rest of the mesh do not move).
std::vector<double> signedDistanceFromCgal(const modeling::Mesh& mesh,
                                           const modeling::FairingPatch& patch,
                                           const modeling::Positions& flexurePatch,
                                           const modeling::Positions& cgalPatch) {
  const Eigen::MatrixX3d normals = modeling::vertexNormals(cgalPatch, patch.mesh.triangles);
  std::vector<double> d(mesh.vertexCount(), 0.0);
  for (std::size_t p = 0; p < patch.inputVertex.size(); ++p) {
    const auto i = static_cast<Eigen::Index>(p);
    d[patch.inputVertex[p]] = (flexurePatch.row(i) - cgalPatch.row(i)).dot(normals.row(i));
  }
  return d;
}

// The figure: the patch and modeling::kContextRings more rings of the mesh, seen along the region's
// mean normal, every panel framed alike, the region's outline (regionOutline) drawn on each.
render::Image beforeAfterFigure(const FairCommandOptions& o, const modeling::Mesh& mesh,
                                const modeling::Stencils& stencils, const std::vector<bool>& region,
                                const modeling::FairingPatch& patch,
                                const std::vector<FigurePanel>& panels) {
  const Eigen::VectorXi rings =
      modeling::ringDistances(stencils, region, modeling::kHeldRings + modeling::kContextRings);
  std::vector<bool> keep(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) keep[v] = rings[v] >= 0;
  const modeling::Submesh shown = modeling::extractSubmesh(mesh, keep);
  std::vector<modeling::Mesh> meshes(panels.size(), shown.mesh);
  std::vector<std::vector<double>> scalars(panels.size());
  for (std::size_t i = 0; i < panels.size(); ++i) {
    for (std::size_t p = 0; p < shown.inputVertex.size(); ++p) {
      meshes[i].positions.row(static_cast<Eigen::Index>(p)) =
          panels[i].positions.row(shown.inputVertex[p]);
      if (!panels[i].vertexScalars.empty())
        scalars[i].push_back(panels[i].vertexScalars[shown.inputVertex[p]]);
    }
  }

  const Eigen::Vector3d n = modeling::regionNormal(patch.mesh, patch.moves);
  render::RenderOptions look;
  look.style = render::RenderStyle::Reflection;
  look.width = look.height = o.renderSize;
  look.outlineSegments = regionOutline(mesh, stencils, region);
  look.outlineWidth = std::max(2.0, o.renderSize / 250.0);
  // The camera direction e = (cos E sin A, −cos E cos A, sin E) of mesh_renderer.h set to n.
  look.elevationDegrees = std::asin(std::clamp(n.z(), -1.0, 1.0)) * 180.0 / kPi;
  look.azimuthDegrees = std::atan2(n.x(), -n.y()) * 180.0 / kPi;
  const Eigen::Index rows = shown.mesh.vertexCount();
  look.framingPoints.resize(rows * static_cast<Eigen::Index>(panels.size()), 3);
  for (std::size_t i = 0; i < panels.size(); ++i)
    look.framingPoints.middleRows(rows * static_cast<Eigen::Index>(i), rows) = meshes[i].positions;

  render::OffscreenContext context;
  render::FigureGrid grid;
  grid.title = o.input + "  --region " + o.region + "  (reflection lines; region outlined)";
  grid.rowLabels = {""};
  grid.panels.emplace_back();
  grid.panelTitles.emplace_back();
  for (std::size_t i = 0; i < panels.size(); ++i) {
    grid.columnLabels.push_back(panels[i].label);
    grid.panelTitles.back().push_back(panels[i].title);
    render::RenderOptions panelLook = look;
    if (!scalars[i].empty()) {
      panelLook.style = render::RenderStyle::Curvature;
      panelLook.vertexScalars = scalars[i];
      panelLook.scalarLabel = panels[i].scalarLabel;
      panelLook.scalarSymbol = panels[i].scalarSymbol;
    }
    grid.panels.back().push_back(render::renderMesh(context, meshes[i], panelLook));
  }
  return render::composeFigureGrid(grid);
}

// The method, energies and solver that the options name, each checked before any work.
struct FairSettings {
  bool cgal = false;                  // --method cgal: CGAL's fair is the result
  curvature::BendingOptions bending;  // the measures' energy (flat rest)
  std::string energyName;
  optimize::FairingOptions options;  // flexure's solve
};

// The figure is written as PNG: a name with another extension would hold a PNG under a wrong name.
bool endsWithPng(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".png";
}

FairSettings fairSettings(const FairCommandOptions& o) {
  modeling::writableMeshFormatOf(o.output);  // an unusable output name fails before any work
  if (!o.renderFile.empty() && !endsWithPng(o.renderFile))
    throw InputError("--render '" + o.renderFile +
                     "': the figure is a PNG image; give a name ending in .png");
  if (o.renderSize < kMinRenderSize || o.renderSize > 4096)
    throw InputError("--render-size must be in [" + std::to_string(kMinRenderSize) +
                     ", 4096] (got " + std::to_string(o.renderSize) + ")");
  optimize::FairingSpec spec = o.spec;
  applySolverArguments(o.solverArguments, spec.solver);
  FairSettings s;
  s.options = spec.options();  // every rule of the run, before any work
  s.cgal = spec.fairingMethod() == optimize::FairingMethod::Cgal;
  s.bending = spec.material();
  s.energyName = curvature::discretizationName(s.bending.discretization);
  return s;
}

optimize::FairingOptions flexureFairingOptions(const FairSettings& s, bool quiet) {
  optimize::FairingOptions options = s.options;
  options.solver.progress = !quiet;
  return options;
}

using FairOutcome = optimize::FairingOutcome;

// The patch faired by flexure (unless --method cgal) and by CGAL, measured with the command's
// bending options and checked.
FairOutcome fairPatch(const FairSettings& s, const modeling::FairingPatch& patch, bool quiet) {
  return optimize::fairAndCheck(
      patch, flexureFairingOptions(s, quiet),
      s.cgal ? optimize::FairingMethod::Cgal : optimize::FairingMethod::Flexure, s.bending);
}

std::vector<MeasureColumn> measureColumns(const FairCommandOptions& o, const RegionChoice& choice,
                                          const FairSettings& s, const FairOutcome& r) {
  // Headings fit printSideBySide's column of 17 characters.
  std::string input = choice.filled ? "holes filled" : "input";
  if (o.spec.remesh) input = choice.filled ? "fill remeshed" : "input remeshed";
  std::vector<MeasureColumn> columns = {{"input", input, r.before},
                                        {"cgal", "CGAL fair", r.cgalMeasures}};
  if (!s.cgal) columns.push_back({"flexure", "flexure " + s.energyName, r.after});
  return columns;
}

nlohmann::json holesJson(const modeling::FilledMesh& filled) {
  nlohmann::json holes = nlohmann::json::array();
  for (const modeling::FilledHole& h : filled.holes) {
    holes.push_back({{"boundary_edges", h.boundaryEdges},
                     {"vertex", h.loopVertex},
                     {"new_faces", h.newFaces},
                     {"new_vertices", h.newVertices}});
  }
  nlohmann::json skipped = nlohmann::json::array();
  for (const modeling::SkippedHole& h : filled.skipped) {
    skipped.push_back(
        {{"boundary_edges", h.boundaryEdges}, {"vertex", h.loopVertex}, {"reason", h.reason}});
  }
  return {{"filled", holes}, {"skipped", skipped}, {"loops_left", filled.loopsLeft}};
}

// flexure's own part of the report: the energy, the membrane, the start and the solver.
void addFlexureReport(const FairCommandOptions& o, const FairSettings& s, const FairOutcome& r,
                      nlohmann::json& report) {
  report["energy_name"] = s.energyName;
  report["poisson"] = curvature::effectivePoisson(s.bending);
  report["stiffness"] = s.bending.stiffness;
  // weight: as asked; final_weight: of the solve the result is from, after the fade's stages.
  report["membrane"] = {{"model", o.spec.membrane},
                        {"weight", s.options.membraneWeight},
                        {"final_weight", r.fairing->membraneWeight},
                        {"fade_stages", r.fairing->membraneFadeStages}};
  report["start"] = r.fairing->start == optimize::FairingStart::Input ? "input" : "biharmonic";
  report["metric"] = o.spec.metric;
  const optimize::MinimizeReport& solve = r.fairing->report;
  report["solver"] = {{"name", solve.solver},
                      {"factorizations", solve.factorizations},
                      {"converged", solve.converged},
                      {"termination", solve.termination},
                      {"iterations", solve.iterations},
                      {"initial_energy", solve.initialEnergy},
                      {"final_energy", solve.finalEnergy},
                      {"final_gradient_norm", solve.gradientNorm},
                      {"unknowns", solve.unknowns}};
}

// The JSON report without its "seconds".
nlohmann::json fairReport(const FairCommandOptions& o, const FairSettings& s,
                          const RegionChoice& choice, const modeling::FairingPatch& patch,
                          const FairOutcome& r, const std::vector<MeasureColumn>& columns) {
  nlohmann::json measures = nlohmann::json::object();
  for (const MeasureColumn& c : columns) measures[c.key] = measuresJson(c.measures);
  nlohmann::json checksReport = checksJson(r.checks);
  if (!s.cgal) {
    checksReport["min_angle_degrees"] = {
        {"input", r.slivers.inputDegrees},      {"cgal", r.slivers.cgalDegrees},
        {"result", r.slivers.resultDegrees},    {"limit", r.slivers.limitDegrees()},
        {"tolerance", kSliverToleranceDegrees}, {"passed", r.slivers.passed()},
        {"allow_slivers", o.spec.allowSlivers}};
  }
  nlohmann::json report = {
      {"input", o.input},
      {"output",
       r.converged(o.spec.allowSlivers) ? nlohmann::json(o.output) : nlohmann::json(nullptr)},
      {"method", o.spec.method},
      {"region",
       {{"spec", o.region},
        {"vertices", modeling::countVertices(choice.region)},
        {"indices", regionIndices(choice.region)},
        {"held_rings", modeling::kHeldRings},
        {"patch_vertices", patch.mesh.vertexCount()},
        {"patch_faces", patch.mesh.faceCount()}}},
      // Side by side: the input (for holes, CGAL's fill), CGAL's fair and flexure's result (with
      // --method flexure); "result" names the column that was written.
      {"measures", measures},
      {"result", s.cgal ? "cgal" : "flexure"},
      {"converged", r.converged(o.spec.allowSlivers)},
      {"checks", checksReport},
  };
  const std::string failure = r.failure(o.spec.allowSlivers);
  if (!failure.empty()) report["failed_check"] = failure;
  if (!s.cgal) addFlexureReport(o, s, r, report);
  if (choice.filled) report["holes"] = holesJson(*choice.filled);
  nlohmann::json errors = nlohmann::json::object();
  for (const optimize::EnergyMeasure& e : r.before.bending)
    if (!e.error.empty()) errors[e.energy] = e.error;
  if (!errors.empty()) report["energy_errors"] = errors;
  return report;
}

// An unconverged fair: the report (when asked for) without a mesh, and the error saying why.
[[noreturn]] void failUnconverged(const FairCommandOptions& o, const FairSettings& s,
                                  const FairOutcome& r, const nlohmann::json& report) {
  if (!o.reportFile.empty()) writeFailureReport(o.reportFile, report);
  const std::string notWritten =
      o.output + " not written" + (o.reportFile.empty() ? "" : ", see " + o.reportFile);
  if (r.solverConverged) {
    const bool onlySlivers = r.checks.passed();
    throw NumericalError(
        std::string(s.cgal ? "CGAL's fair" : "the fairing solve") +
        " ended at a result that fails its checks: " + r.failure(o.spec.allowSlivers) + "; " +
        notWritten +
        (s.cgal        ? ""
         : onlySlivers ? "; try a larger --membrane-weight, or pass --allow-slivers to accept it"
                       : "; try a larger --membrane-weight, another --energy or a smaller region"));
  }
  throw NumericalError("the fairing solve did not converge (" + r.fairing->report.termination +
                       "); " + notWritten + "; " + solverAdvice(r.fairing->report, o.spec.solver) +
                       " (or lower --membrane-weight)");
}

// The render: the input, CGAL's fair and (with --method flexure) flexure's result and its signed
// distance from CGAL's, each titled with its energy.
render::Image fairFigure(const FairCommandOptions& o, const FairSettings& s,
                         const RegionChoice& choice, const modeling::Stencils& stencils,
                         const modeling::FairingPatch& patch, const FairOutcome& r,
                         const modeling::Positions& faired, bool quiet) {
  const modeling::Mesh& mesh = choice.mesh;
  const auto title = [&](const optimize::FairingMeasures& m) {
    char text[96];
    std::snprintf(text, sizeof text, "E_%s = %.4g", s.energyName.c_str(),
                  measuredEnergy(m, s.energyName));
    return std::string(text);
  };
  const modeling::Positions cgalFaired =
      modeling::scatterPatchPositions(mesh.positions, patch, r.cgalPatch);
  std::vector<FigurePanel> panels = {{choice.filled ? "holes filled (CGAL)" : "input",
                                      title(r.before),
                                      mesh.positions,
                                      {},
                                      {},
                                      {}},
                                     {"CGAL fair", title(r.cgalMeasures), cgalFaired, {}, {}, {}}};
  if (!s.cgal) {
    panels.push_back({"flexure " + s.energyName, title(r.after), faired, {}, {}, {}});
    // The fourth panel: where and how far flexure's surface leaves CGAL's (the reflection
    // lines of the two often look alike; this map shows the difference itself). CGAL's
    // normals need its faces non-degenerate; without them the panel is left out.
    try {
      panels.push_back({"flexure - CGAL", "signed distance, flexure - CGAL", cgalFaired,
                        signedDistanceFromCgal(mesh, patch, r.patchAfter, r.cgalPatch),
                        "distance of flexure's result from CGAL's fair", "d"});
    } catch (const InputError& e) {
      if (!quiet)
        std::cerr << "flexure fair: no signed-distance panel: CGAL's fair has a degenerate "
                     "face ("
                  << e.what() << ")\n";
    }
  }
  return beforeAfterFigure(o, mesh, stencils, choice.region, patch, panels);
}

// The region remeshed (modeling::remeshRegion): `choice` takes the remeshed mesh and its region.
// Said on stderr unless quiet; the report's "remesh" object says it too.
modeling::RemeshedRegion remeshChoice(const FairCommandOptions& o, RegionChoice& choice,
                                      bool quiet) {
  modeling::RemeshedRegion r = modeling::remeshRegion(choice.mesh, choice.region, o.spec.remeshing);
  choice.mesh = r.mesh;
  choice.region = r.region;
  if (!quiet) {
    std::cerr << "flexure fair: remeshed the region's " << counted(r.facesBefore, "face")
              << " into " << r.facesAfter << " (target edge length " << r.targetEdgeLength << ", "
              << counted(r.iterations, "iteration") << "): smallest angle "
              << r.minAngleDegreesBefore << " -> " << r.minAngleDegreesAfter
              << " deg, Hausdorff distance " << r.hausdorffDistance << " from the input's faces\n";
  }
  if (!quiet && r.minAngleDegreesAfter < r.minAngleDegreesBefore) {
    std::cerr << "flexure fair: --remesh lowered the region's smallest angle; a target edge length "
                 "nearer the slivers' own (--remesh-edge-length) may suit this mesh better\n";
  }
  return r;
}

nlohmann::json remeshJson(const modeling::RemeshedRegion& r) {
  return {{"target_edge_length", r.targetEdgeLength},
          {"iterations", r.iterations},
          {"faces_before", r.facesBefore},
          {"faces_after", r.facesAfter},
          {"hausdorff_distance", r.hausdorffDistance},
          {"hausdorff_input_to_remeshed", r.hausdorffInputToRemeshed},
          {"hausdorff_remeshed_to_input", r.hausdorffRemeshedToInput},
          {"min_angle_degrees_before", r.minAngleDegreesBefore},
          {"min_angle_degrees_after", r.minAngleDegreesAfter},
          {"vertices", r.mesh.vertexCount()},
          {"faces", r.mesh.faceCount()}};
}

// Holes whose fills gained no interior vertex (CGAL closed each by triangles alone): the filled
// mesh is the result and there is nothing to fair. Writes it and the report; no figure.
void writeFilledOnly(const FairCommandOptions& o, const RegionChoice& choice, bool quiet) {
  const nlohmann::json report = {{"input", o.input},
                                 {"output", o.output},
                                 {"method", o.spec.method},
                                 {"region", {{"spec", o.region}, {"vertices", 0}}},
                                 {"result", "filled"},
                                 {"converged", true},
                                 {"holes", holesJson(*choice.filled)}};
  modeling::writeMesh(o.output, choice.mesh);
  if (!o.reportFile.empty()) writeJsonFile(o.reportFile, report);
  if (!quiet) {
    std::cerr << "flexure fair: wrote " << o.output << ": "
              << counted(static_cast<long long>(choice.filled->holes.size()), "hole")
              << " closed by triangles alone, no new vertex: nothing to fair"
              << (o.spec.remesh ? " or remesh" : "")
              << (o.renderFile.empty() ? "" : "; " + o.renderFile + " not drawn") << '\n';
  }
}

void runFairCommand(const FairCommandOptions& o, const GlobalOptions& global) {
  const auto start = Clock::now();
  const FairSettings s = fairSettings(o);
  if (!o.renderFile.empty()) render::OffscreenContext();  // a missing OSMesa fails before any solve

  std::vector<std::string> notices;
  modeling::Mesh input = modeling::readMesh(o.input, &notices);
  if (!global.quiet)
    for (const std::string& notice : notices) std::cerr << "flexure fair: " << notice << '\n';
  const modeling::Stencils inputStencils = modeling::compileStencils(input);
  RegionChoice choice = chooseRegion(o, std::move(input), inputStencils, global.quiet);
  if (choice.filled && modeling::countVertices(choice.region) == 0)
    return writeFilledOnly(o, choice, global.quiet);
  modeling::Stencils stencils = modeling::compileStencils(choice.mesh);
  modeling::requireFairableRegion(stencils, choice.region, o.input + ": --region " + o.region);
  std::optional<modeling::RemeshedRegion> remeshed;
  if (o.spec.remesh) {
    remeshed = remeshChoice(o, choice, global.quiet);
    stencils = modeling::compileStencils(choice.mesh);
    modeling::requireFairableRegion(stencils, choice.region,
                                    o.input + ": --region " + o.region + " remeshed");
  }
  const modeling::Mesh& mesh = choice.mesh;
  const modeling::FairingPatch patch = modeling::extractFairingPatch(mesh, stencils, choice.region);
  if (!global.quiet) {
    std::cerr << "flexure fair: region "
              << counted(modeling::countVertices(choice.region), "vertex", "vertices") << ", patch "
              << counted(patch.mesh.vertexCount(), "vertex", "vertices") << " and "
              << counted(patch.mesh.faceCount(), "face") << " (" << modeling::kHeldRings
              << " held rings)\n";
  }

  const FairOutcome r = fairPatch(s, patch, global.quiet);
  const modeling::Positions faired =
      modeling::scatterPatchPositions(mesh.positions, patch, r.patchAfter);
  const std::vector<MeasureColumn> columns = measureColumns(o, choice, s, r);
  nlohmann::json report = fairReport(o, s, choice, patch, r, columns);
  if (remeshed) report["remesh"] = remeshJson(*remeshed);
  if (!global.quiet) printSideBySide(columns);

  const auto seconds = [&] {
    return nlohmann::json{
        {"solve", r.solveSeconds}, {"cgal", r.cgalSeconds}, {"total", secondsSince(start)}};
  };
  if (!r.converged(o.spec.allowSlivers)) {
    report["seconds"] = seconds();
    failUnconverged(o, s, r, report);
  }
  if (!r.sliversPassed && !global.quiet)
    std::cerr << "flexure fair: --allow-slivers: accepting " << r.slivers.failure() << '\n';
  std::optional<render::Image> figure;
  if (!o.renderFile.empty())
    figure = fairFigure(o, s, choice, stencils, patch, r, faired, global.quiet);
  modeling::Mesh out = mesh;
  out.positions = faired;
  modeling::writeMesh(o.output, out);
  if (!o.cgalOutput.empty()) {
    modeling::Mesh cgal = mesh;
    cgal.positions = modeling::scatterPatchPositions(mesh.positions, patch, r.cgalPatch);
    modeling::writeMesh(o.cgalOutput, cgal);
    report["cgal_output"] = o.cgalOutput;
  }
  if (figure) render::writePng(o.renderFile, *figure);
  report["seconds"] = seconds();
  if (!o.reportFile.empty()) writeJsonFile(o.reportFile, report);
  if (!global.quiet) {
    std::cerr << "flexure fair: wrote " << o.output << " (E_" << s.energyName << " "
              << measuredEnergy(r.before, s.energyName) << " -> "
              << measuredEnergy(r.after, s.energyName) << ", max displacement "
              << r.after.maxDisplacement << ", smallest angle " << r.checks.inputMinAngleDegrees
              << " -> " << r.checks.resultMinAngleDegrees << " deg"
              << (remeshed ? " after remeshing" : "") << ", " << r.solveSeconds << " s)\n";
  }
}

}  // namespace

void registerFairCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<FairCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "fair",
      "Fair a region of a mesh: its vertices minimize a bending energy (flat rest) + membrane");
  auto files = CommandFiles::of(*sub);
  files->input("mesh", options->input, "Input mesh (.obj, .off, .ply, .stl)")->required();
  sub->add_option("--region", options->region,
                  "What moves: vertices:FILE (indices) | sphere:x,y,z,r | around:VERTEX,R (the "
                  "vertices within geodesic distance R mean edge lengths of VERTEX) | "
                  "rings:VERTEX,K (VERTEX and its K rings) | all-interior (all but the two "
                  "boundary rings) | holes[:N] (fill every hole, or those of at most N edges, "
                  "with CGAL and fair the new patches)")
      ->required();
  sub->add_option(
         "--method", options->spec.method,
         "flexure (nonlinear bending + membrane) | cgal (CGAL's linear fair, continuity 1)")
      ->capture_default_str();
  addBendingArguments(*sub, options->spec.bending, {"midedge", /*restCurvature=*/false});
  sub->add_option("--membrane", options->spec.membrane,
                  "mips (triangle shapes kept, sizes free; a barrier against collapse) | "
                  "conformal (the same, bounded) | stvk | springs (lengths kept too), on the "
                  "start's metric")
      ->capture_default_str();
  sub->add_option("--membrane-weight", options->spec.membraneWeight,
                  "w: how firmly the triangles keep their shapes against bending (mips, "
                  "conformal k_S = w k_B; stvk Y = w k_B / l^2, l the mean edge length); "
                  "default 1 on the input's metric, 0.1 on the current one");
  sub->add_option("--start", options->spec.start,
                  "Start of the nonlinear solve: best (whichever of the other two has the lower "
                  "bending energy) | biharmonic (the linear fair) | input")
      ->capture_default_str();
  sub->add_option("--metric", options->spec.metric,
                  "Whose metric the bending energy measures curvature in: input (an elastic "
                  "energy of the displacement from the input) | current (the surface's own: a "
                  "geometric, Willmore-type energy whose minimizers approach spheres; its metric "
                  "capped on slivers under 2.56 degrees) | current-exact (the same, uncapped)")
      ->capture_default_str();
  addSolverArguments(*sub, options->solverArguments);
  addSolverLimits(*sub, options->spec.solver, /*tolerances=*/false);
  files->output("-o,--output", options->output, "Faired mesh (.obj, .off, .ply)")->required();
  sub->add_flag("--remesh", options->spec.remesh,
                "Remesh the faces touching the region before fairing (CGAL's isotropic remeshing, "
                "their border and everything outside kept bit for bit); the output is the "
                "remeshed mesh faired, the report's remesh object has the Hausdorff distance to "
                "the input and the smallest angle before and after");
  sub->add_option("--remesh-edge-length", options->spec.remeshing.targetEdgeLength,
                  "With --remesh: the target edge length (default: the mean edge length of the "
                  "faces touching the region)");
  sub->add_option("--remesh-iterations", options->spec.remeshing.iterations,
                  "With --remesh: rounds of split, collapse, flip and relaxation")
      ->capture_default_str();
  sub->add_flag("--allow-slivers", options->spec.allowSlivers,
                "Fair without the angle barrier that keeps the smallest angle at most 1 degree "
                "below the input's and CGAL's fair's, and accept a result below that (otherwise "
                "exit 3)");
  files->output("--report", options->reportFile,
                "JSON report: region; input, CGAL's fair and the result side by side (all five "
                "energies, triangle quality, displacement); checks; time (written even when the "
                "solve fails)");
  files->output("--render", options->renderFile,
                "Reflection-line figure (PNG) of the region (outlined) and its surroundings: the "
                "input, CGAL's fair, flexure's result and the signed distance flexure - CGAL "
                "(with --method flexure)");
  files->output("--cgal-output", options->cgalOutput,
                "Also write CGAL's fair of the same region (.obj, .off, .ply): flexure view of "
                "the report shows input, CGAL and flexure side by side");
  sub->add_option("--render-size", options->renderSize, "Render panel size in pixels")
      ->capture_default_str()
      ->check(inRange(kMinRenderSize, 4096));
  sub->footer(
      "The two vertex rings around the region stay fixed (positions and normals).\n"
      "Exit 2 for bad input (empty region, region at the boundary, ...), 3 when the solve does "
      "not converge or its result fails a check (the report says why; no mesh is written).\n"
      "Example: flexure fair elephant-with-holes.off --region holes -o filled.off --report "
      "filled.json --render filled.png");
  files->onRun(global, [options, &global] { runFairCommand(*options, global); });
}

}  // namespace flexure::cli
