// flexure minimize: the static minimizer of a bending energy (plus a membrane in xyz mode) with
// fixed boundary vertices, written as a mesh, with a JSON report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/load_arguments.h"
#include "cli/membrane_arguments.h"
#include "cli/mesh_json.h"
#include "cli/plasticity_arguments.h"
#include "cli/solver_arguments.h"
#include "curvature/energy_registry.h"
#include "curvature/membrane_energy.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"
#include "optimize/inelastic/plasticity.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace flexure::cli {
namespace {

struct MinimizeCommandOptions {
  BendingArguments bending;
  std::string restFile, output, reportFile;
  std::string dof = "height";
  MembraneArguments membrane;
  LoadArguments load;
  std::string fix = "rings:2";
  std::string initFile, boundary, boundaryNormals;
  std::string start;  // linearized | given; empty: linearized with --boundary, given with --init
  bool linearized = false;
  optimize::MinimizeOptions solver;
  SolverArguments solverArguments;
  PlasticityArguments plasticity;
};

void requireSameConnectivity(const std::string& file, const modeling::Mesh& mesh,
                             const std::string& restFile, const modeling::Mesh& rest) {
  if (mesh.vertexCount() != rest.vertexCount() || mesh.triangles != rest.triangles) {
    throw InputError(
        file + ": does not share the connectivity of " + restFile + " (" +
        std::to_string(mesh.vertexCount()) + " vs " + std::to_string(rest.vertexCount()) +
        " vertices, or different faces): --init must be the rest mesh in other positions");
  }
}

optimize::BoundaryNormals boundaryNormals(const MinimizeCommandOptions& o, bool haveSurface,
                                          const curvature::EnergyEntry& energy,
                                          const GlobalOptions& global) {
  if (!o.boundaryNormals.empty() && !energy.hasEdgeUnknowns())
    throw InputError("--boundary-normals applies to --energy " +
                     curvature::energyNamesWhere(&curvature::EnergyEntry::hasEdgeUnknowns) +
                     " only");
  if (o.boundaryNormals == "free") return optimize::BoundaryNormals::Free;
  if (o.boundaryNormals == "clamped") {
    if (!haveSurface) {
      throw InputError(
          "--boundary-normals clamped needs a boundary surface to take the normals "
          "from: give --boundary quadratic:a,b,c");
    }
    return optimize::BoundaryNormals::Clamped;
  }
  if (!o.boundaryNormals.empty())
    throw InputError("--boundary-normals " + o.boundaryNormals + ": expected clamped or free");
  if (energy.hasEdgeUnknowns() && !haveSurface && !global.quiet)
    std::cerr << "flexure minimize: no boundary surface: " << energy.name
              << " boundary normals are free\n";
  return haveSurface ? optimize::BoundaryNormals::Clamped : optimize::BoundaryNormals::Free;
}

// --start, its default filled in: linearized with --boundary, given with --init.
std::string startName(const MinimizeCommandOptions& o) {
  if (!o.start.empty()) return o.start;
  return o.initFile.empty() ? "linearized" : "given";
}

optimize::Start parseStart(const MinimizeCommandOptions& o) {
  return optimize::parseStart(startName(o));
}

// Boundary data too large for double precision (quadratic:1e300,0,1) overflows in the solve: an
// energy of inf, or edges of infinite length that read as degenerate. The kernels take fourth
// powers of lengths (squared areas), which stay finite up to |x| = 1e75 (1e300 < 1.8e308); the
// first energy evaluation catches what overflows sooner. Lifting moves only z, so a finite start
// has no degenerate element: a failure here is the data's size.
void requireFiniteStartEnergy(const MinimizeCommandOptions& o, const optimize::Problem& problem) {
  const optimize::BoundaryConditions& bc = problem.boundary;
  const double largest = bc.start.cwiseAbs().maxCoeff();
  double startEnergy = std::numeric_limits<double>::infinity();
  if (largest <= 1e75) {
    try {
      startEnergy = problem.bending().energy(bc.start, bc.xi);
    } catch (const NumericalError&) {
    }
  }
  if (!std::isfinite(startEnergy)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  ": the lifted boundary reaches |z| = %.3g, too large for double precision "
                  "(the energy overflows; keep values below 1e75); scale the surface down",
                  largest);
    throw InputError("--boundary " + o.boundary + text);
  }
}

nlohmann::json reportJson(const MinimizeCommandOptions& o, const curvature::BendingOptions& b,
                          const optimize::MinimizeResult& result, bool meshWritten) {
  const optimize::MinimizeReport& r = result.report;
  nlohmann::json report = {
      {"rest", o.restFile},
      {"output", meshWritten ? nlohmann::json(o.output) : nlohmann::json(nullptr)},
      {"energy_name", std::string(curvature::discretizationName(b.discretization))},
      {"poisson", curvature::effectivePoisson(b)},
      {"dof", o.dof},
      {"membrane",
       o.membrane.model.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.membrane.model)},
      {"fix", o.fix},
      {"linearized", o.linearized},
      {"start", o.linearized ? "" : startName(o)},
      {"converged", r.converged},
      {"solver", r.solver},
      {"termination", r.termination},
      {"iterations", r.iterations},
      {"factorizations", r.factorizations},
      {"initial_energy", r.initialEnergy},
      {"final_energy", r.finalEnergy},
      {"final_gradient_norm", r.gradientNorm},
      {"seconds",
       {{"total", r.totalSeconds},
        {"evaluation", r.evaluationSeconds},
        {"linear_solver", r.linearSolverSeconds},
        {"ordering", r.orderingSeconds}}},
      {"problem",
       {{"vertices", r.vertices},
        {"fixed_vertices", r.fixedVertices},
        {"free_edge_unknowns", r.freeEdgeUnknowns},
        {"unknowns", r.unknowns},
        {"residuals", r.residuals}}},
  };
  if (!o.boundary.empty()) report["boundary"] = o.boundary;
  if (!o.load.gravity.empty())
    report["load"] = {
        {"gravity", o.load.gravity}, {"density", o.load.density}, {"mass", o.load.mass}};
  if (!o.load.obstacles.empty()) report["obstacles"] = o.load.obstacles;
  if (!o.initFile.empty()) report["init"] = o.initFile;
  if (result.xi.size() > 0) {
    report["xi"] = std::vector<double>(result.xi.data(), result.xi.data() + result.xi.size());
  }
  return report;
}

// --dof, with the membrane it needs (xyz) or refuses (height).
optimize::DofMode parseDof(const MinimizeCommandOptions& o) {
  if (o.dof == "height") {
    if (!o.membrane.model.empty())
      throw InputError("--membrane applies to --dof xyz (height mode keeps x and y at rest)");
    return optimize::DofMode::Height;
  }
  if (o.dof == "xyz") {
    if (o.membrane.model.empty()) {
      throw InputError(
          "--dof xyz needs a membrane (--membrane stvk|springs): bending alone has "
          "no stiffness against sliding in the surface");
    }
    return optimize::DofMode::Xyz;
  }
  throw InputError("--dof " + o.dof + ": expected height or xyz");
}

// The problem's options from the command's, on the compiled rest mesh (the fixed set and the
// boundary data are checked against it).
optimize::ProblemOptions problemOptions(const MinimizeCommandOptions& o,
                                        const curvature::BendingOptions& b, optimize::DofMode dof,
                                        const modeling::Mesh& restMesh,
                                        const modeling::Stencils& stencils,
                                        const GlobalOptions& global) {
  optimize::ProblemOptions p;
  p.bending = b;
  p.dof = dof;
  if (!o.membrane.model.empty()) p.membrane = membraneOptions(o.membrane);
  p.fixedVertex = optimize::parseFixedSet("--fix", o.fix, stencils, restMesh.positions);
  // Rings count from the boundary: on a closed mesh rings:K holds nothing.
  const std::vector<bool> boundary = optimize::fixedRings(stencils, 1);
  if (o.fix.rfind("rings:", 0) == 0 &&
      std::find(boundary.begin(), boundary.end(), true) == boundary.end())
    throw InputError(o.restFile + ": has no boundary (a closed surface), so --fix " + o.fix +
                     " holds no vertex; hold vertices by index with --fix vertices:FILE (three "
                     "not on a line remove the motions that cost no energy)");
  if (!o.boundary.empty()) p.boundarySurface = modeling::PolynomialSurface::parse(o.boundary);
  const std::optional<modeling::PolynomialSurface>& surface = p.boundarySurface;
  // An energy that owns edge unknowns (midedge's ξ) has boundary normals to hold or free.
  p.boundaryNormals =
      boundaryNormals(o, surface.has_value(), curvature::energyEntry(b.discretization), global);
  p.linearizedClamp = o.linearized;
  p.load = loadOptions(o.load);

  // Boundary data that overflows fails here, as bad input, rather than as a failed solve.
  const modeling::Positions& rest = restMesh.positions;
  for (Eigen::Index v = 0; surface && v < rest.rows(); ++v) {
    const double x = rest(v, 0), y = rest(v, 1);
    if (p.fixedVertex[v] &&
        !(std::isfinite(surface->height(x, y)) && surface->gradient(x, y).allFinite()))
      throw InputError("--boundary " + o.boundary + ": vertex " + std::to_string(v) +
                       " gets a non-finite height or slope (overflow); scale the surface down");
  }
  if (!surface) {
    const modeling::Mesh init = modeling::readMesh(o.initFile);
    requireSameConnectivity(o.initFile, init, o.restFile, restMesh);
    p.boundaryPositions = init.positions;
  }
  return p;
}

// Plastic forming (formPlastically): the minimizer after the load steps (and the release), with
// the plastic state for the report's "plasticity" section.
optimize::MinimizeResult formPlastically(const MinimizeCommandOptions& o,
                                         optimize::Problem& problem,
                                         const optimize::PlasticityOptions& plasticity,
                                         const optimize::MinimizeOptions& solver,
                                         nlohmann::json& section) {
  if (o.linearized)
    throw InputError("--linearized cannot form plastically: give the yield values without it");
  const optimize::FormingOptions forming = formingOptions(o.plasticity);
  const optimize::FormingResult formed =
      optimize::formPlastically(problem, plasticity, forming, solver);
  const optimize::FormingReport& r = formed.report;
  const auto valueOrNull = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  section = {{"yield_curvature", valueOrNull(plasticity.yieldCurvature)},
             {"yield_strain", valueOrNull(plasticity.yieldStrain)},
             {"hardening", plasticity.hardening},
             {"load_steps", forming.loadSteps},
             {"release", forming.release},
             {"release_pins", r.releasePins},
             {"element", "face"},  // every energy's plastic strain is per face
             {"elements", formed.state.yielded.size()},
             {"yielded_elements", r.yieldedElements},
             {"yielded_membrane_faces", r.yieldedFaces},
             {"plastic_dissipation", r.dissipation},
             {"solves", r.solves},
             {"settled", r.converged}};
  optimize::MinimizeResult result;
  result.positions = formed.positions;
  result.xi = formed.xi;
  result.report = r.lastSolve;
  result.report.converged = r.converged;
  if (!r.converged && r.lastSolve.converged)
    result.report.termination = "the plastic updates did not settle within the update limit";
  return result;
}

void runMinimizeCommand(const MinimizeCommandOptions& o, const GlobalOptions& global) {
  modeling::writableMeshFormatOf(o.output);  // an unusable output name fails before any work
  const curvature::BendingOptions b = bendingOptions(o.bending);
  optimize::MinimizeOptions solver = o.solver;
  applySolverArguments(o.solverArguments, solver);
  solver.linearized = o.linearized;
  solver.start = parseStart(o);
  solver.progress = !global.quiet && !o.linearized;
  const optimize::DofMode dof = parseDof(o);
  if (!o.initFile.empty() && !o.boundary.empty())
    throw InputError("give either --init or --boundary, not both");
  if (o.initFile.empty() && o.boundary.empty())
    throw InputError(
        "the fixed vertices need values: give --boundary quadratic:a,b,c or --init FILE");
  std::vector<optimize::Obstacle> obstacles = obstacleList(o.load);
  if (const std::vector<std::string> meshes = meshObstacleSpecs(o.load); !meshes.empty())
    throw InputError(
        "--obstacle " + meshes.front() +
        ": mesh obstacles are for flexure simulate; minimize takes planes and spheres");

  const modeling::Mesh restMesh = modeling::readMesh(o.restFile);
  modeling::Stencils stencils = modeling::compileStencils(restMesh);
  modeling::RestState rest = modeling::precomputeRestState(stencils, restMesh.positions);
  optimize::ProblemOptions options = problemOptions(o, b, dof, restMesh, stencils, global);
  options.obstacles = std::move(obstacles);
  const optimize::PlasticityOptions plasticity = plasticityOptions(o.plasticity);
  optimize::Problem problem = optimize::buildProblem(std::move(stencils), std::move(rest), options);
  if (options.boundarySurface) requireFiniteStartEnergy(o, problem);
  nlohmann::json plasticSection;
  const optimize::MinimizeResult result =
      plasticity.enabled() ? formPlastically(o, problem, plasticity, solver, plasticSection)
                           : optimize::minimize(problem, solver);
  nlohmann::json report = reportJson(o, b, result, result.report.converged);
  if (plasticity.enabled()) report["plasticity"] = plasticSection;
  if (!problem.obstacles.empty()) {
    report["obstacle_layer"] = problem.obstacles.layer();
    report["smallest_obstacle_distance"] = problem.obstacles.smallestDistance(result.positions);
  }
  if (!result.report.converged) {
    if (!o.reportFile.empty()) writeFailureReport(o.reportFile, report);
    throw NumericalError("the solve did not converge (" + result.report.termination + "); " +
                         o.output + " not written" +
                         (o.reportFile.empty() ? "" : ", see " + o.reportFile) + "; " +
                         solverAdvice(result.report, solver));
  }
  modeling::Mesh out = restMesh;
  out.positions = result.positions;
  modeling::writeMesh(o.output, out);
  if (!o.reportFile.empty()) writeJsonFile(o.reportFile, report);
  if (!global.quiet) {
    std::cerr << "flexure minimize: wrote " << o.output << " (energy "
              << result.report.initialEnergy << " -> " << result.report.finalEnergy << ", "
              << result.report.solver << ", " << counted(result.report.iterations, "iteration")
              << ", " << counted(result.report.factorizations, "factorization") << ", "
              << result.report.totalSeconds << " s)\n";
    if (plasticity.enabled())
      std::cerr << "flexure minimize: plastic: " << plasticSection["yielded_elements"] << " of "
                << plasticSection["elements"] << " " << plasticSection["element"].get<std::string>()
                << "s yielded in bending, " << plasticSection["yielded_membrane_faces"]
                << " faces in the membrane, dissipation " << plasticSection["plastic_dissipation"]
                << ", " << counted(plasticSection["solves"].get<int>(), "solve") << "\n";
  }
}

}  // namespace

void registerMinimizeCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<MinimizeCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "minimize", "Minimize a bending energy with fixed boundary vertices (static equilibrium)");
  auto files = CommandFiles::of(*sub);
  files->input("--rest", options->restFile, "Rest mesh (flat plate or curved shell)")->required();
  addBendingArguments(*sub, options->bending);
  sub->add_option("--dof", options->dof, "height (z only; x, y at rest) | xyz (needs --membrane)")
      ->capture_default_str();
  addMembraneArguments(*sub, options->membrane, "xyz mode: stvk | springs | conformal");
  addLoadArguments(*sub, options->load);
  sub->add_option("--fix", options->fix,
                  "Fixed vertices: rings:K (ring 0 = boundary; 2 clamps positions and normals), "
                  "vertices:FILE (indices) or box:X0,X1,Y0,Y1,Z0,Z1")
      ->capture_default_str();
  sub->add_option("--boundary", options->boundary,
                  "Fixed vertices lifted onto z = p(x, y) at their rest x, y (quadratic:a,b,c or "
                  "polynomial:EXPR); the interior starts at rest")
      ->check(surfaceSpec());
  files->input("--init", options->initFile,
               "A mesh (rest connectivity) giving the fixed vertices' values and the start");
  sub->add_option("--start", options->start,
                  "Start of the nonlinear solve: linearized (the linearized minimizer, one sparse "
                  "solve; default with --boundary) | given (the interior at rest, or as in --init; "
                  "default with --init)");
  sub->add_option("--boundary-normals", options->boundaryNormals,
                  curvature::energyNamesWhere(&curvature::EnergyEntry::hasEdgeUnknowns) +
                      ": clamped (boundary xi from --boundary's normals; the default with "
                      "--boundary) | free");
  sub->add_flag("--linearized", options->linearized,
                "Minimize the linearized energy E_lin exactly (one sparse solve)");
  addSolverArguments(*sub, options->solverArguments);
  addSolverLimits(*sub, options->solver, /*tolerances=*/true);
  addPlasticityArguments(*sub, options->plasticity);
  files->output("-o,--output", options->output, "Minimizer mesh (.obj, .off, .ply)")->required();
  files->output("--report", options->reportFile, "JSON report (written even when the solve fails)");
  sub->footer(
      "Exit 3 when the solve does not converge (the report says why; no mesh is written).\n"
      "Example: flexure minimize --rest plate.obj --energy midedge --boundary quadratic:1,0,1 "
      "-o bowl.obj --report bowl.json");
  files->onRun(global, [options, &global] { runMinimizeCommand(*options, global); });
}

}  // namespace flexure::cli
