// The slides' test problem for tests: optimize::FlatPlateProblem (a flat mesh, one energy, two
// fixed rings) with its solves and C2 through the library's helpers.
#pragma once

#include "optimize/studies/convergence_study.h"

namespace flexure::testing {

struct TestProblem : optimize::FlatPlateProblem {
  std::vector<bool> fixed;  // = boundary.fixedVertex

  TestProblem(const modeling::Mesh& flat, const curvature::BendingOptions& options, int rings = 2)
      : FlatPlateProblem(flat, options, rings), fixed(boundary.fixedVertex) {}

  optimize::MinimizeResult solve(
      const modeling::PolynomialSurface& p, bool linearized,
      optimize::BoundaryNormals normals = optimize::BoundaryNormals::Clamped,
      optimize::MinimizeOptions options = {}) const {
    return optimize::solveWithSurfaceBoundary(*this, p, normals, linearized, options);
  }

  // C2's measure, max_interior |z − p| / max |p|, of the (linearized or nonlinear) minimizer.
  double c2(const modeling::PolynomialSurface& p, bool linearized = true,
            optimize::BoundaryNormals normals = optimize::BoundaryNormals::Clamped) const {
    return optimize::reproductionError(rest.positions, solve(p, linearized, normals).positions,
                                       fixed, p);
  }
};

}  // namespace flexure::testing
