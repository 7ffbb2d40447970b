// The bending (dihedral) angle of a hinge, docs/energies.md "Bending angle":
//
//   θ_e = atan2( (n_g × n_f) · ê , n_f · n_g ),
//   n_f = (x_j − x_i) × (x_k − x_i),  n_g = (x_l − x_i) × (x_j − x_i),  ê = (x_j − x_i)/|x_j −
//   x_i|,
//
// for the hinge (i, j, k, l) with faces f = (i, j, k) and g = (j, i, l). θ = 0 on a flat hinge,
// θ ∈ (−π, π), and on a counter-clockwise height field z = f(x, y) it has the sign of f's second
// derivative across the edge. atan2 keeps it accurate near 0 and ±π, where acos is not.
#pragma once

#include <cmath>

#include "curvature/kernel_math.h"

namespace flexure::curvature {

template <class T>
T bendingAngle(const Vec3<T>& xi, const Vec3<T>& xj, const Vec3<T>& xk, const Vec3<T>& xl) {
  using std::atan2;
  const Vec3<T> e = xj - xi;
  const Vec3<T> nf = cross(e, xk - xi);
  const Vec3<T> ng = cross(xl - xi, e);
  // (n_g × n_f) · ê with ê = e/|e|: the division by |e| is folded into atan2's first argument.
  return atan2(dot(cross(ng, nf), e) / norm(e), dot(nf, ng));
}

// The angle measure a hinge energy uses: θ itself, or 2 tan(θ/2) (Discrete Shells' option, and
// the φ of the triangle-averaged shape operator).
enum class HingeAngle { Theta, Tan };

template <class T>
T hingeAngleMeasure(const T& theta, HingeAngle measure) {
  using std::tan;
  return measure == HingeAngle::Theta ? theta : T(2.0) * tan(theta / T(2.0));
}

// dφ/dθ and d²φ/dθ² of that measure: 1 and 0 for θ; for φ = 2 tan(θ/2), with τ = tan(θ/2),
// 1 + τ² and τ (1 + τ²).
struct HingeAngleMeasureSlopes {
  double first, second;
};
inline HingeAngleMeasureSlopes hingeAngleMeasureSlopes(double theta, HingeAngle measure) {
  if (measure == HingeAngle::Theta) return {1.0, 0.0};
  const double tau = std::tan(theta / 2.0), first = 1.0 + tau * tau;
  return {first, tau * first};
}

}  // namespace flexure::curvature
