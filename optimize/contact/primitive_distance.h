// Unsigned squared distances between the primitives of a triangle mesh, with their exact gradients
// and Hessians, for self-contact in the style of incremental potential contact (Li et al. 2020,
// "Incremental Potential Contact", ACM TOG 39(4), §4 and its supplement).
//
// The distance between two primitives is the distance between their closest features, and each
// function first classifies which pair of features that is (IPC's distance types), then evaluates
// that type's closed form, smooth where the type is fixed:
//   point–point  |p − q|²
//   point–edge   |(e0 − p) × (e1 − p)|² / |e1 − e0|²       (p's distance to the line e0 e1)
//   point–plane  ((p − t0) · n)² / |n|²,  n = (t1 − t0) × (t2 − t0)
//   line–line    ((b0 − a0) · n)² / |n|²,  n = (a1 − a0) × (b1 − b0)
// The squared distance is C¹ across the types' borders; its Hessian is that of the active type.
//
// Derivatives are with respect to the four points stacked in the order of the arguments, 3
// coordinates each (12 unknowns); a null `gradient` or `hessian` is not computed.
#pragma once

#include <Eigen/Core>

namespace flexure::optimize {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;

// Squared distance from point p to the triangle (t0, t1, t2) (non-degenerate), the closest feature
// being a vertex, an edge or the interior (point–point, point–edge, point–plane); derivatives
// with respect to (p, t0, t1, t2).
double pointTriangleDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                    const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                    Vector12* gradient = nullptr, Matrix12* hessian = nullptr);

// Squared distance between the segments (a0, a1) and (b0, b1) (each of positive length):
// line–line when the closest points of the two lines lie inside both segments and the segments
// are not parallel, otherwise the nearest of the four endpoint-to-segment distances (point–edge
// or point–point), which is the distance of parallel segments too. Derivatives with respect to
// (a0, a1, b0, b1).
double edgeEdgeDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                               const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                               Vector12* gradient = nullptr, Matrix12* hessian = nullptr);

// IPC's edge–edge mollifier (Li et al. 2020, §4.3 and supplement), which takes the edge–edge
// barrier smoothly to zero as the edges become parallel (where the line–line distance's
// derivatives blow up):
//   c = |(a1 − a0) × (b1 − b0)|²,   m(c) = (2 − c/ε) c/ε for c < ε,   1 for c ≥ ε,
// C¹ at c = ε; derivatives with respect to (a0, a1, b0, b1), zero where c ≥ ε.
double edgeEdgeMollifier(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                         const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, double threshold,
                         Vector12* gradient = nullptr, Matrix12* hessian = nullptr);

// The mollifier's threshold ε = 10⁻³ |a1 − a0|² |b1 − b0|² (Li et al. 2020, supplement), from the
// edges' rest positions.
double edgeEdgeMollifierThreshold(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                  const Eigen::Vector3d& b0, const Eigen::Vector3d& b1);

}  // namespace flexure::optimize
