#include "curvature/projected_hessian.h"

#include <Eigen/Eigenvalues>

namespace flexure::curvature {

Eigen::MatrixXd projectedToPositiveSemidefinite(const Eigen::MatrixXd& h) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(h);
  if (eigen.eigenvalues().size() == 0 || eigen.eigenvalues().minCoeff() >= 0.0) return h;
  const Eigen::VectorXd clamped = eigen.eigenvalues().cwiseMax(0.0);
  return eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace flexure::curvature
