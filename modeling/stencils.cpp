#include "modeling/stencils.h"

#include <algorithm>
#include <vector>

#include "modeling/halfedge_mesh.h"

namespace flexure::modeling {
namespace {

void compileEdges(const HalfedgeMesh& he, Stencils& s) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(he.n_edges());
  for (const auto e : he.edges()) {
    const int a = e.v0().idx(), b = e.v1().idx();
    pairs.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(pairs.begin(), pairs.end());
  s.edges.resize(static_cast<int>(pairs.size()), 2);
  s.edgeFaces.setConstant(static_cast<int>(pairs.size()), 2, -1);
  for (size_t e = 0; e < pairs.size(); ++e) s.edges.row(e) << pairs[e].first, pairs[e].second;

  const auto edgeId = [&](int a, int b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    return static_cast<int>(std::lower_bound(pairs.begin(), pairs.end(), key) - pairs.begin());
  };
  const int nf = static_cast<int>(he.n_faces());
  s.faceEdges.resize(nf, 3);
  s.faceEdgeSigns.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      const int a = s.faces(f, (i + 1) % 3), b = s.faces(f, (i + 2) % 3);
      const int e = edgeId(a, b);
      s.faceEdges(f, i) = e;
      s.faceEdgeSigns(f, i) = a < b ? 1 : -1;
      s.edgeFaces(e, a < b ? 0 : 1) = f;
    }
  }
}

void compileFlapsAndHinges(Stencils& s) {
  const int nf = s.faceCount();
  const auto oppositeVertex = [&](int f, int e) {
    for (int i = 0; i < 3; ++i)
      if (s.faceEdges(f, i) == e) return s.faces(f, i);
    return -1;
  };
  s.faceFlaps.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      const int e = s.faceEdges(f, i);
      const int other = s.edgeFaces(e, 0) == f ? s.edgeFaces(e, 1) : s.edgeFaces(e, 0);
      s.faceFlaps(f, i) = other < 0 ? -1 : oppositeVertex(other, e);
    }
  }
  std::vector<int> interior;
  for (int e = 0; e < s.edgeCount(); ++e)
    if (s.edgeFaces(e, 0) >= 0 && s.edgeFaces(e, 1) >= 0) interior.push_back(e);
  s.hinges.resize(static_cast<int>(interior.size()), 4);
  s.hingeEdges.resize(static_cast<int>(interior.size()));
  for (size_t h = 0; h < interior.size(); ++h) {
    const int e = interior[h];
    s.hinges.row(h) << s.edges(e, 0), s.edges(e, 1), oppositeVertex(s.edgeFaces(e, 0), e),
        oppositeVertex(s.edgeFaces(e, 1), e);
    s.hingeEdges[h] = e;
  }
}

// Rotating an outgoing half-edge h (v → a, in face (v, a, b)) to opposite(prev(h)) = v → b turns
// counter-clockwise about v. A boundary vertex starts at its outgoing boundary half-edge v → a,
// which has no face; the rotation then crosses the gap first, so a is moved to the end.
void compileOneRings(const HalfedgeMesh& he, Stencils& s) {
  const int nv = static_cast<int>(he.n_vertices());
  s.oneRingOffsets.resize(nv + 1);
  s.vertexOnBoundary.resize(nv);
  std::vector<int> ring, all;
  all.reserve(he.n_halfedges());
  s.oneRingOffsets[0] = 0;
  for (int v = 0; v < nv; ++v) {
    const auto vh = he.vertex_handle(v);
    const auto start = he.halfedge_handle(vh);
    ring.clear();
    auto h = start;
    do {
      ring.push_back(he.to_vertex_handle(h).idx());
      h = he.opposite_halfedge_handle(he.prev_halfedge_handle(h));
    } while (h != start);
    const bool boundary = he.is_boundary(start);
    if (boundary) std::rotate(ring.begin(), ring.begin() + 1, ring.end());
    s.vertexOnBoundary[v] = boundary;
    all.insert(all.end(), ring.begin(), ring.end());
    s.oneRingOffsets[v + 1] = static_cast<int>(all.size());
  }
  s.oneRingVertices = Eigen::Map<Eigen::VectorXi>(all.data(), static_cast<int>(all.size()));
}

}  // namespace

Stencils compileStencils(const Mesh& mesh) {
  const HalfedgeMesh he = buildHalfedgeMesh(mesh);
  Stencils s;
  s.faces = mesh.triangles;
  compileEdges(he, s);
  compileFlapsAndHinges(s);
  compileOneRings(he, s);
  return s;
}

std::vector<int> vertexComponents(const Stencils& s) {
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
  return component;
}

}  // namespace flexure::modeling
