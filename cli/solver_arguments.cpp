#include "cli/solver_arguments.h"

#include "modeling/errors.h"

namespace flexure::cli {

void addSolverArguments(CLI::App& sub, SolverArguments& arguments) {
  sub.add_option("--solver", arguments.solver,
                 "newton (exact Hessians, CHOLMOD; the default: faster in scripts/bench solve) | "
                 "ceres (Ceres' Levenberg-Marquardt, the reference)")
      ->capture_default_str();
  sub.add_option("--hessian", arguments.hessian,
                 "newton: exact (J^T J where indefinite) | projected (element Hessians "
                 "projected to positive semidefinite)")
      ->capture_default_str();
}

void applySolverArguments(const SolverArguments& arguments, optimize::MinimizeOptions& options) {
  if (arguments.solver == "newton") {
    options.solver = optimize::Solver::Newton;
  } else if (arguments.solver == "ceres") {
    options.solver = optimize::Solver::Ceres;
  } else {
    throw InputError("--solver " + arguments.solver + ": expected newton or ceres");
  }
  if (arguments.hessian == "exact") {
    options.hessian = optimize::HessianMode::Exact;
  } else if (arguments.hessian == "projected") {
    options.hessian = optimize::HessianMode::Projected;
  } else {
    throw InputError("--hessian " + arguments.hessian + ": expected exact or projected");
  }
  if (options.solver == optimize::Solver::Ceres && arguments.hessian != "exact")
    throw InputError("--hessian applies to --solver newton (Ceres factors JᵀJ, not the Hessian)");
}

}  // namespace flexure::cli
