#include "curvature/hinge_angle_derivatives.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>

#include "curvature/bending_angle.h"

namespace flexure::curvature {
namespace {

using Vector3 = Eigen::Vector3d;
using RowVector3 = Eigen::RowVector3d;
using Matrix3 = Eigen::Matrix3d;

// [a]_×, the matrix of b ↦ a × b.
Matrix3 crossMatrix(const Vector3& a) {
  Matrix3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

// One face of the hinge seen from its opposite vertex p (the header's formulas); local vertex
// order (i, j, p).
struct HingeFlap {
  Vector3 gradient;                         // g_p = ∂θ/∂x_p
  double t;                                 // t_p
  std::array<Matrix3, 3> gradientJacobian;  // ∂g_p/∂x_b
  std::array<RowVector3, 3> tGradient;      // ∂t_p/∂x_b
};

HingeFlap hingeFlap(const Vector3& e, const Vector3& d, double sign, bool withJacobians) {
  const Vector3 n = e.cross(d);
  const double squaredArea = n.squaredNorm(), squaredLength = e.squaredNorm();
  const double length = std::sqrt(squaredLength);
  HingeFlap flap;
  flap.gradient = (sign * length / squaredArea) * n;
  flap.t = d.dot(e) / squaredLength;
  if (!withJacobians) return flap;
  // s ℓ (I − 2 n̂ n̂ᵀ) / |n|², and s n ∂ℓ/∂x_j / |n|² = (s n / (|n|² ℓ)) eᵀ.
  const Matrix3 projected = (sign * length / squaredArea) *
                            (Matrix3::Identity() - (2.0 / squaredArea) * n * n.transpose());
  const Matrix3 lengthPart = (sign / (squaredArea * length)) * n * e.transpose();
  flap.gradientJacobian[0] = projected * crossMatrix(d - e) - lengthPart;
  flap.gradientJacobian[1] = lengthPart - projected * crossMatrix(d);
  flap.gradientJacobian[2] = projected * crossMatrix(e);
  flap.tGradient[2] = e.transpose() / squaredLength;
  flap.tGradient[1] = (d - 2.0 * flap.t * e).transpose() / squaredLength;
  flap.tGradient[0] = -(flap.tGradient[1] + flap.tGradient[2]);
  return flap;
}

}  // namespace

void hingeAngleDerivatives(const double* const* x, bool withHessian, HingeAngleDerivatives& out) {
  const Eigen::Map<const Vector3> xi(x[0]), xj(x[1]);
  out.angle = bendingAngle(load(x[0]), load(x[1]), load(x[2]), load(x[3]));
  const Vector3 e = xj - xi;
  out.gradient.setZero();
  if (withHessian) out.hessian.setZero();
  // Opposite vertex k (slot 2, s = +1), then l (slot 3, s = −1).
  for (int p = 2; p < 4; ++p) {
    const HingeFlap flap =
        hingeFlap(e, Eigen::Map<const Vector3>(x[p]) - xi, p == 2 ? 1.0 : -1.0, withHessian);
    const std::array<int, 3> slots = {0, 1, p};
    const std::array<double, 3> coefficient = {flap.t - 1.0, -flap.t, 1.0};
    const std::array<double, 3> coefficientSlope = {1.0, -1.0, 0.0};  // dc_a/dt
    for (int a = 0; a < 3; ++a)
      out.gradient.segment<3>(3 * slots[a]) += coefficient[a] * flap.gradient;
    if (!withHessian) continue;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        if (slots[a] > slots[b]) continue;  // the upper blocks; the lower ones mirror them
        out.hessian.block<3, 3>(3 * slots[a], 3 * slots[b]) +=
            coefficientSlope[a] * flap.gradient * flap.tGradient[b] +
            coefficient[a] * flap.gradientJacobian[b];
      }
  }
  if (withHessian) out.hessian.triangularView<Eigen::StrictlyLower>() = out.hessian.transpose();
}

}  // namespace flexure::curvature
