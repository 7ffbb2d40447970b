// The compile step: flat index arrays ("stencils") compiled once from the half-edge mesh. Energy
// evaluation reads only these, the RestState and the current positions — never the half-edge mesh.
//
// Conventions (docs/energies.md):
//  - Face f = (v0, v1, v2) counter-clockwise; edge i of f is opposite vertex i, i.e. runs
//    v_{i+1} → v_{i+2} (indices mod 3) in f.
//  - Edge e = (lower, higher) vertex index; edges are numbered in lexicographic order of that pair.
//  - σ_{f,i} = +1 when f traverses its edge i from the lower to the higher vertex index, else −1.
//  - Hinge (i, j, k, l) for each interior edge, with i < j, f = (i, j, k) holding the half-edge
//    i → j and g = (j, i, l).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

using IndexPairs = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;
using IndexQuads = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;

struct Stencils {
  Triangles faces;      // #F by 3: (v0, v1, v2)
  Triangles faceFlaps;  // #F by 3: vertex across edge i in the neighbouring face, −1 if boundary
  Triangles faceEdges;  // #F by 3: id of edge i
  Triangles faceEdgeSigns;  // #F by 3: σ_{f,i} ∈ {+1, −1}

  IndexPairs edges;      // #E by 2: (lower, higher)
  IndexPairs edgeFaces;  // #E by 2: (f, g), f traverses lower → higher; −1 where there is no face

  IndexQuads hinges;           // #H by 4: (i, j, k, l), one per interior edge, in edge order
  Eigen::VectorXi hingeEdges;  // #H: the edge id of each hinge

  // Vertex one-rings in compressed rows: the neighbours of v are
  // oneRingVertices[oneRingOffsets[v] .. oneRingOffsets[v+1]), counter-clockwise. For an interior
  // vertex the ring is cyclic; for a boundary vertex it runs from one boundary neighbour to the
  // other, so every consecutive pair (a, b) spans a face (v, a, b).
  Eigen::VectorXi oneRingOffsets;                          // #V + 1
  Eigen::VectorXi oneRingVertices;                         // Σ valences
  Eigen::Array<bool, Eigen::Dynamic, 1> vertexOnBoundary;  // #V

  int vertexCount() const { return static_cast<int>(vertexOnBoundary.size()); }
  int faceCount() const { return static_cast<int>(faces.rows()); }
  int edgeCount() const { return static_cast<int>(edges.rows()); }
  int hingeCount() const { return static_cast<int>(hinges.rows()); }
  int valence(int v) const { return oneRingOffsets[v + 1] - oneRingOffsets[v]; }
  // Whether every edge of face f is interior (the faces triavg and quadfit use).
  bool faceIsInterior(int f) const { return (faceFlaps.row(f).array() >= 0).all(); }
};

// `mesh` must pass checkMesh() (every Mesh from readMesh() or a generator does).
Stencils compileStencils(const Mesh& mesh);

// #V: the connected component (through edges) of every vertex, numbered 0, 1, … in the order of
// each component's smallest vertex.
std::vector<int> vertexComponents(const Stencils& stencils);

}  // namespace flexure::modeling
