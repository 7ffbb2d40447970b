#include "modeling/mesh_info.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>

#include "modeling/boundary_rings.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::modeling {
MeshInfo describeMesh(const Mesh& mesh) {
  const Stencils s = compileStencils(mesh);
  const RestState rest = precomputeRestState(s, mesh.positions);
  MeshInfo info;
  info.vertices = s.vertexCount();
  info.faces = s.faceCount();
  info.edges = s.edgeCount();
  const std::vector<int> component = vertexComponents(s);
  info.components =
      component.empty() ? 0 : *std::max_element(component.begin(), component.end()) + 1;
  info.eulerCharacteristic = info.vertices - info.edges + info.faces;
  for (const auto& loop : boundaryLoops(s))
    info.boundaryLoopLengths.push_back(static_cast<int>(loop.size()));
  std::sort(info.boundaryLoopLengths.begin(), info.boundaryLoopLengths.end(), std::greater<>());
  for (int v = 0; v < s.vertexCount(); ++v)
    ++(s.vertexOnBoundary[v] ? info.boundaryValences : info.interiorValences)[s.valence(v)];
  info.minEdgeLength = rest.edgeLengths.minCoeff();
  info.meanEdgeLength = rest.edgeLengths.mean();
  info.maxEdgeLength = rest.edgeLengths.maxCoeff();
  info.area = rest.faceAreas.sum();
  info.boxMin = mesh.positions.colwise().minCoeff().transpose();
  info.boxMax = mesh.positions.colwise().maxCoeff().transpose();
  return info;
}

double smallestAngleDegrees(const Positions& x, int a, int b, int c) {
  constexpr double kDegrees = 180.0 / 3.14159265358979323846;
  const int corner[3] = {a, b, c};
  double smallest = 180.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d p = x.row(corner[k]);
    const Eigen::Vector3d u = Eigen::Vector3d(x.row(corner[(k + 1) % 3])) - p;
    const Eigen::Vector3d w = Eigen::Vector3d(x.row(corner[(k + 2) % 3])) - p;
    smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * kDegrees);
  }
  return smallest;
}

}  // namespace flexure::modeling
