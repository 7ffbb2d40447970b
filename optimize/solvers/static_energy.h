// The static objective (objective.h) that minimize's Newton solver minimizes:
//
//   f(x, ξ) = Σ_terms E(x, ξ) − fᵀx + B(x)
//
// with f the external load (#V by 3, empty: none) and B the obstacles' barrier (obstacles.h,
// +∞ inside one). Fairing minimizes the same objective with its own terms.
#pragma once

#include <vector>

#include "optimize/assembly/obstacles.h"
#include "optimize/solvers/objective.h"

namespace flexure::optimize {

class StaticEnergy : public Objective {
 public:
  // `projection`: the element Hessians as they are, or projected to positive semidefinite.
  // Every reference outlives the objective.
  StaticEnergy(const HessianAssembly& assembly, Configuration fixedPart,
               const std::vector<const EnergyTerm*>& terms, const Positions& externalForce,
               const ObstacleBarrier& obstacles, HessianProjection projection);

  // At a configuration; `fixedMove` as HessianAssembly::evaluate's.
  HessianEvaluation evaluateAt(const Configuration& at, curvature::SecondDerivatives kind,
                               const Eigen::VectorXd* fixedMove = nullptr) const;

  HessianEvaluation evaluate(const Eigen::VectorXd& y, curvature::SecondDerivatives kind) override;
  double lineSearchValue(const Eigen::VectorXd& y) override;
  Eigen::VectorXd vertexStepBounds(const Eigen::VectorXd& y, const Eigen::VectorXd& delta) override;
  double roundoff(const Eigen::VectorXd& y, double value) const override;

  // fᵀx of the external load (0 without one).
  double loadEnergy(const Positions& x) const;

 private:
  const std::vector<const EnergyTerm*>& terms_;
  const Positions& externalForce_;
  const ObstacleBarrier& obstacles_;
  const HessianProjection projection_;
};

}  // namespace flexure::optimize
