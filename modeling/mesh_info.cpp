#include "modeling/mesh_info.h"

#include <algorithm>
#include <functional>

#include "modeling/boundary_rings.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::modeling {
namespace {

int countComponents(const Stencils& s) {
  std::vector<int> component(s.vertexCount(), -1);
  std::vector<int> stack;
  int count = 0;
  for (int seed = 0; seed < s.vertexCount(); ++seed) {
    if (component[seed] >= 0) continue;
    component[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int r = s.oneRingOffsets[v]; r < s.oneRingOffsets[v + 1]; ++r) {
        const int w = s.oneRingVertices[r];
        if (component[w] < 0) {
          component[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return count;
}

}  // namespace

MeshInfo describeMesh(const Mesh& mesh) {
  const Stencils s = compileStencils(mesh);
  const RestState rest = precomputeRestState(s, mesh.positions);
  MeshInfo info;
  info.vertices = s.vertexCount();
  info.faces = s.faceCount();
  info.edges = s.edgeCount();
  info.components = countComponents(s);
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

}  // namespace flexure::modeling
