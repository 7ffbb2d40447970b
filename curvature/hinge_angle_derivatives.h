// Closed-form first and second derivatives of the hinge's bending angle θ (bending_angle.h) with
// respect to its four vertices, after Tamstorf & Grinspun 2013, "Discrete bending forces and
// their Jacobians" (GMOD 75(6)): the gradient in the form of Bridson, Marino & Fedkiw 2003, and
// the Hessian by differentiating that form block by block. The hinge's exact element Hessians
// cost about a seventh of the second-order jets' (bench/energy_bench.cpp BM_HingeElementHessian).
//
// The hinge (i, j, k, l), e = x_j − x_i, ℓ = |e|; face f = (i, j, k) and g = (j, i, l). For an
// opposite vertex p ∈ {k, l} with d_p = x_p − x_i, the face normal n_p = e × d_p (= n_f for k,
// = −n_g for l) and the edge parameter t_p = d_p · e / ℓ² of p's foot on the edge line:
//
//   ∂θ/∂x_p = s_p ℓ n_p / |n_p|²   (= ±n̂_p / h_p, h_p = |n_p| / ℓ p's height over e;
//                                   s_k = +1, s_l = −1: θ's sign convention),
//   ∂θ/∂x_i = Σ_p (t_p − 1) ∂θ/∂x_p,   ∂θ/∂x_j = −Σ_p t_p ∂θ/∂x_p,
//
// (translations and rotations leave θ unchanged). With g_p = ∂θ/∂x_p, a function of x_i, x_j, x_p
// only, and c_i = t_p − 1, c_j = −t_p, c_p = 1 the coefficients above, every block of ∇²θ is
//
//   ∂²θ/∂x_a∂x_b = Σ_p [ (dc_a/dt) g_p (∂t_p/∂x_b)ᵀ + c_a ∂g_p/∂x_b ],   a, b ∈ {i, j, p},
//
//   ∂g_p/∂x_b = s_p [ n_p ∂ℓ/∂x_b / |n_p|² + ℓ (I − 2 n̂_p n̂_pᵀ) ∂n_p/∂x_b / |n_p|² ],
//   ∂n_p/∂x_i = [x_p − x_j]_×,  ∂n_p/∂x_j = −[d_p]_×,  ∂n_p/∂x_p = [e]_×,  ∂ℓ/∂x_j = −∂ℓ/∂x_i = êᵀ,
//   ∂t_p/∂x_p = eᵀ/ℓ²,  ∂t_p/∂x_j = (d_p − 2 t_p e)ᵀ/ℓ²,  ∂t_p/∂x_i = −∂t_p/∂x_p − ∂t_p/∂x_j,
//
// with [a]_× b = a × b. Nothing here divides by sin θ or θ, so flat hinges need no special case.
#pragma once

#include <Eigen/Core>

namespace flexure::curvature {

struct HingeAngleDerivatives {
  double angle = 0.0;                     // θ, as bendingAngle computes it
  Eigen::Matrix<double, 12, 1> gradient;  // ∂θ/∂(x_i, x_j, x_k, x_l), each x, y, z
  Eigen::Matrix<double, 12, 12> hessian;  // ∇²θ, symmetric; left unset unless asked for
};

// θ and its derivatives at the hinge x[0..3] = (x_i, x_j, x_k, x_l), each three doubles.
// Non-finite entries where a face is degenerate (zero area or a zero-length edge).
void hingeAngleDerivatives(const double* const* x, bool withHessian, HingeAngleDerivatives& out);

}  // namespace flexure::curvature
