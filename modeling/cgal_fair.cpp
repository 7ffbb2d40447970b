#include "modeling/cgal_fair.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/fair.h>
#include <CGAL/Surface_mesh.h>

#include "modeling/errors.h"

namespace flexure::modeling {

Positions cgalFair(const Mesh& mesh, const std::vector<bool>& freeVertex, int continuity) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
  using Vertex = SurfaceMesh::Vertex_index;

  SurfaceMesh sm;
  sm.reserve(mesh.vertexCount(), 3 * mesh.faceCount() / 2 + mesh.vertexCount(), mesh.faceCount());
  std::vector<Vertex> vertices;
  vertices.reserve(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    vertices.push_back(sm.add_vertex(
        Kernel::Point_3(mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2))));
  }
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    if (sm.add_face(vertices[t(0)], vertices[t(1)], vertices[t(2)]) == SurfaceMesh::null_face())
      throw InputError("cgalFair: CGAL rejected face " + std::to_string(f) + " (not manifold)");
  }
  std::vector<Vertex> region;
  for (int v = 0; v < mesh.vertexCount(); ++v)
    if (freeVertex[v]) region.push_back(vertices[v]);

  const bool solved = CGAL::Polygon_mesh_processing::fair(
      sm, region, CGAL::parameters::fairing_continuity(static_cast<unsigned>(continuity)));
  if (!solved) {
    throw NumericalError("CGAL's fair could not solve its bi-Laplacian system for the " +
                         std::to_string(region.size()) +
                         " selected vertices (too few fixed vertices around the region?)");
  }
  Positions out(mesh.vertexCount(), 3);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const Kernel::Point_3& p = sm.point(vertices[v]);
    out.row(v) << p.x(), p.y(), p.z();
  }
  return out;
}

}  // namespace flexure::modeling
