#include "modeling/cgal_fair.h"

#include <CGAL/Polygon_mesh_processing/fair.h>

#include "modeling/cgal_surface_mesh.h"
#include "modeling/errors.h"

namespace flexure::modeling {

Positions cgalFair(const Mesh& mesh, const std::vector<bool>& freeVertex, int continuity) {
  CgalSurfaceMesh sm = toCgalSurfaceMesh(mesh, "cgalFair");
  std::vector<CgalSurfaceMesh::Vertex_index> region;
  for (int v = 0; v < mesh.vertexCount(); ++v)
    if (freeVertex[v]) region.emplace_back(v);

  const bool solved = CGAL::Polygon_mesh_processing::fair(
      sm, region, CGAL::parameters::fairing_continuity(static_cast<unsigned>(continuity)));
  if (!solved) {
    throw NumericalError("CGAL's fair could not solve its bi-Laplacian system for the " +
                         std::to_string(region.size()) +
                         " selected vertices (too few fixed vertices around the region?)");
  }
  return cgalPositions(sm);
}

}  // namespace flexure::modeling
