#include "modeling/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>

namespace flexure::modeling {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;

Kernel::Point_3 vertexPoint(const Mesh& mesh, int v) {
  return {mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2)};
}

Kernel::Triangle_3 faceTriangle(const Mesh& mesh, int f) {
  return {vertexPoint(mesh, mesh.triangles(f, 0)), vertexPoint(mesh, mesh.triangles(f, 1)),
          vertexPoint(mesh, mesh.triangles(f, 2))};
}

// One box per face: the triangle's exact bounding box (Bbox_3 of points with double coordinates
// is exact), so boxes of intersecting triangles overlap.
std::vector<Box> faceBoxes(const Mesh& mesh) {
  std::vector<Box> boxes;
  boxes.reserve(mesh.faceCount());
  for (int f = 0; f < mesh.faceCount(); ++f) boxes.emplace_back(faceTriangle(mesh, f).bbox(), f);
  return boxes;
}

bool sharePosition(const Mesh& mesh, int f, int g) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (mesh.positions.row(mesh.triangles(f, i)) == mesh.positions.row(mesh.triangles(g, j)))
        return true;
  return false;
}

}  // namespace

std::vector<std::array<int, 2>> intersectingFacePairs(const Mesh& mesh) {
  std::vector<Box> boxes = faceBoxes(mesh);
  std::vector<std::array<int, 2>> pairs;
  CGAL::box_self_intersection_d(
      boxes.begin(), boxes.end(), [&](const Box& first, const Box& second) {
        const int f = std::min(first.info(), second.info()),
                  g = std::max(first.info(), second.info());
        if (!sharePosition(mesh, f, g) &&
            CGAL::do_intersect(faceTriangle(mesh, f), faceTriangle(mesh, g)))
          pairs.push_back({f, g});
      });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<std::array<int, 2>> intersectingFacePairs(const Mesh& a, const Mesh& b) {
  std::vector<Box> aBoxes = faceBoxes(a), bBoxes = faceBoxes(b);
  std::vector<std::array<int, 2>> pairs;
  CGAL::box_intersection_d(aBoxes.begin(), aBoxes.end(), bBoxes.begin(), bBoxes.end(),
                           [&](const Box& first, const Box& second) {
                             const int f = first.info(), g = second.info();
                             if (CGAL::do_intersect(faceTriangle(a, f), faceTriangle(b, g)))
                               pairs.push_back({f, g});
                           });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace flexure::modeling
