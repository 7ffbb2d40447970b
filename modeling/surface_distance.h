// The distance from points to a triangle mesh's surface: the closest point on its triangles, by
// CGAL's AABB tree (a triangle soup: the faces need not be manifold or closed).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

class SurfaceDistance {
 public:
  // The surface of `mesh`'s faces with kept[f] (every face when `kept` is empty); at least one.
  explicit SurfaceDistance(const Mesh& mesh, const std::vector<bool>& kept = {});
  ~SurfaceDistance();
  SurfaceDistance(const SurfaceDistance&) = delete;
  SurfaceDistance& operator=(const SurfaceDistance&) = delete;

  // min over the surface's points q of |p − q|.
  double operator()(const Eigen::Vector3d& p) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace flexure::modeling
