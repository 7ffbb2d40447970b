// The linear thin plate: the cotangent bi-Laplacian L M⁻¹ L (M the mixed Voronoi areas) solved for
// the free vertices' heights with the fixed ones held — one sparse Cholesky (CHOLMOD)
// factorization and solve. It is the floor every solve of flexure is measured against: no
// discretization of a bending energy can be minimized with less than one such solve.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/energy_evaluation.h"

namespace flexure::optimize {

// #V by #V: (L z)_v = ½ Σ_j (cot α_vj + cot β_vj)(z_j − z_v) on the rest mesh (negative
// semidefinite; boundary edges take their one cotangent).
SparseMatrix cotanLaplacian(const modeling::Stencils& stencils, const modeling::RestState& rest);

// The normal equations of the free vertices: matrix · z_free = rhs, with B = Lᵀ M⁻¹ L split into
// free and fixed columns (the fixed values moved to the right-hand side).
struct BiharmonicSystem {
  Eigen::SparseMatrix<double> matrix;  // #free by #free, symmetric positive definite
  Eigen::VectorXd rhs;                 // #free
  std::vector<int> freeIndex;          // #V: the row of each free vertex, −1 for fixed ones
};

BiharmonicSystem assembleBiharmonic(const modeling::Stencils& stencils,
                                    const modeling::RestState& rest,
                                    const std::vector<bool>& fixedVertex,
                                    const Eigen::VectorXd& values);

// #V: the values z (one coordinate, e.g. heights) minimizing Σ_v (L z)_v² / Ā_v over the free
// vertices, the fixed ones keeping their entries of `values`.
Eigen::VectorXd solveBiharmonic(const modeling::Stencils& stencils, const modeling::RestState& rest,
                                const std::vector<bool>& fixedVertex,
                                const Eigen::VectorXd& values);

}  // namespace flexure::optimize
