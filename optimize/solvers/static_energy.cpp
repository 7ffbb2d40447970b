#include "optimize/solvers/static_energy.h"

#include <cmath>
#include <limits>

#include "modeling/errors.h"

namespace flexure::optimize {

StaticEnergy::StaticEnergy(const HessianAssembly& assembly, Configuration fixedPart,
                           const std::vector<const EnergyTerm*>& terms,
                           const Positions& externalForce, const ObstacleBarrier& obstacles,
                           HessianProjection projection)
    : Objective(assembly, std::move(fixedPart)),
      terms_(terms),
      externalForce_(externalForce),
      obstacles_(obstacles),
      projection_(projection) {}

double StaticEnergy::loadEnergy(const Positions& x) const {
  return externalForce_.rows() > 0 ? externalForce_.cwiseProduct(x).sum() : 0.0;
}

HessianEvaluation StaticEnergy::evaluateAt(const Configuration& at,
                                           curvature::SecondDerivatives kind,
                                           const Eigen::VectorXd* fixedMove) const {
  // First derivatives alone need no projection.
  const HessianProjection projection =
      kind == curvature::SecondDerivatives::None ? HessianProjection::Exact : projection_;
  HessianEvaluation e = assembly_.evaluate(at.positions, at.xi, projection, fixedMove, kind);
  if (externalForce_.rows() > 0) {  // − fᵀx and its gradient − f
    e.energy -= loadEnergy(at.positions);
    const std::vector<int>& unknowns = assembly_.freeUnknowns();
    for (size_t k = 0; k < unknowns.size(); ++k)
      if (unknowns[k] < at.positions.size())
        e.gradient[static_cast<Eigen::Index>(k)] -= externalForce_.data()[unknowns[k]];
  }
  obstacles_.add(assembly_, at.positions, e,
                 kind != curvature::SecondDerivatives::Exact ||
                     projection == HessianProjection::PositiveSemidefinite);
  return e;
}

HessianEvaluation StaticEnergy::evaluate(const Eigen::VectorXd& y,
                                         curvature::SecondDerivatives kind) {
  return evaluateAt(configuration(y), kind);
}

double StaticEnergy::lineSearchValue(const Eigen::VectorXd& y) {
  const Configuration at = configuration(y);
  double sum = 0.0;
  try {
    for (const EnergyTerm* term : terms_) sum += term->energy(at.positions, at.xi);
  } catch (const NumericalError&) {
    return std::numeric_limits<double>::infinity();
  }
  sum -= loadEnergy(at.positions);
  sum += obstacles_.energy(at.positions);  // +∞ inside an obstacle
  return std::isfinite(sum) ? sum : std::numeric_limits<double>::infinity();
}

Eigen::VectorXd StaticEnergy::vertexStepBounds(const Eigen::VectorXd& y,
                                               const Eigen::VectorXd& delta) {
  if (obstacles_.empty()) return Eigen::VectorXd();
  return obstacles_.vertexStepBounds(configuration(y).positions, displacement(delta));
}

double StaticEnergy::roundoff(const Eigen::VectorXd&, double value) const {
  return 1e-14 * std::abs(value);
}

}  // namespace flexure::optimize
