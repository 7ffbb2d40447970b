// Per-vertex quantities of a mesh that the solvers, the dynamics and the renderer share
// (geometry-central's naming: <element><Quantity>s).
#pragma once

#include <Eigen/Core>
#include <string_view>

#include "modeling/mesh.h"
#include "modeling/rest_state.h"

namespace flexure::modeling {

// Which rest area a vertex's lumped mass stands for: barycentric (Σ incident Ā_T / 3) or the
// mixed Voronoi area (rest_state.h).
enum class MassLumping { Barycentric, Voronoi };
const char* massLumpingName(MassLumping mass);  // "barycentric" | "voronoi"
// The lumping named `name`; InputError naming `field` (the option that gave it) otherwise.
MassLumping parseMassLumping(std::string_view name, std::string_view field);

// #V: m_v = ρh × the vertex's rest area, `density` = ρh (mass per unit rest area).
Eigen::VectorXd lumpedVertexMasses(const RestState& rest, MassLumping lumping, double density);

// #V by 3: the unit area-weighted vertex normals of `positions` (#V by 3) over `triangles` (#F by
// 3): n_v = Σ_T (x_1 − x_0) × (x_2 − x_0) over the faces T around v, normalized; zero where that
// sum is zero.
Eigen::MatrixX3d vertexNormals(const Positions& positions, const Triangles& triangles);

}  // namespace flexure::modeling
