// The slides' test problem for tests: a flat mesh, two fixed rings lifted onto a quadratic, the
// interior free in height mode.
#pragma once

#include <memory>

#include "curvature/bending_energy.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"
#include "optimize/minimize.h"

namespace flexure::testing {

struct TestProblem {
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::unique_ptr<curvature::EnergyTerm> term;
  Eigen::VectorXd restXi;
  std::vector<bool> fixed;

  TestProblem(const modeling::Mesh& flat, const curvature::BendingOptions& options, int rings = 2)
      : stencils(modeling::compileStencils(flat)),
        rest(modeling::precomputeRestState(stencils, flat.positions)),
        term(curvature::makeBendingEnergy(stencils, rest, options)),
        restXi(term->usesEdgeUnknowns()
                   ? curvature::midedgeRestXi(stencils, rest, options.restCurvature)
                   : Eigen::VectorXd()),
        fixed(optimize::fixedRings(stencils, rings)) {}

  optimize::MinimizeResult solve(
      const modeling::PolynomialSurface& p, bool linearized,
      optimize::BoundaryNormals normals = optimize::BoundaryNormals::Clamped,
      optimize::MinimizeOptions options = {}) const {
    options.linearized = linearized;
    const optimize::BoundaryConditions bc =
        optimize::surfaceBoundary(stencils, rest.positions, restXi, fixed, p, normals, linearized);
    return optimize::minimize({term.get()}, bc, rest.positions, restXi, options);
  }

  // C2: max_interior |z − p| / max |p| of the minimizer.
  double c2(const modeling::PolynomialSurface& p, bool linearized = true,
            optimize::BoundaryNormals normals = optimize::BoundaryNormals::Clamped) const {
    return optimize::reproductionError(rest.positions, solve(p, linearized, normals).positions,
                                       fixed, p);
  }
};

}  // namespace flexure::testing
