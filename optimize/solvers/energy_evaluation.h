// Energies, gradients and residual Jacobians of a set of terms through Ceres, and the linearized
// energies of docs/energies.md. Unknowns are ordered: vertex positions row by row (3 #V values),
// then the midedge unknowns ξ (#E values) when a term uses them.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "curvature/energy_term.h"

namespace flexure::optimize {

using curvature::EnergyTerm;
using modeling::Positions;
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

struct EnergyGradient {
  double energy = 0.0;
  Eigen::VectorXd gradient;  // 3 #V (+ #E): ∂E/∂x row by row, then ∂E/∂ξ
};

// Whether any term reads midedge unknowns.
bool usesEdgeUnknowns(const std::vector<const EnergyTerm*>& terms);

// E and ∇E at (x, ξ), by Ceres autodiff on the terms' residuals.
EnergyGradient energyGradient(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi);

// The Jacobian J of the stacked residuals r at (x, ξ): E = ½ |r|², so at rest (r = 0) the
// second-order expansion of E is E_lin(δ) = ½ |J δ|² (= |J' δ|² for the unscaled residuals r/√2
// of docs/energies.md). Columns follow the unknown order above.
// With Derivatives::HeightOnly only the z and ξ columns are filled (height_only_cost.h).
SparseMatrix residualJacobian(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi,
                              curvature::Derivatives derivatives = curvature::Derivatives::All);

// min over the unknowns marked free of ½ |J u + r0|², starting from the given u (the fixed
// entries keep their values): returns the minimizing u. J is the residual Jacobian at positions
// `at` (#V by 3). A quadratic in the free unknowns, so one sparse Cholesky solve with CHOLMOD,
// which factors J_freeᵀ J_free + β I from J_freeᵀ without forming the normal matrix (the ridge
// β, 1e-13 of its mean diagonal, keeps it defined where Ψ_ν ignores some ξ, e.g. ν = 1), in the
// geometric nested-dissection order of the unknowns (elimination_order.h). `r0` may be empty
// (zero).
Eigen::VectorXd minimizeLeastSquares(const SparseMatrix& jacobian, const Eigen::VectorXd& r0,
                                     Eigen::VectorXd u, const std::vector<bool>& free,
                                     const Positions& at);

// ½ |J u|².
double linearizedEnergy(const SparseMatrix& jacobian, const Eigen::VectorXd& u);

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
