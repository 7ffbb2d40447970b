#include "optimize/contact/broad_phase.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <limits>
#include <string>

#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;

void checkInput(const Eigen::Ref<const modeling::Positions>& x,
                const Eigen::Ref<const modeling::Positions>& dx, const modeling::Triangles& faces,
                const modeling::IndexPairs& edges, double inflation) {
  if (dx.rows() != 0 && dx.rows() != x.rows())
    throw InputError("contact candidates: the displacements have " + std::to_string(dx.rows()) +
                     " rows for " + std::to_string(x.rows()) + " vertices");
  if (!(inflation >= 0.0))
    throw InputError("contact candidates: the inflation must be ≥ 0, not " + numberText(inflation));
  const int n = static_cast<int>(x.rows());
  const bool inRange = (faces.size() == 0 || (faces.minCoeff() >= 0 && faces.maxCoeff() < n)) &&
                       (edges.size() == 0 || (edges.minCoeff() >= 0 && edges.maxCoeff() < n));
  if (!inRange)
    throw InputError("contact candidates: a face or edge names a vertex outside 0.." +
                     std::to_string(n - 1));
}

// The box of the vertices `vertices` at both ends of the motion, inflated on every side.
template <class Indices>
Box motionBox(const Eigen::Ref<const modeling::Positions>& x,
              const Eigen::Ref<const modeling::Positions>& dx, const Indices& vertices,
              double inflation, int info) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const int v : vertices) {
    const Eigen::Vector3d start = x.row(v).transpose();
    lo = lo.cwiseMin(start), hi = hi.cwiseMax(start);
    if (dx.rows() == 0) continue;
    const Eigen::Vector3d end = start + dx.row(v).transpose();
    lo = lo.cwiseMin(end), hi = hi.cwiseMax(end);
  }
  lo.array() -= inflation, hi.array() += inflation;
  return Box(CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()), info);
}

bool shareVertex(const int* a, int aCount, const int* b, int bCount) {
  for (int i = 0; i < aCount; ++i)
    for (int j = 0; j < bCount; ++j)
      if (a[i] == b[j]) return true;
  return false;
}

}  // namespace

CandidatePairs contactCandidates(const Eigen::Ref<const modeling::Positions>& x,
                                 const Eigen::Ref<const modeling::Positions>& dx,
                                 const modeling::Triangles& faces,
                                 const modeling::IndexPairs& edges, double inflation) {
  checkInput(x, dx, faces, edges, inflation);
  std::vector<Box> vertexBoxes, faceBoxes, edgeBoxes;
  for (int v = 0; v < x.rows(); ++v)
    vertexBoxes.push_back(motionBox(x, dx, std::array<int, 1>{v}, inflation, v));
  for (int f = 0; f < faces.rows(); ++f)
    faceBoxes.push_back(
        motionBox(x, dx, std::array<int, 3>{faces(f, 0), faces(f, 1), faces(f, 2)}, inflation, f));
  for (int e = 0; e < edges.rows(); ++e)
    edgeBoxes.push_back(
        motionBox(x, dx, std::array<int, 2>{edges(e, 0), edges(e, 1)}, inflation, e));

  CandidatePairs pairs;
  CGAL::box_intersection_d(vertexBoxes.begin(), vertexBoxes.end(), faceBoxes.begin(),
                           faceBoxes.end(), [&](const Box& vertex, const Box& face) {
                             const int v = vertex.info(), f = face.info();
                             if (!shareVertex(&v, 1, faces.row(f).data(), 3))
                               pairs.vertexFace.push_back({v, f});
                           });
  CGAL::box_self_intersection_d(edgeBoxes.begin(), edgeBoxes.end(),
                                [&](const Box& first, const Box& second) {
                                  const int e = first.info(), g = second.info();
                                  if (!shareVertex(edges.row(e).data(), 2, edges.row(g).data(), 2))
                                    pairs.edgeEdge.push_back({std::min(e, g), std::max(e, g)});
                                });
  std::sort(pairs.vertexFace.begin(), pairs.vertexFace.end());
  std::sort(pairs.edgeEdge.begin(), pairs.edgeEdge.end());
  return pairs;
}

}  // namespace flexure::optimize
