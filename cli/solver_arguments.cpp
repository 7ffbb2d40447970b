#include "cli/solver_arguments.h"

#include <cmath>

#include "cli/command_files.h"
#include "modeling/errors.h"

namespace flexure::cli {

void addSolverArguments(CLI::App& sub, SolverArguments& arguments) {
  sub.add_option("--solver", arguments.solver,
                 "newton (exact Hessians, CHOLMOD; the default: faster in scripts/bench solve) | "
                 "ceres (Ceres' Levenberg-Marquardt, the reference)")
      ->capture_default_str();
  sub.add_option("--hessian", arguments.hessian,
                 "newton: exact (J^T J where indefinite) | projected (element Hessians "
                 "projected to positive semidefinite) | shifted (exact, H + mu I where "
                 "indefinite) | exact-projected (exact, projected where indefinite)")
      ->capture_default_str();
}

void applySolverArguments(const SolverArguments& arguments, optimize::MinimizeOptions& options) {
  options.solver = optimize::parseSolver(arguments.solver);
  options.hessian = optimize::parseHessianMode(arguments.hessian);
  options.validate();
}

void addSolverLimits(CLI::App& sub, optimize::MinimizeOptions& solver, bool tolerances) {
  sub.add_option("--max-iterations", solver.maxIterations)
      ->capture_default_str()
      ->check(inRange(1, 1e6));
  if (tolerances) {
    sub.add_option("--function-tolerance", solver.functionTolerance,
                   "ceres: |dE| / E; newton: the predicted decrease of a step / E")
        ->capture_default_str()
        ->check(positive());
    sub.add_option("--gradient-tolerance", solver.gradientTolerance)
        ->capture_default_str()
        ->check(positive());
    sub.add_option("--parameter-tolerance", solver.parameterTolerance)
        ->capture_default_str()
        ->check(positive());
  }
  sub.add_option("--threads", solver.threads)
      ->capture_default_str()
      ->check(inRange(1, maxThreads()));
}

std::string solverAdvice(const optimize::MinimizeReport& report,
                         const optimize::MinimizeOptions& solver) {
  if (!std::isfinite(report.initialEnergy) || !std::isfinite(report.finalEnergy) ||
      report.stop == optimize::NewtonStop::NonFinite) {
    return "the energy is not finite (overflow, or a degenerate triangle): values this large do "
           "not fit in double precision; scale the boundary data down, and check the mesh with "
           "flexure info";
  }
  if (report.iterations >= solver.maxIterations) {
    return "the solver used all its iterations (--max-iterations " +
           std::to_string(solver.maxIterations) + "): raise --max-iterations";
  }
  return "the solver stopped early; check the mesh for degenerate triangles (flexure info) or "
         "loosen the tolerances";
}

}  // namespace flexure::cli
