// Cracks in a render: the lips of the cracks a cut opened (crackLipEdges) and, per face, the
// crack edges and crack vertices it has (faceCrackBits).
#include "render/cracks.h"

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "modeling/errors.h"
#include "render/mesh_renderer.h"

namespace flexure::render {

std::vector<int> faceCrackBits(const modeling::Mesh& mesh,
                               const std::vector<std::array<int, 2>>& crackEdges) {
  std::map<std::pair<int, int>, bool> isCrack;
  std::set<int> crackVertices;
  for (const auto& [a, b] : crackEdges) {
    isCrack[{std::min(a, b), std::max(a, b)}] = false;
    crackVertices.insert({a, b});
  }
  std::vector<int> bits(crackEdges.empty() ? 0 : mesh.faceCount(), 0);
  for (int f = 0; f < static_cast<int>(bits.size()); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (crackVertices.count(mesh.triangles(f, k))) bits[f] |= 8 << k;
      const int a = mesh.triangles(f, (k + 1) % 3), b = mesh.triangles(f, (k + 2) % 3);
      const auto edge = isCrack.find({std::min(a, b), std::max(a, b)});
      if (edge == isCrack.end()) continue;
      edge->second = true;
      bits[f] |= 1 << k;
    }
  }
  for (const auto& [edge, found] : isCrack)
    if (!found)
      throw InputError("RenderOptions.crackEdges: (" + std::to_string(edge.first) + ", " +
                       std::to_string(edge.second) + ") is not an edge of the mesh");
  return bits;
}

std::vector<std::array<int, 2>> crackLipEdges(const modeling::Positions& rest,
                                              const modeling::Triangles& triangles) {
  // Each undirected edge with the faces that have it; then the boundary edges (one face) keyed by
  // their ends' rest positions, in order.
  std::map<std::pair<int, int>, int> faceCount;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
      ++faceCount[{std::min(a, b), std::max(a, b)}];
    }
  using Point = std::array<double, 3>;
  const auto point = [&](int v) { return Point{rest(v, 0), rest(v, 1), rest(v, 2)}; };
  std::map<std::pair<Point, Point>, std::vector<std::array<int, 2>>> boundaryAt;
  for (const auto& [edge, faces] : faceCount) {
    if (faces != 1) continue;
    const Point p = point(edge.first), q = point(edge.second);
    boundaryAt[{std::min(p, q), std::max(p, q)}].push_back({edge.first, edge.second});
  }
  std::vector<std::array<int, 2>> lips;
  for (const auto& [ends, edges] : boundaryAt)
    if (edges.size() > 1) lips.insert(lips.end(), edges.begin(), edges.end());
  return lips;
}

}  // namespace flexure::render
