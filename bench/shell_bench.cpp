// Newton on a shell problem at large deformation (issue #13's comparison with libshell): a
// patch48 sheet of N × N cells, xyz mode, StVK membrane + midedge bending (ξ free, ν = 0.3,
// k_B = 1), the two outer vertex rings clamped onto z = a (x² + y²). A thickness t enters as the
// membrane's Young's modulus Y = 24 (1 − ν²) / t², so that the bending-to-stretching ratio is a
// plate's of thickness t (D = Y t³ / (12 (1 − ν²)) relative to Y t, with D = 2 k_B).
//
// Each case (N, t, a) runs, in turn in this process, the solvers of --solvers:
//   newton      flexure's Newton (the default solver): CHOLMOD supernodal, chord steps;
//   simplicial  the same Newton as a plain Newton solver does it — Eigen's SimplicialLLT,
//               refactored every iteration, no chord steps (MinimizeOptions::simplicialBaseline):
//               the stand-in for libshell's solver;
//   ceres       Ceres' Levenberg–Marquardt, the reference.
// Wall-clock seconds of optimize::minimize (its default tolerances and start: the linearized
// predictor), iterations, factorizations; ratio_to_newton = seconds / newton's seconds, same run.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"
#include "optimize/linear/heap_reuse.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace {

namespace curvature = flexure::curvature;
namespace modeling = flexure::modeling;
namespace optimize = flexure::optimize;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr double kPoisson = 0.3;

json runCase(int n, double thickness, double amplitude, const std::string& solver) {
  const modeling::Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Patch48, n, 1, {}});
  optimize::ProblemOptions shell;
  shell.bending.discretization = curvature::Discretization::Midedge;
  shell.bending.poisson = kPoisson;
  curvature::MembraneOptions membrane;
  membrane.model = curvature::MembraneModel::Stvk;
  membrane.poisson = kPoisson;
  membrane.young = 24.0 * (1.0 - kPoisson * kPoisson) / (thickness * thickness);
  shell.membrane = membrane;
  shell.dof = optimize::DofMode::Xyz;
  shell.fixedRings = 2;
  shell.boundarySurface = modeling::PolynomialSurface::quadratic(amplitude, 0.0, amplitude);
  shell.boundaryNormals = optimize::BoundaryNormals::Clamped;
  const optimize::Problem problem = optimize::buildProblem(mesh, shell);
  optimize::MinimizeOptions options;
  options.solver = solver == "ceres" ? optimize::Solver::Ceres : optimize::Solver::Newton;
  options.simplicialBaseline = solver == "simplicial";
  const auto start = Clock::now();
  const optimize::MinimizeResult r = optimize::minimize(problem, options);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return {{"n", n},
          {"thickness", thickness},
          {"amplitude", amplitude},
          {"solver", solver},
          {"seconds", seconds},
          {"iterations", r.report.iterations},
          {"factorizations", r.report.factorizations},
          {"converged", r.report.converged},
          {"final_energy", r.report.finalEnergy},
          {"gradient_norm", r.report.gradientNorm},
          {"unknowns", r.report.unknowns},
          {"termination", r.report.termination}};
}

}  // namespace

int main(int argc, char** argv) {
  optimize::reuseFreedMemory();  // as the flexure executable does
  CLI::App app("flexure shell benchmark: Newton vs a simplicial-Cholesky Newton and Ceres' LM");
  std::vector<int> sizes = {16, 32, 64, 128};
  std::vector<double> thicknesses = {0.05, 0.01}, amplitudes = {0.1, 1.0};
  std::vector<std::string> solvers = {"newton", "simplicial"};
  app.add_option("--sizes", sizes, "N, cells per side")->delimiter(',')->capture_default_str();
  app.add_option("--thicknesses", thicknesses)->delimiter(',')->capture_default_str();
  app.add_option("--amplitudes", amplitudes)->delimiter(',')->capture_default_str();
  app.add_option("--solvers", solvers, "newton, simplicial, ceres")
      ->delimiter(',')
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  for (const std::string& s : solvers) {
    if (s != "newton" && s != "simplicial" && s != "ceres") {
      std::cerr << "shell_bench: --solvers " << s << ": expected newton, simplicial, ceres\n";
      return 2;
    }
  }
  json cases = json::array();
  for (int n : sizes) {
    for (double t : thicknesses) {
      for (double a : amplitudes) {
        double newtonSeconds = 0.0;
        for (const std::string& solver : solvers) {
          json c = runCase(n, t, a, solver);
          if (solver == "newton") newtonSeconds = c["seconds"].get<double>();
          if (newtonSeconds > 0.0)
            c["ratio_to_newton"] = c["seconds"].get<double>() / newtonSeconds;
          std::fprintf(stderr, "N=%3d t=%.2f a=%.1f %-10s %8.3f s %3d it %3d fact %s%s\n", n, t, a,
                       solver.c_str(), c["seconds"].get<double>(), c["iterations"].get<int>(),
                       c["factorizations"].get<int>(),
                       c["converged"] ? "converged" : "NOT CONVERGED",
                       c.contains("ratio_to_newton") && solver != "newton"
                           ? ("  x" + std::to_string(c["ratio_to_newton"].get<double>())).c_str()
                           : "");
          cases.push_back(std::move(c));
        }
      }
    }
  }
  std::cout
      << json{{"problem",
               "patch48 N x N, xyz, StVK (Y = 24(1 - nu^2)/t^2, nu = 0.3) + midedge (k_B = 1), "
               "two clamped rings on z = a (x^2 + y^2)"},
              {"cases", cases}}
             .dump(2)
      << '\n';
  return 0;
}
