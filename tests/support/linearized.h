// The linearized quantities of docs/energies.md for tests: C1's energy per covered area of a
// sampled quadratic, with midedge boundary ξ clamped and interior ξ minimized.
#pragma once

#include <memory>

#include "curvature/bending_energy.h"
#include "curvature/midedge_boundary.h"
#include "modeling/boundary_rings.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "optimize/energy_evaluation.h"

namespace flexure::testing {

struct LinearizedSetup {
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::unique_ptr<curvature::EnergyTerm> term;
  Eigen::VectorXd restXi;
  optimize::SparseMatrix jacobian;  // at rest

  LinearizedSetup(const modeling::Mesh& flat, const curvature::BendingOptions& options)
      : stencils(modeling::compileStencils(flat)),
        rest(modeling::precomputeRestState(stencils, flat.positions)),
        term(curvature::makeBendingEnergy(stencils, rest, options)),
        restXi(curvature::midedgeRestXi(stencils, rest, options.restCurvature)),
        jacobian(optimize::residualJacobian({term.get()}, rest.positions, restXi)) {}

  // The unknown vector (3 #V positions, then #E ξ when used) of the displacement z = p(x, y),
  // with midedge boundary ξ clamped to p (linearized) and the rest zero.
  Eigen::VectorXd displacement(const modeling::PolynomialSurface& p) const {
    modeling::Positions delta = modeling::Positions::Zero(rest.positions.rows(), 3);
    for (int v = 0; v < delta.rows(); ++v)
      delta(v, 2) = p.height(rest.positions(v, 0), rest.positions(v, 1));
    Eigen::VectorXd u = Eigen::VectorXd::Zero(jacobian.cols());
    u.head(delta.size()) = Eigen::Map<const Eigen::VectorXd>(delta.data(), delta.size());
    if (term->usesEdgeUnknowns()) {
      u.tail(stencils.edgeCount()) =
          curvature::linearizedClampedBoundaryXi(stencils, rest.positions, delta, p);
    }
    return u;
  }

  // C1: E_lin(p) / A_cov, interior ξ minimized.
  double energyPerArea(const modeling::PolynomialSurface& p) const {
    Eigen::VectorXd u = displacement(p);
    if (term->usesEdgeUnknowns()) {
      const std::vector<bool> boundary = curvature::boundaryEdges(stencils);
      std::vector<bool> free(u.size(), false);
      const int offset = static_cast<int>(u.size()) - stencils.edgeCount();
      for (int e = 0; e < stencils.edgeCount(); ++e) free[offset + e] = !boundary[e];
      u = optimize::minimizeLeastSquares(jacobian, Eigen::VectorXd(), u, free);
    }
    return optimize::linearizedEnergy(jacobian, u) / term->coveredArea();
  }
};

}  // namespace flexure::testing
