// Clamped midedge boundary normals: the ξ of each boundary edge prescribed from a boundary
// surface's normal at the edge midpoint (docs/energies.md, midedge "clamped").
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/polynomial_surface.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

// #E: ξ of each boundary edge clamped to the unit normal of z = p(x, y) at the (x, y) of the
// edge's midpoint in `x`; 0 on interior edges.
Eigen::VectorXd clampedBoundaryXi(const modeling::Stencils& stencils, const modeling::Positions& x,
                                  const modeling::PolynomialSurface& surface);

// The clamp of the linearized problem: d/dε clampedBoundaryXi(X̄ + ε δ, ε p) at ε = 0.
Eigen::VectorXd linearizedClampedBoundaryXi(const modeling::Stencils& stencils,
                                            const modeling::Positions& rest,
                                            const modeling::Positions& delta,
                                            const modeling::PolynomialSurface& surface);

// Per edge: true on the boundary.
std::vector<bool> boundaryEdges(const modeling::Stencils& stencils);

}  // namespace flexure::curvature
