// Time-stepping speed (issue #17): a patch48 sheet of about 10 000 vertices (n = 99), StVK
// membrane (Y = 1e3) + each bending energy, Newmark (β = ¼, γ = ½), dt = 1/200 s, from rest under
// gravity. --scene drape (the scene, the default): nothing pinned, the sheet falls 0.05
// onto the sphere of radius 0.3 centred 0.35 below its centre and drapes over it (the obstacle
// barrier of optimize/assembly/obstacles.h); --scene hang: it hangs from two pinned corners. Per
// energy: steps per second, iterations (Newton and chord steps) and Hessian factorizations per step
// over
// --steps steps, or --duration seconds simulated (the first step, which includes building the
// Hessian pattern and its CHOLMOD analysis, timed apart), and with the sphere the smallest vertex
// distance to it over the run. --chord-steps false --predict false runs the plain Newton of
// DynamicsOptions (a fresh factor every iteration, Newton from x̂) for comparison. The issue's
// targets: ≥ 10 steps/s for hinge and cotan, ≥ 3 for midedge, on these 2-core machines; measured
// (docs/commands/simulate.md; idle machine): at 2 500 vertices (n = 49, 0.25 s) hinge 7.6
// steps/s, cotan 2.3, midedge 5.0; at 10 000 (45 steps, about 26 in contact) hinge 1.74, cotan
// 0.44, midedge 0.49. --trace prints every step; --step-tolerance sets
// DynamicsOptions::stepTolerance. Each record also has `iteration_costs`, what one Newton iteration
// of a step costs part by part on the same machine in the same run (the floor a contact step cannot
// go below: one Hessian, one factorization, one solve), and `step_over_newton_iteration`, a step's
// time in those units. Issue #27: --sizes (cells per side, default 49,99: 2 500 and 10 000
// vertices; 199, 40 000, is opt-in) and, per energy (default hinge, cotan, midedge, exact Hessian),
// --pcg both (default) runs each scene with the Newton steps factoring (before) and solved by
// conjugate gradients preconditioned by the kept factor (after,
// DynamicsOptions::preconditionedSteps), --repeat times alternated, and prints a markdown table on
// stderr: steps/s before and after and their ratio, factorizations, Hessians, PCG solves and
// iterations per step, the in-run unit costs and the floor (one first-derivative evaluation + one
// solve with a fixed factor). --orderings measures the step Hessian's fill-reducing orders instead
// (analysis, nnz(L), factorization, solve). Issue #29: --inelastic runs the drape per size and
// energy (default hinge, midedge) three ways, alternated --repeat times, best kept — elastic,
// plastic (PlasticDynamics::afterStep after every step) and fracture (FracturingDynamics with its
// event search and check) — with yield and fracture values no face reaches, so that the ratio to
// the elastic run is the overhead of the checks alone; a run where anything yields or cracks is no
// such measurement and the program exits
// 1. Midedge has no fracture run (its ξ do not carry across a cut). It also times, on the same
// scene, the parts a cut rebuilds (FracturingDynamics::checkFracture) against one step.
#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "modeling/rest_state.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/boundary_conditions.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracture.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/inelastic/plastic_dynamics.h"
#include "optimize/linear/cholesky_factor.h"
#include "optimize/linear/heap_reuse.h"
#include "optimize/problem.h"
#include "optimize/solvers/hessian_factorization.h"

namespace {

namespace curvature = flexure::curvature;
namespace modeling = flexure::modeling;
namespace optimize = flexure::optimize;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The cost of one Newton iteration of a step, part by part, on the step's own pattern and order
// (every vertex coordinate and ξ free), at the rest state with the inertia M/(βh²) of Newmark's
// β = ¼ on the diagonal: first derivatives (Φ, ∇Φ: a chord step or line-search trial), the exact
// Hessian, its factorization and one solve; the fastest of three runs each. A contact step needs
// at least one Hessian and factorization and a few first-derivative evaluations and solves, so
// hessian + factor bounds what a step costs from below (`newton_iteration_seconds` adds the rest).
json iterationCosts(const std::vector<const curvature::EnergyTerm*>& terms,
                    const modeling::RestState& rest, const Eigen::VectorXd& restXi,
                    const Eigen::VectorXd& mass, double dt) {
  const int vertexCount = static_cast<int>(rest.positions.rows());
  const std::vector<bool> free(3 * vertexCount + restXi.size(), true);
  const optimize::HessianAssembly assembly(terms, free, vertexCount, curvature::Derivatives::All);
  optimize::HessianFactorization factorization(assembly,
                                               optimize::hessianOrder(assembly, rest.positions));
  double gradient = 1e30, hessian = 1e30, factor = 1e30, solve = 1e30;
  for (int run = 0; run < 3; ++run) {
    auto start = Clock::now();
    assembly.evaluate(rest.positions, restXi, optimize::HessianProjection::Exact, nullptr,
                      curvature::SecondDerivatives::None);
    gradient = std::min(gradient, secondsSince(start));
    start = Clock::now();
    optimize::HessianEvaluation e =
        assembly.evaluate(rest.positions, restXi, optimize::HessianProjection::Exact);
    hessian = std::min(hessian, secondsSince(start));
    const std::vector<int>& unknowns = assembly.freeUnknowns();
    for (int k = 0; k < assembly.size(); ++k)
      if (unknowns[k] < 3 * vertexCount)
        e.values[assembly.columnStart()[k + 1] - 1] += 4.0 * mass[unknowns[k] / 3] / (dt * dt);
    start = Clock::now();
    if (!factorization.factor(e.values)) return {{"error", "the step Hessian at rest is singular"}};
    factor = std::min(factor, secondsSince(start));
    start = Clock::now();  // the solve right after a factorization, as a Newton step's
    factorization.solve(e.gradient);
    solve = std::min(solve, secondsSince(start));
  }
  return {{"gradient_seconds", gradient},
          {"hessian_seconds", hessian},
          {"factor_seconds", factor},
          {"solve_seconds", solve},
          {"newton_iteration_seconds", gradient + hessian + factor + solve}};
}

// The fill-reducing orders of the step Hessian's factorization (issue #27 item 3), on the
// iterationCosts matrix: the present choice (hessianOrder: geometric nested dissection of the
// vertices, CHOLMOD's nested dissection where ξ are free), AMD, METIS and CHOLMOD's nested
// dissection. Per
// order: the analysis (ordering included) seconds, nnz(L), and the fastest of three
// factorizations and solves.
json orderingCosts(const std::vector<const curvature::EnergyTerm*>& terms,
                   const modeling::RestState& rest, const Eigen::VectorXd& restXi,
                   const Eigen::VectorXd& mass, double dt) {
  const int vertexCount = static_cast<int>(rest.positions.rows());
  const std::vector<bool> free(3 * vertexCount + restXi.size(), true);
  const optimize::HessianAssembly assembly(terms, free, vertexCount, curvature::Derivatives::All);
  optimize::HessianEvaluation e =
      assembly.evaluate(rest.positions, restXi, optimize::HessianProjection::Exact);
  const std::vector<int>& unknowns = assembly.freeUnknowns();
  for (int k = 0; k < assembly.size(); ++k)
    if (unknowns[k] < 3 * vertexCount)
      e.values[assembly.columnStart()[k + 1] - 1] += 4.0 * mass[unknowns[k] / 3] / (dt * dt);
  optimize::CholeskyOptions options;  // as HessianFactorization's
  options.stopAtNonPositivePivot = true;
  options.cholmodWarnings = false;
  json out = json::object();
  const std::pair<const char*, optimize::FillReducingOrder> orders[] = {
      {"present", optimize::FillReducingOrder::NestedDissection},
      {"amd", optimize::FillReducingOrder::Amd},
      {"metis", optimize::FillReducingOrder::Metis},
      {"nesdis", optimize::FillReducingOrder::NestedDissection}};
  for (const auto& [name, ordering] : orders) {
    auto start = Clock::now();
    const std::vector<int> given = std::string(name) == "present"
                                       ? optimize::hessianOrder(assembly, rest.positions)
                                       : std::vector<int>();
    options.ordering = ordering;
    optimize::CholeskyFactor factor(assembly.size(), assembly.columnStart(), assembly.rowIndex(),
                                    given, options);
    const double analysis = secondsSince(start);
    double factorSeconds = 1e30, solveSeconds = 1e30;
    for (int run = 0; run < 3; ++run) {
      start = Clock::now();
      if (!factor.factor(e.values.data())) return {{"error", factor.failure()}};
      factorSeconds = std::min(factorSeconds, secondsSince(start));
      start = Clock::now();
      factor.solve(e.gradient);
      solveSeconds = std::min(solveSeconds, secondsSince(start));
    }
    out[name] = {{"analysis_seconds", analysis},
                 {"factor_nonzeros", factor.factorNonzeros()},
                 {"factor_seconds", factorSeconds},
                 {"solve_seconds", solveSeconds}};
  }
  return out;
}

// The scene's body: StVK (Y = 1e3) + `energy`, gravity; on the sphere (drape) or hanging from
// two corners.
optimize::ProblemOptions sceneBody(const modeling::Mesh& mesh, const std::string& energy,
                                   bool drape, bool selfContact = false) {
  optimize::ProblemOptions body;
  body.selfContact = selfContact;
  body.bending.discretization = curvature::parseDiscretization(energy);
  curvature::MembraneOptions membrane;
  membrane.young = 1e3;
  body.membrane = membrane;
  body.dof = optimize::DofMode::Xyz;
  body.boundaryNormals = optimize::BoundaryNormals::Free;
  // Two corners of the square held: (−½, −½) and (½, −½).
  body.fixedVertex.assign(mesh.vertexCount(), false);
  for (int v = 0; v < mesh.vertexCount() && !drape; ++v)
    body.fixedVertex[v] = std::abs(std::abs(mesh.positions(v, 0)) - 0.5) < 1e-12 &&
                          std::abs(mesh.positions(v, 1) + 0.5) < 1e-12;
  body.load.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  if (drape) body.obstacles = {optimize::parseObstacle("obstacle", "sphere:0,0,-0.35,0.3")};
  return body;
}

json measureOrderings(const modeling::Mesh& mesh, const std::string& energy, double dt) {
  const optimize::Problem problem = optimize::buildProblem(mesh, sceneBody(mesh, energy, true));
  optimize::TimeStepper stepper(problem, optimize::DynamicsOptions());
  stepper.start(problem.rest.positions, modeling::Positions::Zero(mesh.vertexCount(), 3),
                problem.restXi);
  return orderingCosts(problem.termPointers(), problem.rest, problem.restXi, stepper.masses(), dt);
}

json runEnergy(const modeling::Mesh& mesh, const std::string& energy, int steps, double dt,
               bool gaussNewton, bool drape, bool chordSteps, bool pcg, bool predict, bool trace,
               double stepTolerance, json* costs, bool selfContact = false,
               int quasiNewtonPairs = 0) {
  const optimize::ProblemOptions body = sceneBody(mesh, energy, drape, selfContact);
  optimize::DynamicsOptions options;
  if (gaussNewton) options.hessian = curvature::SecondDerivatives::GaussNewton;
  options.chordSteps = chordSteps;
  options.preconditionedSteps = pcg;
  options.quasiNewtonPairs = quasiNewtonPairs;
  if (stepTolerance > 0.0) options.stepTolerance = stepTolerance;
  options.predictAcceleration = predict;

  const optimize::Problem problem = optimize::buildProblem(mesh, body);
  auto start = Clock::now();
  optimize::TimeStepper stepper(problem, options);
  stepper.start(problem.rest.positions, modeling::Positions::Zero(mesh.vertexCount(), 3),
                problem.restXi);
  const double setup = secondsSince(start);
  start = Clock::now();
  const auto first = stepper.step(dt);
  const double firstSeconds = secondsSince(start);
  int iterations = 0, factorizations = 0, halvings = 0, hessians = 0, pcgSolves = 0,
      pcgIterations = 0;
  double closest =
      stepper.barrier().empty() ? 0.0 : stepper.barrier().smallestDistance(stepper.positions());
  start = Clock::now();
  for (int k = 1; k < steps; ++k) {
    const auto stepStart = Clock::now();
    const int iterationsBefore = iterations, factorizationsBefore = factorizations;
    // As flexure simulate does, a failed step is replaced by two half steps (one halving here).
    const auto advance = stepper.advance(dt, dt / 2);
    factorizations += advance.factorizations;
    hessians += advance.hessians;
    pcgSolves += advance.pcgSolves;
    pcgIterations += advance.pcgIterations;
    halvings += advance.halvings;
    if (!advance.completed)
      return {{"energy", energy},
              {"vertices", mesh.vertexCount()},
              {"pcg", pcg},
              {"quasi_newton_pairs", quasiNewtonPairs},
              {"hessian", gaussNewton ? "gauss-newton" : "exact"},
              {"error", advance.failure.failure}};
    iterations += advance.attemptedIterations;
    if (trace)
      std::fprintf(stderr,
                   "  step %4d t %.4f  %.3f s  iterations %d  factorizations %d  PCG solves %d "
                   "(%d iterations)\n",
                   k, stepper.time(), secondsSince(stepStart), iterations - iterationsBefore,
                   factorizations - factorizationsBefore, advance.pcgSolves, advance.pcgIterations);
    if (!stepper.barrier().empty())
      closest = std::min(closest, stepper.barrier().smallestDistance(stepper.positions()));
  }
  const double seconds = secondsSince(start);
  const optimize::EnergySample e = stepper.energies();
  const json floor = costs != nullptr && !costs->is_null()
                         ? *costs
                         : iterationCosts(problem.termPointers(), problem.rest, problem.restXi,
                                          stepper.masses(), dt);
  if (costs != nullptr) *costs = floor;
  const double perStep = 1.0 / (steps - 1);
  const optimize::TimeStepper::ContactStatistics& contact = stepper.contactStatistics();
  return {{"energy", energy},
          {"self_contact", selfContact},
          {"detection_seconds_per_step", contact.detectionSeconds * perStep},
          {"contact_pairs_mean", contact.steps > 0 ? contact.pairs / contact.steps : 0.0},
          {"contact_pairs_peak", contact.peakPairs},
          {"contact_pattern_growths", contact.patternGrowths},
          {"scene", drape ? "drape" : "hang"},
          {"hessian", gaussNewton ? "gauss-newton" : "exact"},
          {"vertices", mesh.vertexCount()},
          {"setup_seconds", setup},
          {"first_step_seconds", firstSeconds},
          {"first_step_newton_iterations", first.newtonIterations},
          {"steps", steps - 1},
          {"seconds", seconds},
          {"steps_per_second", (steps - 1) / seconds},
          {"newton_iterations_per_step", double(iterations) / (steps - 1)},
          {"factorizations_per_step", factorizations * perStep},
          {"hessians_per_step", hessians * perStep},
          {"pcg_solves_per_step", pcgSolves * perStep},
          {"pcg_iterations_per_step", pcgIterations * perStep},
          {"chord_steps", chordSteps},
          {"pcg", pcg},
          {"quasi_newton_pairs", quasiNewtonPairs},
          {"predict_acceleration", predict},
          {"halvings", halvings},
          {"smallest_sphere_distance", drape ? json(closest) : json(nullptr)},
          {"contact_layer", drape ? json(stepper.barrier().layer()) : json(nullptr)},
          {"iteration_costs", floor},
          // A step's time in Newton iterations at their floor (one Hessian, factor and solve).
          {"step_over_newton_iteration",
           floor.contains("newton_iteration_seconds")
               ? json(seconds / (steps - 1) / floor["newton_iteration_seconds"].get<double>())
               : json(nullptr)},
          {"final_kinetic", e.kinetic},
          {"final_total", e.total()}};
}

// The inelastic runs' values, above anything the drape reaches (a curvature of 1e3 is a radius of
// 1 mm, a tenth of the 10 000-vertex mesh's edge; Green strains stay below 0.01): the checks run
// on every face and step, and nothing yields or cracks.
constexpr double kUnreachedYieldCurvature = 1e3, kUnreachedYieldStrain = 0.5, kHardening = 0.1;
constexpr double kUnreachedFractureStrain = 0.5, kFractureThickness = 1e-3;

enum class Inelastic { Elastic, Plastic, Fracture };
const char* inelasticName(Inelastic way) {
  return way == Inelastic::Elastic ? "elastic" : way == Inelastic::Plastic ? "plastic" : "fracture";
}

// The drape with `way`'s checks after every step, as flexure simulate runs them
// (FracturingDynamics, PlasticDynamics::afterStep); the first step (the stepper's analysis and
// first factorization) is timed apart. Also the largest fibre strain (thickness
// kFractureThickness) at the end, and what yielded or cracked.
json runInelastic(const modeling::Mesh& mesh, const std::string& energy, Inelastic way, int steps,
                  double dt) {
  const optimize::ProblemOptions body = sceneBody(mesh, energy, true);
  std::optional<optimize::FractureOptions> fracture;
  if (way == Inelastic::Fracture)
    fracture = optimize::FractureOptions{kUnreachedFractureStrain, kFractureThickness};
  optimize::FracturingDynamics dynamics(mesh, optimize::buildProblem(mesh, body), body,
                                        optimize::DynamicsOptions(), fracture);
  dynamics.start(mesh.positions, modeling::Positions::Zero(mesh.vertexCount(), 3));
  std::optional<optimize::PlasticDynamics> plastic;
  if (way == Inelastic::Plastic) {
    optimize::PlasticityOptions plasticity;
    plasticity.yieldCurvature = kUnreachedYieldCurvature;
    plasticity.yieldStrain = kUnreachedYieldStrain;
    plasticity.hardening = kHardening;
    plastic.emplace(dynamics.problem(), dynamics.stepper(), plasticity);
  }
  int yieldedElements = 0, yieldedFaces = 0;
  long step = 0;
  double seconds = 0.0, firstSeconds = 0.0;
  int iterations = 0;
  for (int k = 0; k < steps; ++k) {
    const auto start = Clock::now();
    const auto advance = dynamics.advance(dt, dt / 2, step);
    if (!advance.completed)
      return {{"energy", energy}, {"way", inelasticName(way)}, {"error", advance.failure.failure}};
    if (plastic) {
      const optimize::PlasticUpdate update = plastic->afterStep();
      yieldedElements += update.yieldedElements;
      yieldedFaces += update.yieldedFaces;
    }
    (k == 0 ? firstSeconds : seconds) += secondsSince(start);
    if (k > 0) iterations += advance.attemptedIterations;
    step += advance.steps;
  }
  const optimize::FractureCriterion criterion(dynamics.restMesh());
  double largestStrain = 0.0;
  for (const optimize::FacePrincipalStrain& s : criterion.principalStrains(
           criterion.strains(dynamics.stepper().positions()), kFractureThickness))
    largestStrain = std::max(largestStrain, s.strain);
  return {{"energy", energy},
          {"way", inelasticName(way)},
          {"vertices", mesh.vertexCount()},
          {"first_step_seconds", firstSeconds},
          {"steps", steps - 1},
          {"seconds", seconds},
          {"steps_per_second", (steps - 1) / seconds},
          {"newton_iterations_per_step", double(iterations) / (steps - 1)},
          {"yielded_elements", yieldedElements},
          {"yielded_membrane_faces", yieldedFaces},
          {"cracks", dynamics.cracks().size()},
          {"largest_fibre_strain_at_end", largestStrain}};
}

// What FracturingDynamics::checkFracture rebuilds after a cut, part by part, on the drape's
// problem (the same size as a cut mesh of it): the Problem (stencils, rest state, masses), the
// fracture criterion's rest data and event faces, the TimeStepper (its Hessian pattern, the
// fill-reducing order and CHOLMOD's symbolic analysis, here each timed apart as well), its start,
// and the first numerical factorization, which the next step makes. The fastest of three.
json rebuildCosts(const modeling::Mesh& mesh, const std::string& energy, double dt) {
  const optimize::ProblemOptions body = sceneBody(mesh, energy, true);
  json best = json::object();
  const auto keep = [&](const char* part, double seconds) {
    if (!best.contains(part) || seconds < best[part].get<double>()) best[part] = seconds;
  };
  for (int run = 0; run < 3; ++run) {
    auto start = Clock::now();
    const optimize::Problem problem = optimize::buildProblem(mesh, body);
    keep("problem_seconds", secondsSince(start));
    start = Clock::now();
    const optimize::FractureCriterion criterion(mesh);
    const std::vector<bool> events = optimize::fractureEventFaces(mesh, {});
    keep("criterion_seconds", secondsSince(start));
    start = Clock::now();
    optimize::TimeStepper stepper(problem, optimize::DynamicsOptions());
    keep("stepper_seconds", secondsSince(start));
    start = Clock::now();
    stepper.start(mesh.positions, modeling::Positions::Zero(mesh.vertexCount(), 3), problem.restXi);
    keep("start_seconds", secondsSince(start));
    // The stepper's parts, again apart: pattern, order, analysis, one factorization.
    const int vertexCount = mesh.vertexCount();
    const std::vector<bool> free(3 * vertexCount + problem.restXi.size(), true);
    start = Clock::now();
    const optimize::HessianAssembly assembly(problem.termPointers(), free, vertexCount,
                                             curvature::Derivatives::All);
    keep("pattern_seconds", secondsSince(start));
    start = Clock::now();
    const std::vector<int> order = optimize::hessianOrder(assembly, mesh.positions);
    keep("order_seconds", secondsSince(start));
    start = Clock::now();
    optimize::HessianFactorization factorization(assembly, order);
    keep("analysis_seconds", secondsSince(start));
    optimize::HessianEvaluation e =
        assembly.evaluate(mesh.positions, problem.restXi, optimize::HessianProjection::Exact);
    const std::vector<int>& unknowns = assembly.freeUnknowns();
    for (int k = 0; k < assembly.size(); ++k)
      if (unknowns[k] < 3 * vertexCount)
        e.values[assembly.columnStart()[k + 1] - 1] +=
            4.0 * stepper.masses()[unknowns[k] / 3] / (dt * dt);
    start = Clock::now();
    if (!factorization.factor(e.values)) return {{"error", "the step Hessian at rest is singular"}};
    keep("factor_seconds", secondsSince(start));
  }
  best["rebuild_seconds"] =
      best["problem_seconds"].get<double>() + best["criterion_seconds"].get<double>() +
      best["stepper_seconds"].get<double>() + best["start_seconds"].get<double>() +
      best["factor_seconds"].get<double>();
  return best;
}

// --inelastic: per size and energy the three ways alternated `repeat` times (the best kept), the
// rebuild's parts; false when something yielded or cracked or a run failed.
bool measureInelastic(const std::vector<int>& cells, const std::string& energies, int steps,
                      double dt, int repeat, json& records) {
  bool clean = true;
  std::fprintf(stderr,
               "\n| vertices | energy | elastic steps/s | plastic steps/s | plastic/elastic | "
               "fracture steps/s | fracture/elastic | yielded, cracked | largest fibre strain "
               "| rebuild after a cut s (problem + criterion + stepper [pattern, order, "
               "analysis] + start + factor) | rebuild / elastic step |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const int size : cells) {
    const modeling::Mesh mesh =
        modeling::generateMesh({modeling::MeshFamily::Patch48, size, 1, {}});
    std::stringstream list(energies);
    for (std::string energy; std::getline(list, energy, ',');) {
      std::vector<Inelastic> ways = {Inelastic::Elastic, Inelastic::Plastic};
      // Midedge's ξ do not carry across a cut (FracturingDynamics refuses it); cotan has no rest
      // curvature per element for a yield curvature.
      if (energy == "cotan")
        ways = {Inelastic::Elastic, Inelastic::Fracture};
      else if (energy != "midedge")
        ways.push_back(Inelastic::Fracture);
      std::map<Inelastic, json> best;
      for (int run = 0; run < repeat; ++run)
        for (const Inelastic way : ways) {
          json record = runInelastic(mesh, energy, way, steps, dt);
          std::fprintf(stderr, "%s\n", record.dump().c_str());
          if (record.contains("error") || record["yielded_elements"] != 0 ||
              record["yielded_membrane_faces"] != 0 || record["cracks"] != 0)
            clean = false;
          if (!best.count(way) || record.contains("error") ||
              (!best[way].contains("error") &&
               record.value("steps_per_second", 0.0) > best[way].value("steps_per_second", 0.0)))
            best[way] = record;
        }
      json rebuild = rebuildCosts(mesh, energy, dt);
      const auto rate = [&](Inelastic way) {
        return best.count(way) ? best[way].value("steps_per_second", 0.0) : 0.0;
      };
      const auto cell = [&](Inelastic way, bool ratio) {
        char text[32] = "–";
        if (rate(way) > 0.0)
          std::snprintf(text, sizeof text, "%.3g",
                        ratio ? rate(Inelastic::Elastic) / rate(way) : rate(way));
        return std::string(text);
      };
      int yielded = 0, cracked = 0;
      double strain = 0.0;
      for (auto& [way, r] : best) {
        yielded += r.value("yielded_elements", 0) + r.value("yielded_membrane_faces", 0);
        cracked += r.value("cracks", 0);
        strain = std::max(strain, r.value("largest_fibre_strain_at_end", 0.0));
        records.push_back(r);
      }
      records.push_back(
          {{"energy", energy}, {"vertices", mesh.vertexCount()}, {"rebuild", rebuild}});
      const double rebuildSeconds = rebuild.value("rebuild_seconds", 0.0);
      std::fprintf(stderr,
                   "| %d | %s | %s | %s | %s | %s | %s | %d, %d | %.3g | %.3f (%.3f + %.3f + %.3f "
                   "[%.3f, %.3f, %.3f] + %.3f + %.3f) | %.2f |\n",
                   mesh.vertexCount(), energy.c_str(), cell(Inelastic::Elastic, false).c_str(),
                   cell(Inelastic::Plastic, false).c_str(), cell(Inelastic::Plastic, true).c_str(),
                   cell(Inelastic::Fracture, false).c_str(),
                   cell(Inelastic::Fracture, true).c_str(), yielded, cracked, strain,
                   rebuildSeconds, rebuild.value("problem_seconds", 0.0),
                   rebuild.value("criterion_seconds", 0.0), rebuild.value("stepper_seconds", 0.0),
                   rebuild.value("pattern_seconds", 0.0), rebuild.value("order_seconds", 0.0),
                   rebuild.value("analysis_seconds", 0.0), rebuild.value("start_seconds", 0.0),
                   rebuild.value("factor_seconds", 0.0), rebuildSeconds * rate(Inelastic::Elastic));
    }
  }
  if (!clean)
    std::fprintf(stderr,
                 "simulate_bench: something yielded, cracked or failed in an inelastic run: "
                 "not an overhead measurement\n");
  return clean;
}

}  // namespace

// The before/after table on stderr (markdown): per size and energy, steps/s with the Newton
// steps factoring (before) and solved by PCG on the kept factor (after), their ratio, the counts
// per step, the in-run unit costs, and the floor of a step (one first-derivative evaluation and
// one solve with a fixed factor).
void printTable(const json& records) {
  std::fprintf(stderr,
               "\n| vertices | energy | steps/s before | steps/s after | after/before | "
               "factorizations/step before → after | Hessians/step after | PCG solves/step | "
               "PCG iterations/step | first derivatives ms | Hessian ms | factorization ms | "
               "solve ms | floor ms | step/floor after |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const json& after : records) {
    if (!after.value("pcg", false) || after.contains("error")) continue;
    const json* before = nullptr;
    for (const json& r : records)
      if (!r.value("pcg", true) && r.value("energy", "") == after["energy"] &&
          r.value("quasi_newton_pairs", 0) == after.value("quasi_newton_pairs", 0) &&
          r.value("vertices", 0) == after["vertices"] && r.value("hessian", "") == after["hessian"])
        before = &r;
    const bool paired = before != nullptr && !before->contains("error");
    const json& c = after["iteration_costs"];
    const double floor = c.value("gradient_seconds", 0.0) + c.value("solve_seconds", 0.0);
    const double stepSeconds = 1.0 / after["steps_per_second"].get<double>();
    std::fprintf(
        stderr,
        "| %d | %s | %s | %.3g | %s | %s → %.2f | %.2f | %.2f | %.2f | %.1f | %.1f | %.1f | %.1f | "
        "%.1f | %.1f |\n",
        after["vertices"].get<int>(), after["energy"].get<std::string>().c_str(),
        paired ? std::to_string((*before)["steps_per_second"].get<double>()).substr(0, 5).c_str()
               : "failed",
        after["steps_per_second"].get<double>(),
        paired ? std::to_string(after["steps_per_second"].get<double>() /
                                (*before)["steps_per_second"].get<double>())
                     .substr(0, 4)
                     .c_str()
               : "–",
        paired ? std::to_string((*before)["factorizations_per_step"].get<double>())
                     .substr(0, 4)
                     .c_str()
               : "–",
        after["factorizations_per_step"].get<double>(), after["hessians_per_step"].get<double>(),
        after["pcg_solves_per_step"].get<double>(), after["pcg_iterations_per_step"].get<double>(),
        1e3 * c.value("gradient_seconds", 0.0), 1e3 * c.value("hessian_seconds", 0.0),
        1e3 * c.value("factor_seconds", 0.0), 1e3 * c.value("solve_seconds", 0.0), 1e3 * floor,
        floor > 0.0 ? stepSeconds / floor : 0.0);
  }
}

// The quasi-Newton table on stderr (markdown): per size, energy and PCG mode, steps/s with chord
// steps on the kept factor (off) and L-BFGS steps on it (on), their ratio, and the Newton
// iterations (all iterations) and factorizations per step off → on.
void printQuasiNewtonTable(const json& records) {
  std::fprintf(stderr,
               "\n| vertices | energy | PCG | steps/s off | steps/s on | on/off | iterations/step "
               "off → on | factorizations/step off → on |\n|---|---|---|---|---|---|---|---|\n");
  for (const json& on : records) {
    if (on.value("quasi_newton_pairs", 0) == 0 || on.contains("error")) continue;
    const json* off = nullptr;
    for (const json& r : records)
      if (r.value("quasi_newton_pairs", 1) == 0 && r.value("energy", "") == on["energy"] &&
          r.value("vertices", 0) == on["vertices"] && r.value("hessian", "") == on["hessian"] &&
          r.value("pcg", false) == on.value("pcg", false))
        off = &r;
    if (off == nullptr || off->contains("error")) {
      std::fprintf(stderr, "| %d | %s | %s | failed | %.3g | – | – | – |\n",
                   on["vertices"].get<int>(), on["energy"].get<std::string>().c_str(),
                   on.value("pcg", false) ? "on" : "off", on["steps_per_second"].get<double>());
      continue;
    }
    const double a = (*off)["steps_per_second"], b = on["steps_per_second"];
    std::fprintf(stderr, "| %d | %s | %s | %.3g | %.3g | %.2f | %.2f → %.2f | %.2f → %.2f |\n",
                 on["vertices"].get<int>(), on["energy"].get<std::string>().c_str(),
                 on.value("pcg", false) ? "on" : "off", a, b, b / a,
                 (*off)["newton_iterations_per_step"].get<double>(),
                 on["newton_iterations_per_step"].get<double>(),
                 (*off)["factorizations_per_step"].get<double>(),
                 on["factorizations_per_step"].get<double>());
  }
}

namespace {

// A stepper compared by the elastic runs: Newton steps by PCG on the kept factor or factoring;
// the steps on the kept factor L-BFGS with this many pairs, or chord steps (0).
struct StepperMode {
  bool pcg = false;
  int quasiNewtonPairs = 0;
};

// The bench's options, as the flags give them.
struct BenchOptions {
  int n = 99, steps = 40, repeat = 1;
  double dt = 1.0 / 200.0, duration = 0.0;
  std::string scene = "drape", sizes = "49,99", pcgModes = "both", quasiNewtonModes = "off";
  int quasiNewtonPairs = 6;  // m of --quasi-newton on
  std::string energies = "hinge,cotan,midedge", hessians = "exact";
  bool orderings = false, inelastic = false, selfContact = false;
  bool chordSteps = true, predict = true;
  bool trace = false;
  double stepTolerance = 0.0;  // 0: DynamicsOptions' default
  bool energiesGiven = false;  // --energies given
  std::vector<int> cells;      // the sizes run: --n, or --sizes
};

// The command line into `o`; the exit code when it asks for help or is refused.
std::optional<int> parseArguments(int argc, char** argv, BenchOptions& o) {
  CLI::App app(
      "flexure simulate benchmark: a ~10k-vertex sheet draping on a sphere (or hanging), "
      "Newmark, per energy");
  app.add_option("--n", o.n, "Cells per side (n = 99: 10 000 vertices); overrides --sizes");
  app.add_option("--sizes", o.sizes,
                 "Cells per side, a list (49, 99, 199: 2 500, 10 000, 40 000 vertices)")
      ->capture_default_str();
  app.add_option("--pcg", o.pcgModes,
                 "both (before: Newton steps factor; after: PCG on the kept factor), on, off")
      ->capture_default_str();
  app.add_option("--quasi-newton", o.quasiNewtonModes,
                 "off (chord steps on the kept factor), on (L-BFGS steps on it, "
                 "--quasi-newton-pairs), both (alternated)")
      ->capture_default_str();
  app.add_option("--quasi-newton-pairs", o.quasiNewtonPairs,
                 "L-BFGS pairs m of --quasi-newton on (DynamicsOptions::quasiNewtonPairs)")
      ->capture_default_str();
  app.add_option("--repeat", o.repeat, "Runs of each before/after pair, alternated (best kept)")
      ->capture_default_str();
  app.add_option("--steps", o.steps, "Steps per energy")->capture_default_str();
  app.add_flag("--inelastic", o.inelastic,
               "Elastic vs plastic vs fracture runs of the drape, nothing yielding, "
               "and the parts of the rebuild after a cut");
  app.add_flag("--self-contact", o.selfContact,
               "The drape with self-contact off and on, alternated --repeat times (best kept): "
               "steps/s, their ratio, collision detection seconds per step, pairs");
  app.add_flag("--orderings", o.orderings,
               "Only the step Hessian's fill-reducing orders: analysis, nnz(L), factor, solve");
  app.add_option("--duration", o.duration,
                 "Simulated seconds per energy (the issue's: 2); overrides --steps");
  app.add_option("--scene", o.scene, "drape (on a sphere) | hang (from two corners)")
      ->capture_default_str();
  app.add_option("--dt", o.dt, "Time step")->capture_default_str();
  app.add_option("--energies", o.energies)->capture_default_str();
  app.add_option("--hessians", o.hessians, "exact and/or gauss-newton (the step's Hessian of E)")
      ->capture_default_str();
  app.add_option("--chord-steps", o.chordSteps,
                 "Reuse the step Hessian's factor while it contracts (false: plain Newton)")
      ->capture_default_str();
  app.add_option("--predict", o.predict, "Newton starts from x̂ + β h² a_n (false: from x̂)")
      ->capture_default_str();
  app.add_option("--step-tolerance", o.stepTolerance,
                 "DynamicsOptions::stepTolerance ε_v (default: its default; 1e-9: the strict "
                 "reference)");
  app.add_flag("--trace", o.trace, "Each step's seconds, iterations and factorizations on stderr");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (o.scene != "drape" && o.scene != "hang") {
    std::cerr << "--scene " << o.scene << ": expected drape or hang\n";
    return 2;
  }
  if (app.count("--step-tolerance") > 0 && !(o.stepTolerance > 0.0)) {
    std::cerr << "--step-tolerance " << o.stepTolerance << ": expected a value > 0\n";
    return 2;
  }
  if (o.pcgModes != "both" && o.pcgModes != "on" && o.pcgModes != "off") {
    std::cerr << "--pcg " << o.pcgModes << ": expected both, on or off\n";
    return 2;
  }
  if (o.quasiNewtonModes != "both" && o.quasiNewtonModes != "on" && o.quasiNewtonModes != "off") {
    std::cerr << "--quasi-newton " << o.quasiNewtonModes << ": expected both, on or off\n";
    return 2;
  }
  if (!(o.quasiNewtonPairs >= 1 && o.quasiNewtonPairs <= 100)) {
    std::cerr << "--quasi-newton-pairs " << o.quasiNewtonPairs << ": expected 1 to 100\n";
    return 2;
  }
  if (o.duration > 0.0) o.steps = static_cast<int>(std::lround(o.duration / o.dt)) + 1;
  if (app.count("--n") > 0) {
    o.cells = {o.n};
  } else {
    std::stringstream sizeList(o.sizes);
    for (std::string size; std::getline(sizeList, size, ',');) o.cells.push_back(std::stoi(size));
  }
  o.energiesGiven = app.count("--energies") > 0;
  return std::nullopt;
}

// One energy on `mesh` with each Hessian asked for: the best of the repeated runs of each mode
// (`modes`: PCG on or off, L-BFGS pairs), alternated, appended to `records`.
void runEnergyModes(const BenchOptions& o, const modeling::Mesh& mesh, const std::string& energy,
                    const std::vector<StepperMode>& modes, json& records) {
  for (const char* hessian : {"exact", "gauss-newton"}) {
    if (o.hessians.find(hessian) == std::string::npos) continue;
    json costs;  // measured once per energy and size, shared by its before and after
    std::vector<json> best(modes.size());
    for (int run = 0; run < o.repeat; ++run)
      for (size_t m = 0; m < modes.size(); ++m) {
        json record = runEnergy(mesh, energy, o.steps, o.dt, std::string(hessian) == "gauss-newton",
                                o.scene == "drape", o.chordSteps, modes[m].pcg, o.predict, o.trace,
                                o.stepTolerance, &costs, false, modes[m].quasiNewtonPairs);
        if (best[m].is_null() || record.contains("error") ||
            (!best[m].contains("error") &&
             record["steps_per_second"] > best[m]["steps_per_second"]))
          best[m] = record;
      }
    for (json& record : best) {
      std::fprintf(stderr, "%-8s %s\n", energy.c_str(), record.dump().c_str());
      records.push_back(record);
    }
  }
}

// Every size and energy: the step Hessian's orderings (--orderings) or the timed runs.
json runElastic(const BenchOptions& o, const std::vector<StepperMode>& modes) {
  json records = json::array();
  for (const int size : o.cells) {
    const modeling::Mesh mesh =
        modeling::generateMesh({modeling::MeshFamily::Patch48, size, 1, {}});
    std::stringstream list(o.energies);
    for (std::string energy; std::getline(list, energy, ',');) {
      if (o.orderings) {
        records.push_back({{"energy", energy},
                           {"vertices", mesh.vertexCount()},
                           {"orderings", measureOrderings(mesh, energy, o.dt)}});
        std::fprintf(stderr, "%s\n", records.back().dump().c_str());
        continue;
      }
      runEnergyModes(o, mesh, energy, modes, records);
    }
  }
  return records;
}

}  // namespace

// The growth exponents log(t₂/t₁) / log(n₂/n₁) of the detection seconds per step t between
// consecutive sizes n (vertices), per energy.
void printDetectionGrowth(
    const std::map<std::string, std::vector<std::array<double, 2>>>& seconds) {
  std::fprintf(stderr,
               "\n| energy | vertices n₁ → n₂ | detection s/step t₁ → t₂ | growth exponent |\n"
               "|---|---|---|---|\n");
  for (const auto& [energy, points] : seconds)
    for (std::size_t k = 1; k < points.size(); ++k) {
      const auto& [n1, t1] = points[k - 1];
      const auto& [n2, t2] = points[k];
      std::fprintf(stderr, "| %s | %.0f → %.0f | %.4f → %.4f | %.2f |\n", energy.c_str(), n1, n2,
                   t1, t2, std::log(t2 / t1) / std::log(n2 / n1));
    }
}

// --self-contact: per size and energy the drape without and with self-contact (PCG off, the
// default stepper), alternated `repeat` times, the best of each kept; a table of steps/s, their
// ratio (the target: on/off time ≤ 1.5), the broad phase + CCD seconds per step and the pairs,
// then the detection's growth with the size.
json measureSelfContact(const BenchOptions& o) {
  json records = json::array();
  std::map<std::string, std::vector<std::array<double, 2>>> detectionSeconds;
  std::fprintf(stderr,
               "\n| vertices | energy | off steps/s | on steps/s | on time / off time | "
               "detection s/step | detection share | pairs mean, peak | pattern growths |\n"
               "|---|---|---|---|---|---|---|---|---|\n");
  for (const int size : o.cells) {
    const modeling::Mesh mesh =
        modeling::generateMesh({modeling::MeshFamily::Patch48, size, 1, {}});
    std::stringstream list(o.energies);
    for (std::string energy; std::getline(list, energy, ',');) {
      json best[2];
      for (int run = 0; run < o.repeat; ++run)
        for (int on = 0; on < 2; ++on) {
          json record = runEnergy(mesh, energy, o.steps, o.dt, false, true, o.chordSteps, false,
                                  o.predict, o.trace, o.stepTolerance, nullptr, on == 1);
          if (best[on].is_null() || record.contains("error") ||
              (!best[on].contains("error") &&
               record["steps_per_second"] > best[on]["steps_per_second"]))
            best[on] = record;
        }
      for (const json& record : best) records.push_back(record);
      if (best[0].contains("error") || best[1].contains("error")) continue;
      const double off = best[0]["steps_per_second"], on = best[1]["steps_per_second"];
      const double detection = best[1]["detection_seconds_per_step"];
      std::fprintf(stderr, "| %d | %s | %.2f | %.2f | %.2f | %.4f | %.0f %% | %.1f, %d | %d |\n",
                   mesh.vertexCount(), energy.c_str(), off, on, off / on, detection,
                   100.0 * detection * on, best[1]["contact_pairs_mean"].get<double>(),
                   best[1]["contact_pairs_peak"].get<int>(),
                   best[1]["contact_pattern_growths"].get<int>());
      detectionSeconds[energy].push_back({double(mesh.vertexCount()), detection});
    }
  }
  printDetectionGrowth(detectionSeconds);
  return records;
}

int main(int argc, char** argv) {
  flexure::optimize::reuseFreedMemory();
  BenchOptions o;
  if (const std::optional<int> exitCode = parseArguments(argc, argv, o)) return *exitCode;
  if (o.inelastic) {
    const std::string energies = o.energiesGiven ? o.energies : "hinge,midedge";
    json records = json::array();
    const bool clean = measureInelastic(o.cells, energies, o.steps, o.dt, o.repeat, records);
    std::cout << json({{"dt", o.dt}, {"scene", "drape"}, {"records", records}}).dump(2) << "\n";
    return clean ? 0 : 1;
  }
  if (o.selfContact) {
    const json records = measureSelfContact(o);
    std::cout << json({{"dt", o.dt}, {"scene", "drape"}, {"records", records}}).dump(2) << "\n";
    return 0;
  }
  // PCG (after) first: the last record of an energy is the default stepper's, which
  // bench/python_bench.py compares with Python's Simulation.
  std::vector<StepperMode> modes;
  for (const bool pcg : {true, false}) {
    if (o.pcgModes == (pcg ? "off" : "on")) continue;
    if (o.quasiNewtonModes != "off") modes.push_back({pcg, o.quasiNewtonPairs});
    if (o.quasiNewtonModes != "on") modes.push_back({pcg, 0});
  }
  const json records = runElastic(o, modes);
  if (o.pcgModes == "both") printTable(records);
  if (o.quasiNewtonModes == "both") printQuasiNewtonTable(records);
  std::cout << json({{"n", o.cells.size() == 1 ? json(o.cells[0]) : json(o.cells)},
                     {"dt", o.dt},
                     {"scene", o.scene},
                     {"records", records}})
                   .dump(2)
            << "\n";
  return 0;
}
