// Hand-built meshes for tests whose answers are worked out by hand.
#pragma once

#include "modeling/mesh.h"
#include "modeling/stencils.h"

namespace flexure::testing {

using modeling::Mesh;

// The unit square split by the diagonal 0–2: vertices (0,0), (1,0), (1,1), (0,1);
// faces (0, 1, 2) and (0, 2, 3).
inline Mesh twoTriangleSquare() {
  Mesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 2, 3;
  return m;
}

// A closed, outward-oriented tetrahedron (Euler characteristic 2, no boundary).
inline Mesh tetrahedron() {
  Mesh m;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.triangles.resize(4, 3);
  m.triangles << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

// An nx × ny grid of unit cells, each split by its lower-left → upper-right diagonal, with the
// cells for which skip(i, j) is true left out. Vertex (i, j) has index j (nx + 1) + i.
template <class Skip>
Mesh gridMesh(int nx, int ny, Skip skip) {
  Mesh m;
  m.positions.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.positions.row(j * (nx + 1) + i) << i, j, 0.0;
  std::vector<int> t;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (skip(i, j)) continue;
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      t.insert(t.end(), {a, b, c, a, c, d});
    }
  }
  m.triangles = Eigen::Map<modeling::Triangles>(t.data(), static_cast<int>(t.size() / 3), 3);
  return m;
}

inline Mesh gridMesh(int nx, int ny) {
  return gridMesh(nx, ny, [](int, int) { return false; });
}

// The mesh with its first interior face split 1 → 3 at the centroid: the new vertex has valence
// 3, so the faces around it see one vertex as two of their flaps (a repeated parameter block).
inline Mesh withValenceThreeVertex(const Mesh& mesh) {
  const modeling::Stencils s = modeling::compileStencils(mesh);
  int f = 0;
  while (!s.faceIsInterior(f)) ++f;
  const auto t = mesh.triangles.row(f);
  Mesh out = mesh;
  const int v = mesh.vertexCount();
  out.positions.conservativeResize(v + 1, 3);
  out.positions.row(v) =
      (mesh.positions.row(t(0)) + mesh.positions.row(t(1)) + mesh.positions.row(t(2))) / 3.0;
  const int a = t(0), b = t(1), c = t(2);
  out.triangles.conservativeResize(mesh.faceCount() + 2, 3);
  out.triangles.row(f) << a, b, v;
  out.triangles.row(mesh.faceCount()) << b, c, v;
  out.triangles.row(mesh.faceCount() + 1) << c, a, v;
  return out;
}

}  // namespace flexure::testing
