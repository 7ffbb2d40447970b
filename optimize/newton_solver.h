// Newton's method on the exact Hessian for the static minimizers of minimize.h.
//
// Each iteration assembles E, ∇E and ∇²E over the free unknowns (hessian_assembly.h), factors
// ∇²E with CHOLMOD (supernodal; the symbolic analysis is done once for the problem and reused),
// and steps along δ = −(∇²E)⁻¹ ∇E with a backtracking line search on the true energy (Armijo:
// E(x + αδ) ≤ E(x) + 10⁻⁴ α ∇Eᵀδ, α halved). Where the Hessian is not positive definite (away
// from a minimizer, e.g. a compressed membrane about to buckle) μI is added, the smallest μ of a
// 10-fold sequence that makes it so — every step is a descent direction. Near a strict minimizer
// the exact Hessian is positive definite and the convergence quadratic. HessianMode::Projected
// factors the sum of the element Hessians projected to positive semidefinite instead, in every
// iteration.
//
// Start::Linearized: the first step is the Newton step from the rest state with the fixed
// unknowns moved to their values — at a stress-free rest (every residual zero) the Hessian is
// JᵀJ and this step is the linearized minimizer; its factorization shares the analysis.
//
// Stops, converged, when the gradient's max-norm is at most gradientTolerance, or when a full
// step (α = 1) was predicted to lower E by at most functionTolerance · E (½ λ², λ² = −∇Eᵀδ the
// Newton decrement): the gradient is then evaluated once more (first derivatives only) and
// reported. No factorization is made only to confirm convergence.
#pragma once

#include <vector>

#include "optimize/minimize.h"

namespace flexure::optimize {

// Called by minimize() for Solver::Newton; the problem has been checked (requireWellPosed).
MinimizeResult minimizeNewton(const std::vector<const EnergyTerm*>& terms,
                              const BoundaryConditions& conditions, const Positions& rest,
                              const Eigen::VectorXd& restXi, const MinimizeOptions& options);

}  // namespace flexure::optimize
