// Accuracy of the time step's stopping rule (DynamicsOptions::stepTolerance ε_v: Newton stops when
// ‖δ‖∞ / h ≤ ε_v l, l the rest bounding-box diagonal). Each scene runs once at the strict
// reference ε_v = 1e-9 and once per --tolerances value; per run: the largest vertex distance to
// the reference over the whole run (compared after every dt, each run covering dt by halving as
// flexure simulate does) divided by l, the energy balance (TimeStepper::balanceVerdict and its
// relative drift; "driven" where pins move), Newton iterations and factorizations per step, and
// steps per second (wall clock, the first step included). The scenes: drape, simulate_bench's
// (a sheet dropped 0.05 onto a sphere, StVK Y = 1e3 + each of --energies with k_B = 1, undamped,
// on an n × n patch48 sheet); drape-soft, examples/drape-sphere.json's (k_B = 0.01, Rayleigh
// α = 2: it wrinkles); fold and cantilever, examples/fold-strip.json and cantilever-droop.json.
// Self-contact is on, as flexure simulate has it. The runs at --tolerances take
// --quasi-newton-pairs m (DynamicsOptions::quasiNewtonPairs, the library's default unless given);
// the reference takes chord steps (m = 0), the strict stepper. JSON on stdout, a Markdown table on
// stderr: scripts/bench step-tolerance.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/assembly/pin_motion.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/problem.h"

namespace {

namespace curvature = flexure::curvature;
namespace modeling = flexure::modeling;
namespace optimize = flexure::optimize;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr double kReference = 1e-9;  // the strict stepper's ε_v

// One scene of examples/: a patch48 sheet of n × n cells, StVK (Y = young) + `energy` of stiffness
// k_B, gravity, Rayleigh α, the vertices with x in [pinFrom, pinTo] pinned (none when empty),
// optionally rotating, an obstacle, steps of dt for `duration`.
struct Scene {
  std::string name, energy;
  int n = 12;
  double stiffness = 1.0, young = 1e3, rayleighMass = 0.0, dt = 0.01, duration = 1.0;
  std::string obstacle;               // parseObstacle's spec; empty: none
  double pinFrom = 1.0, pinTo = 0.0;  // empty range: nothing pinned
  optimize::PinMotion motion;
};

std::vector<Scene> scenes(const std::vector<std::string>& energies, int drapeN, double drapeDt,
                          double drapeDuration) {
  std::vector<Scene> out;
  for (const std::string& energy : energies)  // simulate_bench's drape, undamped, k_B = 1
    out.push_back({"drape",
                   energy,
                   drapeN,
                   1.0,
                   1e3,
                   0.0,
                   drapeDt,
                   drapeDuration,
                   "sphere:0,0,-0.35,0.3",
                   1.0,
                   0.0,
                   {}});
  for (const std::string& energy : energies)  // examples/drape-sphere.json: k_B = 0.01, α = 2
    out.push_back({"drape-soft",
                   energy,
                   drapeN,
                   0.01,
                   1e3,
                   2.0,
                   drapeDt,
                   drapeDuration,
                   "sphere:0,0,-0.32,0.3",
                   1.0,
                   0.0,
                   {}});
  Scene fold{"fold", "hinge", 8, 0.05, 1e3, 2.0, 0.01, 1.0, "plane:0,0,1,-0.02", 0.45, 0.5, {}};
  fold.motion = optimize::PinMotion::rotation({0, -1, 0}, {0, 0, 0.1}, M_PI);
  out.push_back(fold);  // examples/fold-strip.json
  out.push_back({"cantilever", "midedge", 12, 10.0, 1e4, 8.0, 0.01, 1.0, "", -0.5, -0.4, {}});
  return out;  // examples/cantilever-droop.json
}

struct Run {
  std::vector<modeling::Positions> positions;  // after each dt
  double diagonal = 1.0;                       // l
  json record;
};

Run runScene(const Scene& s, double stepTolerance, int quasiNewtonPairs) {
  modeling::GeneratorOptions g;
  g.n = s.n;
  const modeling::Mesh mesh = modeling::generateMesh(g);
  optimize::ProblemOptions body;
  body.bending.discretization = curvature::parseDiscretization(s.energy);
  body.bending.stiffness = s.stiffness;
  curvature::MembraneOptions membrane;
  membrane.young = s.young;
  body.membrane = membrane;
  body.dof = optimize::DofMode::Xyz;
  body.fixedRings = 0;
  body.boundaryNormals = optimize::BoundaryNormals::Free;
  body.selfContact = true;
  body.load.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  if (!s.obstacle.empty()) body.obstacles = {optimize::parseObstacle("obstacle", s.obstacle)};
  body.fixedVertex.assign(mesh.vertexCount(), false);
  for (int v = 0; v < mesh.vertexCount(); ++v)
    body.fixedVertex[v] = mesh.positions(v, 0) >= s.pinFrom && mesh.positions(v, 0) <= s.pinTo;
  const optimize::Problem problem = optimize::buildProblem(mesh, body);
  optimize::DynamicsOptions options;
  options.rayleighMass = s.rayleighMass;
  options.pinMotion = s.motion;
  options.stepTolerance = stepTolerance;
  options.quasiNewtonPairs = quasiNewtonPairs;

  Run run;
  run.diagonal = (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).norm();
  const auto start = Clock::now();
  optimize::TimeStepper stepper(problem, options);
  stepper.start(problem.rest.positions, modeling::Positions::Zero(mesh.vertexCount(), 3),
                problem.restXi);
  const long steps = std::lround(s.duration / s.dt);
  long taken = 0, iterations = 0, factorizations = 0, halvings = 0;
  std::string failure;
  for (long k = 0; k < steps; ++k) {
    const auto a = stepper.advance(s.dt, s.dt / 64.0);  // flexure simulate's --min-dt
    taken += a.steps;
    iterations += a.attemptedIterations;
    factorizations += a.factorizations;
    halvings += a.halvings;
    if (!a.completed) {
      failure = a.failure.failure;
      break;
    }
    run.positions.push_back(stepper.positions());
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const optimize::BalanceVerdict verdict = stepper.balanceVerdict();
  run.record = {{"scene", s.name},
                {"energy", s.energy},
                {"vertices", mesh.vertexCount()},
                {"dt", s.dt},
                {"step_tolerance", stepTolerance},
                {"quasi_newton_pairs", quasiNewtonPairs},
                {"completed", failure.empty()},
                {"failure", failure},
                {"steps", taken},
                {"halvings", halvings},
                {"newton_iterations_per_step", double(iterations) / std::max(1L, taken)},
                {"factorizations_per_step", double(factorizations) / std::max(1L, taken)},
                {"steps_per_second", taken / seconds},
                {"balance", optimize::balanceVerdictName(verdict)},
                {"balance_drift", stepper.balance().relativeDrift()}};
  return run;
}

// The largest vertex distance between the runs after any dt both reached, divided by l.
double largestDistance(const Run& a, const Run& b) {
  const double diagonal = b.diagonal;
  double worst = 0.0;
  const std::size_t common = std::min(a.positions.size(), b.positions.size());
  for (std::size_t k = 0; k < common; ++k)
    worst = std::max(worst, (a.positions[k] - b.positions[k]).rowwise().norm().maxCoeff());
  return worst / diagonal;
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Accuracy and speed of the time step's stopping rule against the strict reference");
  std::string tolerances = "1e-2,1e-3,1e-4", energies = "hinge,cotan,midedge";
  int drapeN = 24;
  double drapeDuration = 0.8, drapeDt = 0.005;
  app.add_option("--tolerances", tolerances, "ε_v values compared with 1e-9")
      ->capture_default_str();
  app.add_option("--energies", energies, "The drape's energies")->capture_default_str();
  app.add_option("--n", drapeN, "The drape's cells per side")->capture_default_str();
  app.add_option("--dt", drapeDt, "The drape's time step")->capture_default_str();
  app.add_option("--duration", drapeDuration, "The drape's simulated seconds")
      ->capture_default_str();
  int pairs = optimize::DynamicsOptions().quasiNewtonPairs;
  app.add_option("--quasi-newton-pairs", pairs, "L-BFGS pairs of the runs at --tolerances")
      ->capture_default_str();
  std::string only = "drape,fold,cantilever";
  app.add_option("--scenes", only, "drape, drape-soft, fold and/or cantilever")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::vector<double> values;
  for (const std::string& t : split(tolerances)) values.push_back(std::stod(t));
  const std::vector<std::string> wanted = split(only);

  json out = json::array();
  std::fprintf(stderr,
               "| scene | energy | ε_v | max distance / l | balance (drift) | Newton it./step | "
               "factorizations/step | steps/s |\n|---|---|---|---|---|---|---|---|\n");
  for (const Scene& s : scenes(split(energies), drapeN, drapeDt, drapeDuration)) {
    if (std::find(wanted.begin(), wanted.end(), s.name) == wanted.end()) continue;
    const Run reference = runScene(s, kReference, 0);
    std::vector<Run> runs;
    for (double value : values) runs.push_back(runScene(s, value, pairs));
    runs.push_back(reference);
    for (Run& run : runs) {
      json& r = run.record;
      r["max_distance_over_l"] = largestDistance(run, reference);
      std::fprintf(stderr, "| %s | %s | %.0e | %.2e | %s (%.2g) | %.2f | %.2f | %.1f |%s\n",
                   s.name.c_str(), s.energy.c_str(), r["step_tolerance"].get<double>(),
                   r["max_distance_over_l"].get<double>(), r["balance"].get<std::string>().c_str(),
                   r["balance_drift"].get<double>(), r["newton_iterations_per_step"].get<double>(),
                   r["factorizations_per_step"].get<double>(), r["steps_per_second"].get<double>(),
                   r["completed"].get<bool>()
                       ? ""
                       : (" failed: " + r["failure"].get<std::string>()).c_str());
      out.push_back(r);
    }
  }
  std::cout << out.dump(2) << "\n";
  return 0;
}
