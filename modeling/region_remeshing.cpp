#include "modeling/region_remeshing.h"

#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "modeling/cgal_surface_mesh.h"
#include "modeling/errors.h"
#include "modeling/mesh_info.h"
#include "modeling/surface_distance.h"

namespace flexure::modeling {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Vertex = CgalSurfaceMesh::Vertex_index;
using Face = CgalSurfaceMesh::Face_index;

constexpr int kMaxIterations = 100;
// The most faces a remeshing may make: a target length that would cover the region with more
// (≈ its area over an equilateral face of side ℓ, √3 ℓ² / 4) is refused before any work.
constexpr double kMaxRemeshedFaces = 2e6;
// Samples per face of the distance measures: barycentric (i, j, k)/n with i + j + k = n.
constexpr int kSampleDivisions = 4;

// The smallest interior angle of the faces with `kept[f]`, in degrees.
double minAngleDegrees(const Mesh& mesh, const std::vector<bool>& kept) {
  double smallest = 180.0;
  for (int f = 0; f < mesh.faceCount(); ++f)
    if (kept[f])
      smallest =
          std::min(smallest, smallestAngleDegrees(mesh.positions, mesh.triangles(f, 0),
                                                  mesh.triangles(f, 1), mesh.triangles(f, 2)));
  return smallest;
}

// The mean length of the distinct edges of the faces with `kept[f]`.
double meanFaceEdgeLength(const Mesh& mesh, const std::vector<bool>& kept) {
  std::map<std::pair<int, int>, double> edges;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    if (!kept[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(f, k), b = mesh.triangles(f, (k + 1) % 3);
      edges[{std::min(a, b), std::max(a, b)}] =
          (mesh.positions.row(a) - mesh.positions.row(b)).norm();
    }
  }
  double sum = 0.0;
  for (const auto& edge : edges) sum += edge.second;
  return sum / static_cast<double>(edges.size());
}

// The largest distance from the sample points of the faces of `from` with `fromKept[f]`
// (kSampleDivisions above) to the faces of `to` with `toKept[f]` (surface_distance.h).
double sampledDistance(const Mesh& from, const std::vector<bool>& fromKept, const Mesh& to,
                       const std::vector<bool>& toKept) {
  const SurfaceDistance distance(to, toKept);
  const int n = kSampleDivisions;
  double largest = 0.0;
  for (int f = 0; f < from.faceCount(); ++f) {
    if (!fromKept[f]) continue;
    const Eigen::Vector3d x0 = from.positions.row(from.triangles(f, 0)),
                          x1 = from.positions.row(from.triangles(f, 1)),
                          x2 = from.positions.row(from.triangles(f, 2));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        largest = std::max(largest, distance((i * x0 + j * x1 + (n - i - j) * x2) / n));
  }
  return largest;
}

// The Surface_mesh back as a Mesh, its removed elements skipped and the rest kept in index order
// (collect_garbage would reorder them); `inputVertex` and `remeshedFace` filled for it, the faces
// of index < `inputFaces` and !remeshed[f] being the input's held faces.
void fromRemeshed(const CgalSurfaceMesh& sm, int inputVertices, int inputFaces,
                  const std::vector<bool>& remeshed, RemeshedRegion& out) {
  std::vector<int> index(sm.num_vertices(), -1);
  int vertices = 0;
  for (const Vertex v : sm.vertices()) index[v.idx()] = vertices++;
  out.mesh.positions.resize(vertices, 3);
  out.inputVertex.assign(vertices, -1);
  for (const Vertex v : sm.vertices()) {
    const CgalKernel::Point_3& p = sm.point(v);
    out.mesh.positions.row(index[v.idx()]) << p.x(), p.y(), p.z();
    if (static_cast<int>(v.idx()) < inputVertices) out.inputVertex[index[v.idx()]] = v.idx();
  }
  out.mesh.triangles.resize(static_cast<Eigen::Index>(sm.number_of_faces()), 3);
  out.remeshedFace.assign(sm.number_of_faces(), false);
  int row = 0;
  for (const Face f : sm.faces()) {
    int k = 0;
    for (const Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      out.mesh.triangles(row, k++) = index[v.idx()];
    const int i = static_cast<int>(f.idx());
    out.remeshedFace[row++] = i >= inputFaces || remeshed[i];
  }
}

// The vertices of the remeshed faces that are on no edge with a remeshed face on one side only.
std::vector<bool> interiorVertices(const Mesh& mesh, const std::vector<bool>& remeshedFace) {
  std::map<std::pair<int, int>, int> sides;  // remeshed faces on each edge
  std::vector<bool> region(mesh.vertexCount(), false);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    if (!remeshedFace[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(f, k), b = mesh.triangles(f, (k + 1) % 3);
      ++sides[{std::min(a, b), std::max(a, b)}];
      region[a] = true;
    }
  }
  for (const auto& [edge, count] : sides) {
    if (count == 1) region[edge.first] = region[edge.second] = false;
  }
  return region;
}

}  // namespace

void RemeshOptions::validate() const {
  if (targetEdgeLength && !(*targetEdgeLength > 0.0 && std::isfinite(*targetEdgeLength)))
    throw InputError("RemeshOptions.targetEdgeLength " + numberText(*targetEdgeLength) +
                     ": expected a finite length > 0");
  if (iterations < 1 || iterations > kMaxIterations)
    throw InputError("RemeshOptions.iterations " + std::to_string(iterations) + ": expected 1 to " +
                     std::to_string(kMaxIterations));
}

RemeshedRegion remeshRegion(const Mesh& mesh, const std::vector<bool>& region,
                            const RemeshOptions& options) {
  options.validate();
  if (static_cast<int>(region.size()) != mesh.vertexCount())
    throw InputError("region: " + std::to_string(region.size()) + " entries for a mesh of " +
                     std::to_string(mesh.vertexCount()) + " vertices");
  std::vector<bool> remeshed(mesh.faceCount(), false);
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) remeshed[f] = remeshed[f] || region[mesh.triangles(f, k)];
  if (std::find(remeshed.begin(), remeshed.end(), true) == remeshed.end())
    throw InputError("region: no vertex selected, no face to remesh");

  RemeshedRegion out;
  out.targetEdgeLength = options.targetEdgeLength.value_or(meanFaceEdgeLength(mesh, remeshed));
  double area = 0.0;
  for (int f = 0; f < mesh.faceCount(); ++f)
    if (remeshed[f])
      area += 0.5 * (Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 1))) -
                     Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 0))))
                        .cross(Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 2))) -
                               Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 0))))
                        .norm();
  const double expectedFaces =
      area / (std::sqrt(3.0) / 4.0 * out.targetEdgeLength * out.targetEdgeLength);
  if (expectedFaces > kMaxRemeshedFaces)
    throw InputError("RemeshOptions.targetEdgeLength " + numberText(out.targetEdgeLength) +
                     ": would cover the region (area " + numberText(area) + ") with about " +
                     numberText(expectedFaces) + " faces, over the " +
                     numberText(kMaxRemeshedFaces) + " a remeshing may make");
  out.iterations = options.iterations;
  out.facesBefore = static_cast<int>(std::count(remeshed.begin(), remeshed.end(), true));
  out.minAngleDegreesBefore = minAngleDegrees(mesh, remeshed);

  CgalSurfaceMesh sm = toCgalSurfaceMesh(mesh, "region remeshing");
  std::vector<Face> faces;
  for (int f = 0; f < mesh.faceCount(); ++f)
    if (remeshed[f]) faces.emplace_back(f);
  // The border of the face range is constrained by CGAL; protected, it is neither split nor
  // collapsed, and tangential relaxation moves no vertex on it.
  PMP::isotropic_remeshing(
      faces, out.targetEdgeLength, sm,
      CGAL::parameters::number_of_iterations(options.iterations).protect_constraints(true));
  fromRemeshed(sm, mesh.vertexCount(), mesh.faceCount(), remeshed, out);
  out.region = interiorVertices(out.mesh, out.remeshedFace);
  out.facesAfter =
      static_cast<int>(std::count(out.remeshedFace.begin(), out.remeshedFace.end(), true));
  out.minAngleDegreesAfter = minAngleDegrees(out.mesh, out.remeshedFace);

  out.hausdorffInputToRemeshed = sampledDistance(mesh, remeshed, out.mesh, out.remeshedFace);
  out.hausdorffRemeshedToInput = sampledDistance(out.mesh, out.remeshedFace, mesh, remeshed);
  out.hausdorffDistance = std::max(out.hausdorffInputToRemeshed, out.hausdorffRemeshedToInput);
  return out;
}

}  // namespace flexure::modeling
