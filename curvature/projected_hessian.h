// The projected Newton Hessian (Teran, Sifakis, Irving & Fedkiw 2005, "Robust quasistatic finite
// elements and flesh simulation"): each element Hessian replaced by its nearest positive
// semidefinite matrix before assembly, so that their sum is positive semidefinite wherever the
// exact Hessian is indefinite (a buckling sheet, a fairing far from its minimizer).
#pragma once

#include <Eigen/Core>

namespace flexure::curvature {

// The nearest positive semidefinite matrix to a symmetric h (n by n) in the Frobenius norm,
// V max(Λ, 0) Vᵀ for h = V Λ Vᵀ (Higham 1988); h itself, bit for bit, when no eigenvalue is
// negative.
Eigen::MatrixXd projectedToPositiveSemidefinite(const Eigen::MatrixXd& h);

}  // namespace flexure::curvature
