// A closed test surface with a known curvature: the icosphere, a regular icosahedron whose faces
// are split 1 → 4 at the edge midpoints `levels` times, every vertex projected onto the sphere of
// radius R about the origin. Faces are counter-clockwise seen from outside (outward normals).
// Level k has 20 · 4^k faces, 30 · 4^k edges and 10 · 4^k + 2 vertices.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::testing {

inline modeling::Mesh icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;  // golden ratio: vertices (0, ±1, ±t) cyclic
  std::vector<Eigen::Vector3d> points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                         {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                         {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& p : points) p.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      points.push_back((points[a] + points[b]).normalized());
      const int index = static_cast<int>(points.size()) - 1;
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> refined;
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      refined.push_back({f[0], ab, ca});
      refined.push_back({f[1], bc, ab});
      refined.push_back({f[2], ca, bc});
      refined.push_back({ab, bc, ca});
    }
    faces = std::move(refined);
  }
  modeling::Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v)
    mesh.positions.row(static_cast<Eigen::Index>(v)) = radius * points[v].transpose();
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f)
    mesh.triangles.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return mesh;
}

}  // namespace flexure::testing
