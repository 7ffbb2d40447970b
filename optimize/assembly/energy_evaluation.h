// Energies, gradients and residual Jacobians of a set of terms through Ceres
// (linear/least_squares.h minimizes their linearizations). Unknowns are ordered: vertex positions
// row by row (3 #V values), then the midedge unknowns ξ (#E values) when a term uses them.
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
// The stacked residuals r and their Jacobian J at (x, ξ).
struct Linearization {
  Eigen::VectorXd residuals;
  SparseMatrix jacobian;
};
Linearization linearize(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                        const Eigen::VectorXd& xi,
                        curvature::Derivatives derivatives = curvature::Derivatives::All);
SparseMatrix residualJacobian(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi,
                              curvature::Derivatives derivatives = curvature::Derivatives::All);

// ½ |J u|².
double linearizedEnergy(const SparseMatrix& jacobian, const Eigen::VectorXd& u);

}  // namespace flexure::optimize
