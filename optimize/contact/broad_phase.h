// The broad phase of self-contact: the pairs of mesh primitives (vertex–face, edge–edge) that can
// come within a given distance during a linear motion, found by intersecting axis-aligned boxes
// in a uniform grid (Teschner et al. 2003, "Optimized spatial hashing for collision detection of
// deformable objects"): O(n) for boxes of similar size. The exact distances and impact times of
// the candidates are primitive_distance.h's and continuous_collision.h's.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/stencils.h"

namespace flexure::optimize {

struct CandidatePairs {
  std::vector<std::array<int, 2>> vertexFace;  // (vertex, face), sorted
  std::vector<std::array<int, 2>> edgeEdge;    // (edge i, edge j), i < j, sorted
};

// Each primitive's box bounds it over the motion from x to x + dx (the box of its vertices at
// both ends; dx empty: static) and is inflated by `inflation` (≥ 0) on every side; a vertex's box
// is its point's. The candidates are the pairs whose boxes overlap, so every pair that comes
// within distance `inflation` during the motion is among them (boxes overlap up to 2 × inflation
// apart per axis). Pairs sharing a vertex index (a vertex of its own face, edges with a common
// end) are left out. A box with an undefined (NaN) coordinate overlaps every box.
// x: #V by 3; dx: #V by 3 or empty; faces: #F by 3; edges: #E by 2 (vertex indices).
// Throws InputError for a dx of another size, a negative inflation, or an index out of range.
CandidatePairs contactCandidates(const Eigen::Ref<const modeling::Positions>& x,
                                 const Eigen::Ref<const modeling::Positions>& dx,
                                 const modeling::Triangles& faces,
                                 const modeling::IndexPairs& edges, double inflation);

// The same candidates restricted to the pairs with a vertex in `among` (#V flags): a primitive
// touching one of them on either side. O(n) for the boxes, and queries for the primitives that
// touch `among` only, so a motion in which few vertices move far costs little beyond the boxes.
CandidatePairs contactCandidatesAmong(const Eigen::Ref<const modeling::Positions>& x,
                                      const Eigen::Ref<const modeling::Positions>& dx,
                                      const modeling::Triangles& faces,
                                      const modeling::IndexPairs& edges, double inflation,
                                      const std::vector<bool>& among);

}  // namespace flexure::optimize
