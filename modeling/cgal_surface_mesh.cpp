#include "modeling/cgal_surface_mesh.h"

#include <string>

#include "modeling/errors.h"

namespace flexure::modeling {

CgalSurfaceMesh toCgalSurfaceMesh(const Mesh& mesh, std::string_view caller) {
  using Vertex = CgalSurfaceMesh::Vertex_index;
  CgalSurfaceMesh sm;
  sm.reserve(mesh.vertexCount(), 3 * mesh.faceCount() / 2 + mesh.vertexCount(), mesh.faceCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    sm.add_vertex(
        CgalKernel::Point_3(mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2)));
  }
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    if (sm.add_face(Vertex(t(0)), Vertex(t(1)), Vertex(t(2))) == CgalSurfaceMesh::null_face()) {
      throw InputError(std::string(caller) + ": CGAL rejected face " + std::to_string(f) +
                       " (not manifold)");
    }
  }
  return sm;
}

Positions cgalPositions(const CgalSurfaceMesh& sm) {
  Positions out(static_cast<Eigen::Index>(sm.number_of_vertices()), 3);
  for (const auto v : sm.vertices()) {
    const CgalKernel::Point_3& p = sm.point(v);
    out.row(static_cast<Eigen::Index>(v.idx())) << p.x(), p.y(), p.z();
  }
  return out;
}

Mesh fromCgalSurfaceMesh(const CgalSurfaceMesh& sm) {
  Mesh mesh;
  mesh.positions = cgalPositions(sm);
  mesh.triangles.resize(static_cast<Eigen::Index>(sm.number_of_faces()), 3);
  for (const auto f : sm.faces()) {
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      mesh.triangles(static_cast<Eigen::Index>(f.idx()), k++) = static_cast<int>(v.idx());
  }
  return mesh;
}

}  // namespace flexure::modeling
