#include "curvature/bending_energy.h"

#include <cmath>
#include <string>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::curvature {

double effectivePoisson(const BendingOptions& o) {
  const EnergyEntry& entry = energyEntry(o.discretization);
  if (entry.poissonRule == PoissonRule::MeanCurvatureOnly) {
    if (o.poisson && *o.poisson != 1.0) {
      throw InputError(entry.name +
                       " sees only the mean curvature (a ν = 1 model): it takes no "
                       "BendingOptions.poisson (got " +
                       std::to_string(*o.poisson) + ")");
    }
    return 1.0;
  }
  const double nu = o.poisson.value_or(kDefaultPoisson);
  if (!(nu >= -1.0 && nu <= 1.0)) {
    throw InputError("BendingOptions.poisson " + std::to_string(nu) +
                     " is outside [-1, 1], where Ψ_ν is not "
                     "a non-negative bending density");
  }
  return nu;
}

std::unique_ptr<EnergyTerm> makeBendingEnergy(const modeling::Stencils& s,
                                              const modeling::RestState& rest,
                                              const BendingOptions& o) {
  const double poisson = effectivePoisson(o);
  if (!(o.stiffness > 0.0) || !std::isfinite(o.stiffness)) {
    throw InputError("bending stiffness k_B must be positive (got " + std::to_string(o.stiffness) +
                     ")");
  }
  if (o.metric == CurvatureMetric::Current && o.restCurvature != RestCurvature::Flat) {
    throw InputError(
        "the current metric measures curvature against a flat rest only (a rest curvature "
        "would be measured in the rest mesh's frames)");
  }
  return energyEntry(o.discretization).make(s, rest, o, poisson);
}

}  // namespace flexure::curvature
