// Per-vertex mean curvature of a mesh as it stands, for curvature maps (the render command's
// curvature style), from the cotan discretization's kernel (cotan_mean_curvature.h):
//
//   H_v = ½ K_v · n_v / Ā_v,
//
// K_v the cotangent Laplacian of the positions at v (≈ 2 H n Ā_v), n_v the area-weighted vertex
// normal of the counter-clockwise ring, Ā_v the mixed Voronoi area (rest_state.h) of the mesh
// itself. Sign: H > 0 where the surface bends towards its normal — the faces' normals follow
// their counter-clockwise order (right-hand rule), so a bowl z = x² + y² with faces counter-
// clockwise seen from above (normals +z) has H > 0 (H ≈ 2 at its apex: ½ (κ₁ + κ₂) with
// κ₁ = κ₂ = 2), and a saddle z = x² − y² has H ≈ 0 at its centre and both signs elsewhere.
// Boundary vertices have no closed ring: their H is 0. The cotan registry entry's
// meanCurvatureField (energy_registry.h): curvature maps reach it through the registry.
#pragma once

#include <vector>

#include "modeling/mesh.h"

namespace flexure::curvature {

// H_v for every vertex (#V). Throws InputError for a mesh that fails compileStencils or has a
// zero-area face.
std::vector<double> cotanVertexMeanCurvature(const modeling::Mesh& mesh);

}  // namespace flexure::curvature
