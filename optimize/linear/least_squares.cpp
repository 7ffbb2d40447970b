#include "optimize/linear/least_squares.h"

#include <algorithm>

#include "optimize/linear/linearized_solver.h"

namespace flexure::optimize {

Eigen::VectorXd minimizeLeastSquares(const SparseMatrix& jacobian, const Eigen::VectorXd& r0,
                                     Eigen::VectorXd u, const std::vector<bool>& free,
                                     const Positions& at) {
  if (std::find(free.begin(), free.end(), true) == free.end()) return u;
  return LinearizedSolver(jacobian, free, at).solve(std::move(u), r0);
}

double linearizedEnergyOfDisplacement(const SparseMatrix& jacobian, const Positions& rest,
                                      const Positions& delta, const Eigen::VectorXd& deltaXi,
                                      const std::vector<bool>& freeEdge) {
  const int positionCount = static_cast<int>(delta.size());
  const int edgeCount = static_cast<int>(jacobian.cols()) - positionCount;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(jacobian.cols());
  u.head(positionCount) = Eigen::Map<const Eigen::VectorXd>(delta.data(), positionCount);
  if (edgeCount > 0) {
    if (deltaXi.size() > 0) u.tail(edgeCount) = deltaXi;
    std::vector<bool> free(u.size(), false);
    for (int e = 0; e < edgeCount; ++e) free[positionCount + e] = freeEdge[e];
    u = minimizeLeastSquares(jacobian, Eigen::VectorXd(), u, free, rest);
  }
  return linearizedEnergy(jacobian, u);
}

Eigen::VectorXd minimizeEdgeUnknowns(const std::vector<const EnergyTerm*>& terms,
                                     const Positions& x, const Eigen::VectorXd& xi,
                                     const std::vector<bool>& freeEdge) {
  // Residuals are affine in ξ: r(ξ) = r(ξ0) + J_ξ (ξ − ξ0). Solve for the free part of ξ in the
  // unknown vector (positions fixed).
  // Positions fixed: only the ξ columns matter, which the height-mode Jacobian holds.
  const Linearization at = linearize(terms, x, xi, curvature::Derivatives::HeightOnly);
  const int positionCount = static_cast<int>(3 * x.rows());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(at.jacobian.cols());
  std::vector<bool> free(at.jacobian.cols(), false);
  for (int e = 0; e < xi.size(); ++e) free[positionCount + e] = freeEdge[e];
  const Eigen::VectorXd step = minimizeLeastSquares(at.jacobian, at.residuals, u, free, x);
  return xi + step.tail(xi.size());
}

double relaxedEnergy(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                     const Eigen::VectorXd& xi, const std::vector<bool>& freeEdge) {
  const Eigen::VectorXd relaxed =
      usesEdgeUnknowns(terms) ? minimizeEdgeUnknowns(terms, x, xi, freeEdge) : xi;
  double energy = 0.0;
  for (const EnergyTerm* term : terms) energy += term->energy(x, relaxed);
  return energy;
}

}  // namespace flexure::optimize
