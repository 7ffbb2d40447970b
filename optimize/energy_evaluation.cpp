#include "optimize/energy_evaluation.h"

#include <ceres/crs_matrix.h>
#include <ceres/problem.h>

#include <Eigen/CholmodSupport>
#include <algorithm>

#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

// A Ceres problem over copies of x and ξ holding every term's residuals.
struct AssembledProblem {
  Positions x;
  Eigen::VectorXd xi;
  ceres::Problem problem;

  AssembledProblem(const std::vector<const EnergyTerm*>& terms, const Positions& positions,
                   const Eigen::VectorXd& edgeUnknowns)
      : x(positions), xi(edgeUnknowns) {
    for (int v = 0; v < x.rows(); ++v) problem.AddParameterBlock(x.data() + 3 * v, 3);
    if (usesEdgeUnknowns(terms)) {
      for (int e = 0; e < xi.size(); ++e) problem.AddParameterBlock(xi.data() + e, 1);
    }
    for (const EnergyTerm* term : terms) term->addResidualBlocks(problem, x.data(), xi.data());
  }

  // No explicit parameter_blocks: Ceres then orders the unknowns as the blocks were added, which
  // is the unknown order above, and skips a costly lookup per block on every call.
  ceres::Problem::EvaluateOptions options() const {
    ceres::Problem::EvaluateOptions o;
    o.apply_loss_function = false;
    o.num_threads = 2;
    return o;
  }
};

}  // namespace

bool usesEdgeUnknowns(const std::vector<const EnergyTerm*>& terms) {
  return std::any_of(terms.begin(), terms.end(),
                     [](const EnergyTerm* t) { return t->usesEdgeUnknowns(); });
}

EnergyGradient energyGradient(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi) {
  AssembledProblem assembled(terms, x, xi);
  EnergyGradient out;
  std::vector<double> gradient;
  if (!assembled.problem.Evaluate(assembled.options(), &out.energy, nullptr, &gradient, nullptr)) {
    throw NumericalError(
        "the energy or its gradient is undefined at this configuration (a "
        "degenerate element)");
  }
  out.gradient =
      Eigen::Map<Eigen::VectorXd>(gradient.data(), static_cast<Eigen::Index>(gradient.size()));
  return out;
}

SparseMatrix residualJacobian(const std::vector<const EnergyTerm*>& terms, const Positions& x,
                              const Eigen::VectorXd& xi) {
  AssembledProblem assembled(terms, x, xi);
  ceres::CRSMatrix crs;
  if (!assembled.problem.Evaluate(assembled.options(), nullptr, nullptr, nullptr, &crs)) {
    throw NumericalError(
        "the residual Jacobian is undefined at this configuration (a "
        "degenerate element)");
  }
  return Eigen::Map<const SparseMatrix>(crs.num_rows, crs.num_cols,
                                        static_cast<Eigen::Index>(crs.values.size()),
                                        crs.rows.data(), crs.cols.data(), crs.values.data());
}

Eigen::VectorXd minimizeLeastSquares(const SparseMatrix& jacobian, const Eigen::VectorXd& r0,
                                     Eigen::VectorXd u, const std::vector<bool>& free) {
  std::vector<int> freeColumns;
  for (int c = 0; c < static_cast<int>(free.size()); ++c)
    if (free[c]) freeColumns.push_back(c);
  if (freeColumns.empty()) return u;
  Eigen::VectorXd fixedPart = u;
  for (int c : freeColumns) fixedPart[c] = 0.0;
  Eigen::VectorXd rhs = jacobian * fixedPart;
  if (r0.size() > 0) rhs += r0;

  // J_free: the free columns, renumbered.
  std::vector<int> newIndex(free.size(), -1);
  for (size_t k = 0; k < freeColumns.size(); ++k) newIndex[freeColumns[k]] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> entries;
  for (int row = 0; row < jacobian.outerSize(); ++row)
    for (SparseMatrix::InnerIterator it(jacobian, row); it; ++it)
      if (newIndex[it.col()] >= 0) entries.emplace_back(row, newIndex[it.col()], it.value());
  Eigen::SparseMatrix<double> jf(jacobian.rows(), static_cast<Eigen::Index>(freeColumns.size()));
  jf.setFromTriplets(entries.begin(), entries.end());

  Eigen::SparseMatrix<double> normal = jf.transpose() * jf;
  const double ridge = 1e-13 * normal.diagonal().mean();
  for (int k = 0; k < normal.cols(); ++k) normal.coeffRef(k, k) += ridge;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> solver(normal);
  const Eigen::VectorXd step = solver.solve(-(jf.transpose() * rhs));
  if (solver.info() != Eigen::Success || !step.allFinite()) {
    throw NumericalError("the least-squares solve for the free unknowns failed (singular system)");
  }
  for (size_t k = 0; k < freeColumns.size(); ++k)
    u[freeColumns[k]] = step[static_cast<Eigen::Index>(k)];
  return u;
}

double linearizedEnergy(const SparseMatrix& jacobian, const Eigen::VectorXd& u) {
  return 0.5 * (jacobian * u).squaredNorm();
}

double linearizedEnergyOfDisplacement(const SparseMatrix& jacobian, const Positions& delta,
                                      const Eigen::VectorXd& deltaXi,
                                      const std::vector<bool>& freeEdge) {
  const int positionCount = static_cast<int>(delta.size());
  const int edgeCount = static_cast<int>(jacobian.cols()) - positionCount;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(jacobian.cols());
  u.head(positionCount) = Eigen::Map<const Eigen::VectorXd>(delta.data(), positionCount);
  if (edgeCount > 0) {
    if (deltaXi.size() > 0) u.tail(edgeCount) = deltaXi;
    std::vector<bool> free(u.size(), false);
    for (int e = 0; e < edgeCount; ++e) free[positionCount + e] = freeEdge[e];
    u = minimizeLeastSquares(jacobian, Eigen::VectorXd(), u, free);
  }
  return linearizedEnergy(jacobian, u);
}

Eigen::VectorXd minimizeEdgeUnknowns(const std::vector<const EnergyTerm*>& terms,
                                     const Positions& x, const Eigen::VectorXd& xi,
                                     const std::vector<bool>& freeEdge) {
  // Residuals are affine in ξ: r(ξ) = r(ξ0) + J_ξ (ξ − ξ0). Solve for the free part of ξ in the
  // unknown vector (positions fixed).
  const SparseMatrix jacobian = residualJacobian(terms, x, xi);
  AssembledProblem assembled(terms, x, xi);
  std::vector<double> residuals;
  assembled.problem.Evaluate(assembled.options(), nullptr, &residuals, nullptr, nullptr);
  const int positionCount = static_cast<int>(3 * x.rows());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(jacobian.cols());
  std::vector<bool> free(jacobian.cols(), false);
  for (int e = 0; e < xi.size(); ++e) free[positionCount + e] = freeEdge[e];
  const Eigen::VectorXd r0 =
      Eigen::Map<Eigen::VectorXd>(residuals.data(), static_cast<Eigen::Index>(residuals.size()));
  const Eigen::VectorXd step = minimizeLeastSquares(jacobian, r0, u, free);
  return xi + step.tail(xi.size());
}

}  // namespace flexure::optimize
