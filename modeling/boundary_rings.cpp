#include "modeling/boundary_rings.h"

#include <algorithm>

namespace flexure::modeling {

Eigen::VectorXi ringDistances(const Stencils& s, const std::vector<bool>& seeds, int maxRing) {
  Eigen::VectorXi ring = Eigen::VectorXi::Constant(s.vertexCount(), -1);
  std::vector<int> current, next;
  for (int v = 0; v < s.vertexCount(); ++v) {
    if (seeds[v]) {
      ring[v] = 0;
      current.push_back(v);
    }
  }
  for (int k = 1; k <= maxRing && !current.empty(); ++k) {
    next.clear();
    for (int v : current) {
      for (int r = s.oneRingOffsets[v]; r < s.oneRingOffsets[v + 1]; ++r) {
        const int w = s.oneRingVertices[r];
        if (ring[w] < 0) {
          ring[w] = k;
          next.push_back(w);
        }
      }
    }
    std::swap(current, next);
  }
  return ring;
}

Eigen::VectorXi vertexRings(const Stencils& s) {
  const std::vector<bool> boundary(s.vertexOnBoundary.begin(), s.vertexOnBoundary.end());
  return ringDistances(s, boundary);
}

std::vector<int> verticesInRings(const Eigen::VectorXi& rings, int ringCount) {
  std::vector<int> vertices;
  for (int v = 0; v < rings.size(); ++v)
    if (rings[v] >= 0 && rings[v] < ringCount) vertices.push_back(v);
  return vertices;
}

std::vector<std::vector<int>> boundaryLoops(const Stencils& s) {
  // A face traverses its boundary edge a → b; on a manifold mesh each boundary vertex has exactly
  // one such outgoing boundary edge.
  std::vector<int> nextOnBoundary(s.vertexCount(), -1);
  for (int f = 0; f < s.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      if (s.faceFlaps(f, i) < 0) nextOnBoundary[s.faces(f, (i + 1) % 3)] = s.faces(f, (i + 2) % 3);
    }
  }
  std::vector<std::vector<int>> loops;
  std::vector<char> visited(s.vertexCount(), 0);
  for (int start = 0; start < s.vertexCount(); ++start) {
    if (nextOnBoundary[start] < 0 || visited[start]) continue;
    std::vector<int> loop;
    for (int v = start; !visited[v]; v = nextOnBoundary[v]) {
      visited[v] = 1;
      loop.push_back(v);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace flexure::modeling
