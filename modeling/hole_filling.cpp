#include "modeling/hole_filling.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <iterator>
#include <string>

#include "modeling/cgal_surface_mesh.h"
#include "modeling/errors.h"
#include "modeling/mesh_check.h"

namespace flexure::modeling {

FilledMesh fillHoles(const Mesh& mesh, int maxBoundaryEdges) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  using Halfedge = CgalSurfaceMesh::Halfedge_index;
  CgalSurfaceMesh sm = toCgalSurfaceMesh(mesh, "fillHoles");

  std::vector<Halfedge> loops;  // one border halfedge per boundary cycle
  PMP::extract_boundary_cycles(sm, std::back_inserter(loops));
  FilledMesh filled;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    FilledHole hole;
    for (const Halfedge h : CGAL::halfedges_around_face(loops[i], sm)) {
      (void)h;
      ++hole.boundaryEdges;
    }
    if (maxBoundaryEdges > 0 && hole.boundaryEdges > maxBoundaryEdges) {
      ++filled.loopsLeft;
      continue;
    }
    std::vector<CgalSurfaceMesh::Face_index> faces;
    std::vector<CgalSurfaceMesh::Vertex_index> vertices;
    PMP::triangulate_and_refine_hole(sm, loops[i], std::back_inserter(faces),
                                     std::back_inserter(vertices));
    if (faces.empty()) {
      throw NumericalError("hole filling: CGAL could not triangulate boundary loop " +
                           std::to_string(i) + " (" + std::to_string(hole.boundaryEdges) +
                           " edges)");
    }
    hole.newFaces = static_cast<int>(faces.size());
    hole.newVertices = static_cast<int>(vertices.size());
    filled.holes.push_back(hole);
  }
  filled.mesh = fromCgalSurfaceMesh(sm);
  filled.newVertex.assign(filled.mesh.vertexCount(), false);
  for (int v = mesh.vertexCount(); v < filled.mesh.vertexCount(); ++v) filled.newVertex[v] = true;

  const MeshCheck check = checkMesh(filled.mesh, 1);
  if (!check.valid()) {
    const MeshProblem& p = check.problems.front();
    throw NumericalError("hole filling: CGAL's patches do not make a valid mesh: " + p.element +
                         ": " + p.reason);
  }
  return filled;
}

}  // namespace flexure::modeling
