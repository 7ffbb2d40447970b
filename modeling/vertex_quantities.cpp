#include "modeling/vertex_quantities.h"

#include <string>

#include "modeling/errors.h"

#include <Eigen/Geometry>

namespace flexure::modeling {

const char* massLumpingName(MassLumping mass) {
  return mass == MassLumping::Barycentric ? "barycentric" : "voronoi";
}

MassLumping parseMassLumping(std::string_view name, std::string_view field) {
  if (name == "barycentric") return MassLumping::Barycentric;
  if (name == "voronoi") return MassLumping::Voronoi;
  throw InputError(std::string(field) + " " + std::string(name) +
                   ": expected barycentric or voronoi");
}

Eigen::VectorXd lumpedVertexMasses(const RestState& rest, MassLumping lumping, double density) {
  return density * (lumping == MassLumping::Barycentric ? rest.vertexBarycentricAreas
                                                        : rest.vertexVoronoiAreas);
}

Eigen::MatrixX3d vertexNormals(const Positions& positions, const Triangles& triangles) {
  Eigen::MatrixX3d normals = Eigen::MatrixX3d::Zero(positions.rows(), 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector3d x0 = positions.row(triangles(f, 0)), x1 = positions.row(triangles(f, 1)),
                          x2 = positions.row(triangles(f, 2));
    const Eigen::RowVector3d areaNormal = (x1 - x0).cross(x2 - x0).transpose();
    for (int k = 0; k < 3; ++k) normals.row(triangles(f, k)) += areaNormal;
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    const double length = normals.row(v).norm();
    if (length > 0.0) normals.row(v) /= length;
  }
  return normals;
}

}  // namespace flexure::modeling
