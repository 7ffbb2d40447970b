// Hole filling with CGAL (Polygon_mesh_processing::triangulate_and_refine_hole): each chosen
// boundary loop is closed by a minimum-weight (Delaunay-restricted) triangulation of the loop,
// refined so that the new triangles' sizes match the loop's edge lengths (Liepa 2003, "Filling
// holes in meshes"). The new patch is flat-ish and kinked at the loop; fairing it is the next step.
#pragma once

#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

struct FilledHole {
  int boundaryEdges = 0;  // edges of the loop
  int newFaces = 0, newVertices = 0;
};

struct FilledMesh {
  // The input's vertices and faces with their indices, then the patches' new vertices and faces.
  Mesh mesh;
  std::vector<bool> newVertex;    // #V of `mesh`
  std::vector<FilledHole> holes;  // the filled loops, in CGAL's order of the boundary cycles
  int loopsLeft = 0;              // boundary loops not filled (longer than the limit)
};

// Fills every boundary loop with at most maxBoundaryEdges edges (0: every loop). `mesh` must be
// valid (mesh.h). Throws NumericalError when CGAL cannot triangulate a loop or its result is not a
// valid mesh (the message names the loop and the problem).
FilledMesh fillHoles(const Mesh& mesh, int maxBoundaryEdges = 0);

}  // namespace flexure::modeling
