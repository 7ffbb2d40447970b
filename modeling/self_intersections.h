// Exact intersection checks between the triangles of meshes (CGAL's exact predicates on the
// Exact_predicates_inexact_constructions kernel, do_intersect of two Triangle_3, after a
// box_intersection_d broad phase on the faces' bounding boxes).
#pragma once

#include <array>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

// The pairs (f, g), f < g, of faces of `mesh` that intersect, sorted, leaving out every pair that
// shares a vertex position: faces adjacent in the mesh share a vertex, and the lips of a cut have
// distinct vertices at one position, so such pairs touch by construction. (A pair sharing a
// position that also crosses elsewhere is therefore not reported either.) The mesh may be a
// triangle soup: no manifold or orientation condition.
std::vector<std::array<int, 2>> intersectingFacePairs(const Mesh& mesh);

// The pairs (face of a, face of b) that intersect, sorted (exact; touching counts).
std::vector<std::array<int, 2>> intersectingFacePairs(const Mesh& a, const Mesh& b);

}  // namespace flexure::modeling
