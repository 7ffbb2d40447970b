// Newton's method on the exact Hessian for the static minimizers of minimize.h: the objective
// E − fᵀx + B (static_energy.h) minimized by the Newton loop (newton_loop.h) with
// the static stop rule — converged when the predicted decrease ½ λ² of a step is at most
// functionTolerance · E, or when ‖∇E‖∞ ≤ gradientTolerance. HessianMode::Projected factors the
// sum of the element Hessians projected to positive semidefinite instead of the exact one.
//
// Start::Linearized: the first step is the Gauss–Newton step from the rest state with the fixed
// unknowns moved to their values — at a stress-free rest (every residual zero) JᵀJ is the exact
// Hessian and this is the Newton step and the linearized minimizer; its factor is the first one
// the chord steps use. Where x, y are moved in height mode (the z-only Hessian does not couple
// them) the start is the linearized minimizer with all derivatives instead (one least-squares
// solve, energy_evaluation.h).
#pragma once

#include <vector>

#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

// Called by minimize() for Solver::Newton with the problem's or other boundary conditions; the
// problem has been checked (requireWellPosed). `kept` (may be null): the analysis and factor of an
// earlier solve, used where its pattern is this problem's, and refilled with this solve's.
MinimizeResult minimizeNewton(const Problem& problem, const BoundaryConditions& conditions,
                              const MinimizeOptions& options, KeptFactorization* kept);

}  // namespace flexure::optimize
