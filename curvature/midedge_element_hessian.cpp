// The midedge element's energy, gradient and exact Hessian on the rest metric from the closed-form
// derivatives of its three hinge angles (element_hessian.h states the chain rule). On the rest
// metric S_T = Σ_i γ_i T̄_i with constant tensors T̄_i (midedge_normals.h), so the residuals are
// affine in γ: r = r₀ + Σ_i C_i γ_i with C_i = koiterResiduals(T̄_i, 0) (koiter_density.h), and
// with γ_i = θ_i / 2 + σ_i ξ_i (θ_i = 0 on a boundary edge):
//
//   ∇r = C Jγ,   ∇E_e = (C Jγ)ᵀ r,   ∇²E_e = (C Jγ)ᵀ (C Jγ) + Σ_i (r · C_i) ½ ∇²θ_i,
//
// where row i of Jγ is ½ ∇θ_i + σ_i e_{ξ_i} and ∇²θ_i is hinge_angle_derivatives.h's, over the
// hinge (x_{i+1}, x_{i+2}, x_i, flap_i) of 12 unknowns.
#include <array>

#include "curvature/element_hessian.h"
#include "curvature/hinge_angle_derivatives.h"

namespace flexure::curvature {
namespace {

// The element slot of coordinate c of block b (blocks: ξ0, ξ1, ξ2, then vertices), or −1 where it
// is not an unknown (a vertex's x and y in height mode).
int midedgeSlot(Derivatives derivatives, int block, int c) {
  if (block < 3) return block;
  if (derivatives == Derivatives::All) return 3 + 3 * (block - 3) + c;
  return c == 2 ? block : -1;
}

// Edge i's hinge: its blocks (x_{i+1}, x_{i+2}, x_i, the flap), as bendingAngle reads them in
// MidedgeResidual::shapeOperator.
std::array<int, 4> hingeBlocks(int i, int flapBlock) {
  return {3 + (i + 1) % 3, 3 + (i + 2) % 3, 3 + i, flapBlock};
}

}  // namespace

bool elementHessian(const MidedgeResidual& residual, const std::vector<const double*>& blocks,
                    const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                    Derivatives derivatives, ElementHessian& out) {
  if (residual.currentMetric)
    return elementHessian<MidedgeResidual>(residual, blocks, sizes, firstUnknown, derivatives, out);
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  const int count = static_cast<int>(out.unknowns.size());
  Eigen::Vector3d r;
  if (!residual(blocks.data(), r.data())) return false;
  Eigen::Matrix3d c;  // column i: ∂r/∂γ_i
  for (int i = 0; i < 3; ++i)
    koiterResiduals(residual.edgeTensors[i], Sym2<double>{0.0, 0.0, 0.0}, residual.weights,
                    c.col(i).data());

  using Rows = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxElementUnknowns<MidedgeResidual>>;
  Rows gammaJacobian = Rows::Zero(3, count);  // Jγ
  out.hessian.setZero(count, count);
  thread_local HingeAngleDerivatives theta;
  for (int i = 0, flap = 6; i < 3; ++i) {
    gammaJacobian(i, midedgeSlot(derivatives, i, 0)) = residual.signs[i];
    if (!residual.hasFlap[i]) continue;
    const std::array<int, 4> hinge = hingeBlocks(i, flap++);
    const double* x[4] = {blocks[hinge[0]], blocks[hinge[1]], blocks[hinge[2]], blocks[hinge[3]]};
    hingeAngleDerivatives(x, true, theta);
    const double weight = 0.5 * r.dot(c.col(i));  // (r · C_i) ½
    for (int a = 0; a < 12; ++a) {
      const int sa = midedgeSlot(derivatives, hinge[a / 3], a % 3);
      if (sa < 0) continue;
      gammaJacobian(i, sa) += 0.5 * theta.gradient[a];
      for (int b = 0; b < 12; ++b) {
        const int sb = midedgeSlot(derivatives, hinge[b / 3], b % 3);
        if (sb >= sa) out.hessian(sa, sb) += weight * theta.hessian(a, b);
      }
    }
  }
  const Rows jacobian = c * gammaJacobian;  // ∂r/∂x
  out.energy = 0.5 * r.squaredNorm();
  out.gradient.noalias() = jacobian.transpose() * r;
  out.hessian.triangularView<Eigen::Upper>() += jacobian.transpose() * jacobian;
  out.hessian.triangularView<Eigen::StrictlyLower>() = out.hessian.transpose();
  return out.gradient.allFinite() && out.hessian.allFinite();
}

}  // namespace flexure::curvature
