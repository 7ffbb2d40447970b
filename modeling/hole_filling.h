// Hole filling with CGAL (Polygon_mesh_processing::triangulate_and_refine_hole): each chosen
// boundary loop is closed by a minimum-weight (Delaunay-restricted) triangulation of the loop,
// refined so that the new triangles' sizes match the loop's edge lengths (Liepa 2003, "Filling
// holes in meshes"). The new patch is flat-ish and kinked at the loop; fairing it is the next step.
//
// Not every loop has a clean fill: a slit (a loop that runs along a crack and back over vertices
// with the same coordinates, as in CGAL's elephant-with-holes.off) or a strongly non-planar loop
// gets triangles of zero area or triangles folded onto their neighbours, and a loop that passes
// twice through one point gets triangles joining its two sides there. Such loops are left open
// (FilledMesh::skipped says why), so that one bad loop does not spoil the others.
#pragma once

#include <string>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

// A fill is clean when every new face has 2A > kCleanFillFlatness · (its longest edge)² (its
// height over the longest edge is more than kCleanFillFlatness / 2 of that edge: not collapsed
// onto a line) and no new face's unit normal turns by more than kCleanFillFoldDegrees against a
// neighbouring face's (a fold: the two triangles lie nearly on top of each other).
inline constexpr double kCleanFillFlatness = 1e-6;
inline constexpr double kCleanFillFoldDegrees = 150.0;
// A loop is not filled when two of its vertices lie within this fraction of its mean edge length
// of each other (a pinched loop: hole_filling.cpp, pinchedLoop).
inline constexpr double kPinchedLoopDistance = 1e-6;

struct FilledHole {
  int boundaryEdges = 0;  // edges (= vertices) of the loop
  int loopVertex = 0;     // the loop's smallest vertex index (names the loop)
  int newFaces = 0, newVertices = 0;
};

struct SkippedHole {
  int boundaryEdges = 0;
  int loopVertex = 0;
  std::string reason;  // why CGAL's fill is not clean, naming a face (vertex ids of the result)
};

struct FilledMesh {
  // The input's vertices and faces with their indices, then the patches' new vertices and faces.
  Mesh mesh;
  std::vector<bool> newVertex;       // #V of `mesh`
  std::vector<FilledHole> holes;     // the filled loops, in CGAL's order of the boundary cycles
  std::vector<SkippedHole> skipped;  // loops within the limit whose fill was not clean: left open
  int loopsLeft = 0;                 // boundary loops not filled (longer than the limit)
};

// Fills every boundary loop with at most maxBoundaryEdges edges (0: every loop) whose fill is
// clean (above); the others stay open and are listed in `skipped`. `mesh` must be valid
// (mesh.h). Throws NumericalError when the filled mesh is not a valid mesh anyway.
FilledMesh fillHoles(const Mesh& mesh, int maxBoundaryEdges = 0);

}  // namespace flexure::modeling
