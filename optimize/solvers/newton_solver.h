// Newton's method on the exact Hessian for the static minimizers of minimize.h, reusing each
// sparse factorization for as long as it pays.
//
// Every iteration evaluates E and ∇E over the free unknowns (first derivatives) and, with the
// last factor F, the step δ = −F⁻¹∇E and its predicted decrease ½ λ² = −½ ∇Eᵀδ. Converged when
// that is at most functionTolerance · E, or when ‖∇E‖∞ ≤ gradientTolerance: no factorization is
// made only to confirm. Otherwise δ is taken as a chord step (modified Newton) while λ² shrinks
// at least 10-fold per step; when it does not, the exact Hessian at the iterate is assembled
// (hessian_assembly.h) and factored with CHOLMOD (supernodal; the symbolic analysis is done
// once per problem and reused) for a Newton step, converging quadratically near the minimizer.
// Steps are searched on the true energy (Armijo: E(x + αδ) ≤ E(x) + 10⁻⁴ α ∇Eᵀδ, α halved).
// Where the Hessian is not positive definite (away from a minimizer: a fairing start, a
// compressed membrane about to buckle) that step uses the Gauss–Newton matrix JᵀJ at the iterate
// instead (positive semidefinite; + μI where singular): every step is a descent direction, and
// near a strict minimizer the steps are Newton's. HessianMode::Projected factors the sum of the
// element Hessians projected to positive semidefinite instead of the exact one.
//
// Start::Linearized: the first step is the Gauss–Newton step from the rest state with the fixed
// unknowns moved to their values — at a stress-free rest (every residual zero) JᵀJ is the exact
// Hessian and this is the Newton step and the linearized minimizer; its factor is the first one
// the chord steps use.
#pragma once

#include <vector>

#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

// Called by minimize() for Solver::Newton; the problem has been checked (requireWellPosed).
MinimizeResult minimizeNewton(const std::vector<const EnergyTerm*>& terms,
                              const BoundaryConditions& conditions, const Positions& rest,
                              const Eigen::VectorXd& restXi, const MinimizeOptions& options);

}  // namespace flexure::optimize
