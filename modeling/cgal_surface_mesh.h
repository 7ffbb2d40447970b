// Internal to modeling/: a Mesh as CGAL's Surface_mesh and back, for the CGAL algorithms flexure
// calls (fair, hole filling). Vertex v of the Mesh is vertex index v of the Surface_mesh and face
// f face index f; CGAL appends what it adds, so input indices survive the round trip.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <string_view>

#include "modeling/mesh.h"

namespace flexure::modeling {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalSurfaceMesh = CGAL::Surface_mesh<CgalKernel::Point_3>;

// Throws InputError naming `caller` and the face CGAL rejects (a non-manifold face).
CgalSurfaceMesh toCgalSurfaceMesh(const Mesh& mesh, std::string_view caller);

// #V by 3, in vertex index order (the Surface_mesh must have no removed elements).
Positions cgalPositions(const CgalSurfaceMesh& sm);

// Positions and triangles in index order (triangular faces, no removed elements).
Mesh fromCgalSurfaceMesh(const CgalSurfaceMesh& sm);

}  // namespace flexure::modeling
