#include "modeling/surface_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <cmath>

#include "modeling/cgal_surface_mesh.h"

namespace flexure::modeling {

struct SurfaceDistance::Tree {
  using Triangle = CgalKernel::Triangle_3;
  using Aabb = CGAL::AABB_tree<CGAL::AABB_traits<
      CgalKernel,
      CGAL::AABB_triangle_primitive<CgalKernel, std::vector<Triangle>::const_iterator>>>;
  std::vector<Triangle> triangles;  // the tree holds iterators into it
  Aabb aabb;
};

SurfaceDistance::SurfaceDistance(const Mesh& mesh, const std::vector<bool>& kept)
    : tree_(std::make_unique<Tree>()) {
  const auto point = [&mesh](int f, int k) {
    const auto x = mesh.positions.row(mesh.triangles(f, k));
    return CgalKernel::Point_3(x(0), x(1), x(2));
  };
  for (int f = 0; f < mesh.faceCount(); ++f)
    if (kept.empty() || kept[f])
      tree_->triangles.emplace_back(point(f, 0), point(f, 1), point(f, 2));
  tree_->aabb.insert(tree_->triangles.begin(), tree_->triangles.end());
  tree_->aabb.accelerate_distance_queries();
}

SurfaceDistance::~SurfaceDistance() = default;

double SurfaceDistance::operator()(const Eigen::Vector3d& p) const {
  return std::sqrt(tree_->aabb.squared_distance(CgalKernel::Point_3(p.x(), p.y(), p.z())));
}

}  // namespace flexure::modeling
