// GCC 12 reports a false "may be used uninitialized" inside OpenMesh's property vectors when
// add_vertex is inlined here; the warning is about OpenMesh's code, not ours.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "modeling/halfedge_mesh.h"

#include <stdexcept>
#include <string>

namespace flexure::modeling {

HalfedgeMesh buildHalfedgeMesh(const Mesh& mesh) {
  HalfedgeMesh he;
  he.reserve(mesh.vertexCount(), 3 * mesh.vertexCount(), mesh.faceCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    he.add_vertex(
        HalfedgeMesh::Point(mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2)));
  }
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    const auto face =
        he.add_face(he.vertex_handle(t(0)), he.vertex_handle(t(1)), he.vertex_handle(t(2)));
    if (!face.is_valid() || face.idx() != f) {
      throw std::logic_error("buildHalfedgeMesh: OpenMesh rejected face " + std::to_string(f) +
                             "; the mesh was not checked with checkMesh()");
    }
  }
  return he;
}

}  // namespace flexure::modeling
