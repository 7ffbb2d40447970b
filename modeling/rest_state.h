// The rest (undeformed) metric every discretization shares, computed once from X̄ and then
// immutable. Per-energy rest data (rest angles θ̄, rest shape operators S̄, fit matrices) is built
// on top of it in curvature/. Notation follows docs/energies.md: a bar means "rest".
#pragma once

#include <Eigen/Core>

#include "modeling/mesh.h"
#include "modeling/stencils.h"

namespace flexure::modeling {

using FaceVectors = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using FaceEdgeNormals = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;

struct RestState {
  Positions positions;        // #V by 3: X̄
  Eigen::VectorXd faceAreas;  // #F: Ā_T
  FaceVectors faceNormals;    // #F by 3: unit n̄_T = (x̄1 − x̄0) × (x̄2 − x̄0) / (2 Ā_T)
  FaceVectors faceEdgeLengths;  // #F by 3: ℓ̄_i, edge i opposite vertex i
  // #F by 9: n̂_i for i = 0, 1, 2 (columns 3i..3i+2): the unit normal of edge i in the rest face's
  // plane, pointing out of T: n̂_i = (x̄_{i+2} − x̄_{i+1}) × n̄_T / ℓ̄_i.
  FaceEdgeNormals faceEdgeNormals;
  // #F by 3: cot of the rest angle at vertex i, (x̄_{i+1} − x̄_i)·(x̄_{i+2} − x̄_i) / (2 Ā_T).
  FaceVectors faceCotangents;
  Eigen::VectorXd edgeLengths;  // #E: ℓ̄_e
  // #V: mixed Voronoi areas (Meyer, Desbrun, Schröder, Barr 2003): in a non-obtuse triangle each
  // vertex takes its Voronoi region (1/8)(|x̄_v − x̄_a|² cot ∠b + |x̄_v − x̄_b|² cot ∠a); in an
  // obtuse one the obtuse vertex takes Ā_T / 2 and the others Ā_T / 4. They sum to the total area.
  Eigen::VectorXd vertexVoronoiAreas;
  Eigen::VectorXd vertexBarycentricAreas;  // #V: Σ Ā_T / 3 over the faces around v
};

// Throws InputError naming the face when a rest face has zero area (a Mesh that passed
// checkMesh() has none; rest positions from elsewhere might).
RestState precomputeRestState(const Stencils& stencils, const Positions& restPositions);

}  // namespace flexure::modeling
