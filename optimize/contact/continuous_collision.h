// Continuous collision detection between moving primitives by additive CCD (Li, Kaufman, Jiang
// 2021, "Codimensional Incremental Potential Contact", ACM TOG 40(4), §5, Alg. 1): conservative
// advancement on a bound of how fast the distance can shrink.
//
// The points move linearly, x_i(t) = x_i + t dx_i for t ∈ [0, 1]. The distance between the
// primitives does not change under a common translation, so the mean displacement p̄ is removed
// first; then the distance is Lipschitz in t with the constant
//   l = max_{i ∈ first primitive} |dx_i − p̄| + max_{j ∈ second} |dx_j − p̄|
// (the closest points move at most as fast as the fastest vertex of their primitive). From a
// time t_k with distance d_k ≥ g = s d(0) the step t_{k+1} = t_k + (d_k − g) / l keeps
// d ≥ d_k − l (t − t_k) ≥ g on [t_k, t_{k+1}], so every time reached is safe. ACCD steps by
// 0.9 d_k / l after a first step (1 − s) d(0) / l and checks the gap only at the steps; here each
// step is bounded by the gap itself, so the guarantee holds on the whole interval, not only at
// the steps. The advancement stops when it reaches t = 1 (returned as 1), when the distance left
// above g has fallen below a tenth of its start value d(0) − g (the primitives are about to come
// closer than g: the time reached is returned), or after a fixed number of steps (the time
// reached, conservative).
#pragma once

#include <Eigen/Core>
#include <array>

namespace flexure::optimize {

// l above for the displacements dx of a pair's four points, the first `firstCount` the first
// primitive's. The impact times below are 1 whenever l ≤ (1 − s) d(0): the first step reaches 1.
double distanceRateBound(const std::array<Eigen::Vector3d, 4>& dx, int firstCount);

// The largest time t ∈ [0, 1] found such that on [0, t] the distance between the point p and the
// triangle (t0, t1, t2), moving by (dp, dt0, dt1, dt2), stays ≥ gapFraction × its start distance
// (ACCD's s, 0 < s < 1; InputError otherwise); 1 when it stays so for the whole motion, 0 when the
// start distance is 0 or a displacement is not finite.
double pointTriangleImpactTime(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                               const Eigen::Vector3d& dp, const Eigen::Vector3d& dt0,
                               const Eigen::Vector3d& dt1, const Eigen::Vector3d& dt2,
                               double gapFraction = 0.1);

// The same for the segments (a0, a1) and (b0, b1) moving by (da0, da1, db0, db1).
double edgeEdgeImpactTime(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                          const Eigen::Vector3d& da0, const Eigen::Vector3d& da1,
                          const Eigen::Vector3d& db0, const Eigen::Vector3d& db1,
                          double gapFraction = 0.1);

}  // namespace flexure::optimize
