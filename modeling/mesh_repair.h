// Repair of what checkMesh refuses and a program can mend without guessing: vertices no face uses
// (dropped), non-manifold vertices (split into one copy per fan of faces) and inconsistent face
// orientation (faces flipped so that each edge is traversed once each way), through CGAL's
// polygon-soup orientation (Polygon_mesh_processing::orient_polygon_soup).
#pragma once

#include <string>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

struct MeshRepairReport {
  int droppedVertices = 0;  // unreferenced vertices removed
  int addedVertices = 0;    // copies made to split non-manifold vertices (and edges)
  int flippedFaces = 0;     // faces whose orientation was reversed
  bool changed() const { return droppedVertices + addedVertices + flippedFaces > 0; }
};

struct RepairedMesh {
  Mesh mesh;
  MeshRepairReport report;
};

// `mesh` with its unreferenced vertices dropped (the others keep their order), then split and
// oriented. Faces keep their order; a split vertex's copies are appended. Repairs nothing else
// (zero-area or duplicate faces, non-finite coordinates stay: checkMesh still names them).
RepairedMesh repairMesh(const Mesh& mesh);

}  // namespace flexure::modeling
