// Boundary loops and vertex rings: which vertices a fixed boundary condition holds.
//
// Ring 0 is the boundary vertices; ring k is the neighbours of ring k−1 not in an earlier ring.
// Fixing rings 0 and 1 fixes positions and normals along the boundary ("clamped").
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "modeling/stencils.h"

namespace flexure::modeling {

// #V: the ring of every vertex around the `seeds` (ring 0; ring k = the neighbours of ring k − 1
// not in an earlier ring), up to ring maxRing; −1 beyond it or where no seed reaches.
Eigen::VectorXi ringDistances(const Stencils& stencils, const std::vector<bool>& seeds,
                              int maxRing = std::numeric_limits<int>::max());

// #V: the ring of every vertex around the boundary; −1 for a vertex no boundary reaches (a closed
// component).
Eigen::VectorXi vertexRings(const Stencils& stencils);

// The vertices with 0 ≤ ring < ringCount, in increasing index order.
std::vector<int> verticesInRings(const Eigen::VectorXi& rings, int ringCount);

// Each boundary loop as its vertices in order, following the faces' orientation (a
// counter-clockwise mesh of a disk walks its boundary counter-clockwise). Loops start at their
// lowest vertex index and are sorted by it.
std::vector<std::vector<int>> boundaryLoops(const Stencils& stencils);

}  // namespace flexure::modeling
