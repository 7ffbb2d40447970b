// The linearized energies of docs/energies.md minimized: ½ |J u + r0|² over free unknowns, the
// energy of a displacement with the edge unknowns minimized, and the midedge ξ minimizing E at
// fixed positions. J and r0 come from assembly/energy_evaluation.h.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "optimize/assembly/energy_evaluation.h"

namespace flexure::optimize {

// min over the unknowns marked free of ½ |J u + r0|², starting from the given u (the fixed
// entries keep their values): returns the minimizing u. J is the residual Jacobian at positions
// `at` (#V by 3). One precompute and one solve of a LinearizedSolver (linear/linearized_solver.h):
// to solve for several u or r0 with the same J and free set, keep the solver instead. `r0` may be
// empty (zero).
Eigen::VectorXd minimizeLeastSquares(const SparseMatrix& jacobian, const Eigen::VectorXd& r0,
                                     Eigen::VectorXd u, const std::vector<bool>& free,
                                     const Positions& at);

// E_lin of a displacement: ½ |J u|² with J the residual Jacobian at `rest` and u = (δ, δξ). δ is
// #V by 3; when J has edge-unknown columns, the edges with freeEdge[e] = false take deltaXi[e]
// (e.g. a linearized clamp; zero when deltaXi is empty) and the others are minimized over.
double linearizedEnergyOfDisplacement(const SparseMatrix& jacobian, const Positions& rest,
                                      const Positions& delta, const Eigen::VectorXd& deltaXi,
                                      const std::vector<bool>& freeEdge);

// The midedge unknowns minimizing E at fixed positions x: E is quadratic in ξ (S_T is affine in
// ξ, Ψ_ν quadratic in S_T), so one Gauss–Newton step from any ξ is exact. Edges with
// freeEdge[e] = false keep xi[e].
Eigen::VectorXd minimizeEdgeUnknowns(const std::vector<const EnergyTerm*>& terms,
                                     const Positions& x, const Eigen::VectorXd& xi,
                                     const std::vector<bool>& freeEdge);

// E at positions x with the midedge unknowns at their minimum for x (minimizeEdgeUnknowns from
// `xi`; edges with freeEdge[e] = false keep xi[e]): the energy of a configuration when ξ are
// not given. Terms without ξ: E(x).
double relaxedEnergy(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                     const Eigen::VectorXd& xi, const std::vector<bool>& freeEdge);

}  // namespace flexure::optimize
