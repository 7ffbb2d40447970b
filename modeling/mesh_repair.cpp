#include "modeling/mesh_repair.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>

#include <array>

namespace flexure::modeling {
namespace {

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

// The mesh without the vertices no face uses; `dropped` counts them.
Mesh withoutUnreferencedVertices(const Mesh& mesh, int& dropped) {
  std::vector<int> newIndex(mesh.vertexCount(), -1);
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f)
    for (int i = 0; i < 3; ++i) newIndex[mesh.triangles(f, i)] = 0;
  int kept = 0;
  for (int& index : newIndex)
    if (index == 0) index = kept++;
  dropped = mesh.vertexCount() - kept;
  Mesh out;
  out.positions.resize(kept, 3);
  for (int v = 0; v < mesh.vertexCount(); ++v)
    if (newIndex[v] >= 0) out.positions.row(newIndex[v]) = mesh.positions.row(v);
  out.triangles = mesh.triangles;
  for (Eigen::Index f = 0; f < out.triangles.rows(); ++f)
    for (int i = 0; i < 3; ++i) out.triangles(f, i) = newIndex[mesh.triangles(f, i)];
  return out;
}

// Whether triangle `after` (its copies mapped back to the vertices they copy) runs the other way
// round from `before`.
bool reversed(const Eigen::Vector3i& before, const std::array<int, 3>& after) {
  for (int shift = 0; shift < 3; ++shift)
    if (after[0] == before[shift] && after[1] == before[(shift + 1) % 3]) return false;
  return true;
}

}  // namespace

RepairedMesh repairMesh(const Mesh& mesh) {
  RepairedMesh result;
  const Mesh kept = withoutUnreferencedVertices(mesh, result.report.droppedVertices);
  const int vertexCount = kept.vertexCount();
  std::vector<Point> points;
  for (int v = 0; v < vertexCount; ++v)
    points.emplace_back(kept.positions(v, 0), kept.positions(v, 1), kept.positions(v, 2));
  std::vector<std::array<int, 3>> faces;
  for (Eigen::Index f = 0; f < kept.triangles.rows(); ++f)
    faces.push_back({kept.triangles(f, 0), kept.triangles(f, 1), kept.triangles(f, 2)});
  std::vector<std::array<int, 3>> oriented = faces;
  CGAL::Polygon_mesh_processing::orient_polygon_soup(points, oriented);
  result.report.addedVertices = static_cast<int>(points.size()) - vertexCount;

  // A copy has its original's coordinates: map each face's copies back through its own vertices.
  result.mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v)
    result.mesh.positions.row(static_cast<Eigen::Index>(v)) << points[v].x(), points[v].y(),
        points[v].z();
  result.mesh.triangles.resize(static_cast<Eigen::Index>(oriented.size()), 3);
  for (size_t f = 0; f < oriented.size(); ++f) {
    const Eigen::Vector3i before = kept.triangles.row(static_cast<Eigen::Index>(f)).transpose();
    std::array<int, 3> original = oriented[f];
    for (int& v : original) {
      if (v < vertexCount) continue;
      for (int i = 0; i < 3; ++i)
        if (kept.positions.row(before[i]) == result.mesh.positions.row(v)) v = before[i];
    }
    result.report.flippedFaces += reversed(before, original);
    for (int i = 0; i < 3; ++i)
      result.mesh.triangles(static_cast<Eigen::Index>(f), i) = oriented[f][i];
  }
  return result;
}

}  // namespace flexure::modeling
