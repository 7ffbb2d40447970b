// The command-line options that choose the nonlinear solver, shared by every command that runs a
// nonlinear solve (minimize, fair, compare, converge).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "optimize/solvers/minimize.h"

namespace flexure::cli {

struct SolverArguments {
  std::string solver = "newton";
  std::string hessian = "exact";
};

// --solver newton|ceres, --hessian exact|projected.
void addSolverArguments(CLI::App& sub, SolverArguments& arguments);

// Sets options.solver and options.hessian; an unknown name, or --hessian with --solver ceres
// (which factors JᵀJ, no Hessian), is an InputError naming the option and the choices.
void applySolverArguments(const SolverArguments& arguments, optimize::MinimizeOptions& options);

// The solver limits shared by minimize and fair (the solver itself: above), each
// checked for its range at parse time: --max-iterations, --threads, with `tolerances` the three
// tolerances.
void addSolverLimits(CLI::App& sub, optimize::MinimizeOptions& solver, bool tolerances);

// What to do about a solve that did not converge, from why it stopped: a non-finite energy
// (overflowing data) is not helped by more iterations.
std::string solverAdvice(const optimize::MinimizeReport& report,
                         const optimize::MinimizeOptions& solver);

}  // namespace flexure::cli
