// The hinge element's energy, gradient and Hessian from the closed-form derivatives of its angle
// (element_hessian.h states the formulas).
#include <cmath>

#include "curvature/element_hessian.h"
#include "curvature/hinge_angle_derivatives.h"

namespace flexure::curvature {
namespace {

// The 12 slots (x_i, x_j, x_k, x_l, each x, y, z) an element's unknowns take: all, or the z's.
constexpr int kHingeSlots = 12;
int hingeSlot(Derivatives derivatives, int k) {
  return derivatives == Derivatives::All ? k : 3 * k + 2;
}

// E_e, ∇E_e and (Exact | GaussNewton) ∇²E_e or J_eᵀJ_e; false where the residual is not finite.
bool closedFormDerivatives(const HingeBendingResidual& residual,
                           const std::vector<const double*>& blocks, Derivatives derivatives,
                           SecondDerivatives kind, ElementHessian& out) {
  double r;
  if (!residual(blocks.data(), &r)) return false;
  thread_local HingeAngleDerivatives theta;
  hingeAngleDerivatives(blocks.data(), kind == SecondDerivatives::Exact, theta);
  const HingeAngleMeasureSlopes slope = hingeAngleMeasureSlopes(theta.angle, residual.measure);
  const int count = static_cast<int>(out.unknowns.size());
  const Eigen::Matrix<double, kHingeSlots, 1> jacobian =
      (residual.sqrtWeight * slope.first) * theta.gradient;  // ∇r
  out.energy = 0.5 * r * r;
  out.gradient.resize(count);
  for (int a = 0; a < count; ++a) out.gradient[a] = r * jacobian[hingeSlot(derivatives, a)];
  if (kind == SecondDerivatives::None) {
    out.hessian.resize(0, 0);
    return true;
  }
  out.hessian.resize(count, count);
  const double weight = r * residual.sqrtWeight;  // r w
  for (int b = 0; b < count; ++b) {
    const int sb = hingeSlot(derivatives, b);
    for (int a = 0; a <= b; ++a) {
      const int sa = hingeSlot(derivatives, a);
      out.hessian(a, b) = jacobian[sa] * jacobian[sb];
      if (kind == SecondDerivatives::Exact)
        out.hessian(a, b) += weight * (slope.second * theta.gradient[sa] * theta.gradient[sb] +
                                       slope.first * theta.hessian(sa, sb));
    }
  }
  out.hessian.triangularView<Eigen::StrictlyLower>() = out.hessian.transpose();
  return true;
}

}  // namespace

bool elementFirstDerivatives(const HingeBendingResidual& residual,
                             const std::vector<const double*>& blocks,
                             const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                             Derivatives derivatives, bool gaussNewton, ElementHessian& out) {
  if (residual.currentMetric)
    return elementFirstDerivatives<HingeBendingResidual>(residual, blocks, sizes, firstUnknown,
                                                         derivatives, gaussNewton, out);
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  return closedFormDerivatives(
      residual, blocks, derivatives,
      gaussNewton ? SecondDerivatives::GaussNewton : SecondDerivatives::None, out);
}

bool elementHessian(const HingeBendingResidual& residual, const std::vector<const double*>& blocks,
                    const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                    Derivatives derivatives, ElementHessian& out) {
  if (residual.currentMetric)
    return elementHessian<HingeBendingResidual>(residual, blocks, sizes, firstUnknown, derivatives,
                                                out);
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  return closedFormDerivatives(residual, blocks, derivatives, SecondDerivatives::Exact, out) &&
         out.gradient.allFinite() && out.hessian.allFinite();
}

}  // namespace flexure::curvature
