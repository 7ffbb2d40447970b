#include "optimize/assembly/mesh_obstacles.h"

#include <algorithm>
#include <array>

#include "modeling/errors.h"

namespace flexure::optimize {

modeling::Positions MeshObstacle::positionsAt(double t) const {
  modeling::Positions x = mesh.positions;
  if (!moves()) return x;
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    x.row(v) = motion.position(mesh.positions.row(v).transpose(), t).transpose();
  return x;
}

modeling::Positions MeshObstacle::velocitiesAt(double t) const {
  modeling::Positions v = modeling::Positions::Zero(mesh.positions.rows(), 3);
  if (!moves()) return v;
  for (Eigen::Index k = 0; k < v.rows(); ++k)
    v.row(k) = motion.velocityAt(mesh.positions.row(k).transpose(), t).transpose();
  return v;
}

std::string meshObstacleName(const std::vector<MeshObstacle>& obstacles, int index) {
  const std::string& label = obstacles[static_cast<std::size_t>(index)].label;
  return label.empty() ? "mesh obstacle " + std::to_string(index) : label;
}

void validateMeshObstacles(const std::vector<MeshObstacle>& obstacles) {
  for (int k = 0; k < static_cast<int>(obstacles.size()); ++k) {
    const modeling::Mesh& mesh = obstacles[static_cast<std::size_t>(k)].mesh;
    const std::string name = "ProblemOptions.meshObstacles[" + std::to_string(k) + "] (" +
                             meshObstacleName(obstacles, k) + ")";
    if (mesh.vertexCount() == 0 || mesh.faceCount() == 0)
      throw InputError(name + ": the mesh has no triangles (" + std::to_string(mesh.vertexCount()) +
                       " vertices, " + std::to_string(mesh.faceCount()) + " triangles)");
    if (!mesh.positions.allFinite()) throw InputError(name + ": a vertex coordinate is not finite");
    if (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= mesh.vertexCount())
      throw InputError(name + ": a triangle names a vertex outside 0.." +
                       std::to_string(mesh.vertexCount() - 1));
  }
}

modeling::IndexPairs triangleEdges(const modeling::Triangles& faces) {
  std::vector<std::array<int, 2>> edges;
  edges.reserve(3 * static_cast<std::size_t>(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = faces(f, c), b = faces(f, (c + 1) % 3);
      if (a != b) edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  modeling::IndexPairs out(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t e = 0; e < edges.size(); ++e)
    out.row(static_cast<Eigen::Index>(e)) << edges[e][0], edges[e][1];
  return out;
}

}  // namespace flexure::optimize
