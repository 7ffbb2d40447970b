// The triangle mesh every flexure library sees: plain Eigen arrays.
//
// OpenMesh (the half-edge core) and CGAL stay inside modeling/; downstream code receives a Mesh,
// the compiled Stencils and the RestState. A Mesh that came out of readMesh(), a generator or
// requireValidMesh() is a manifold, consistently oriented triangle mesh with finite coordinates,
// no zero-area or duplicate faces and no unreferenced vertices (see mesh_check.h).
#pragma once

#include <Eigen/Core>

namespace flexure::modeling {

// #V by 3, row-major: one vertex (x, y, z) per row, so that row v is Ceres' parameter block v.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
// #F by 3, row-major: vertex indices of each triangle, counter-clockwise seen from the side the
// normal (x1 - x0) x (x2 - x0) points to.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct Mesh {
  Positions positions;  // #V by 3
  Triangles triangles;  // #F by 3

  int vertexCount() const { return static_cast<int>(positions.rows()); }
  int faceCount() const { return static_cast<int>(triangles.rows()); }
};

}  // namespace flexure::modeling
