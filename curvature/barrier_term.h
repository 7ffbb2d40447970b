// The log barriers' terms (membrane.h's logBarrierResidual: the angle barrier, membrane.h, and the
// dihedral barrier, dihedral_barrier.h): an ElementTerm whose Gauss–Newton Hessian, the one a rule
// asks for where the exact Hessian is indefinite, is each element's exact Hessian projected to
// positive semidefinite (projected_hessian.h) instead of its JᵀJ.
//
// Why: for b(d) = ½ r(d)² near the wall the residual form's JᵀJ = r'(d)² ∇d ∇dᵀ is only
// b''(d) / (2 log(d̂ / d)) of the barrier's curvature across it (b ≈ κ d̂² log(d̂ / d),
// r'² ≈ κ d̂² / (2 d² log(d̂ / d)) as d → 0) and drops b'(d) ∇²d, so Newton steps on it overshoot the
// wall and the line search creeps up to it. The exact element Hessian b'' ∇d ∇dᵀ + b' ∇²d has the
// wall's curvature; projected, it is what a positive semidefinite step may use. Measured:
// boeing.off's holes on the current metric stalled at the dihedral barrier's wall on JᵀJ (|∇E|
// 1.8e8 after 200 steps) and converge with the projection; the angle barrier's projection takes
// mask_cone.off's holes (cotan, current metric) to the same E in 168 steps against 245
// (docs/commands/fair.md).
#pragma once

#include <utility>
#include <vector>

#include "curvature/element_term.h"
#include "curvature/projected_hessian.h"

namespace flexure::curvature {

// Hands each element to `sink` with its Hessian replaced by the nearest positive semidefinite
// matrix (projected_hessian.h).
class ProjectingSink : public ElementHessianSink {
 public:
  explicit ProjectingSink(ElementHessianSink& sink) : sink_(sink) {}
  void add(const ElementHessian& element) override {
    projected_.unknowns = element.unknowns;
    projected_.energy = element.energy;
    projected_.gradient = element.gradient;
    projected_.hessian = projectedToPositiveSemidefinite(element.hessian);
    sink_.add(projected_);
  }

 private:
  ElementHessianSink& sink_;
  ElementHessian projected_;
};

// ElementTerm<Residual> but for Gauss–Newton: then the exact element Hessians, projected.
template <class Residual>
class BarrierTerm : public ElementTerm<Residual> {
 public:
  using ElementTerm<Residual>::ElementTerm;
  void elementHessians(const Positions& x, const Eigen::VectorXd& xi, int begin, int end,
                       Derivatives derivatives, SecondDerivatives kind,
                       ElementHessianSink& sink) const override {
    if (kind != SecondDerivatives::GaussNewton) {
      ElementTerm<Residual>::elementHessians(x, xi, begin, end, derivatives, kind, sink);
      return;
    }
    ProjectingSink projecting(sink);
    ElementTerm<Residual>::elementHessians(x, xi, begin, end, derivatives, SecondDerivatives::Exact,
                                           projecting);
  }
};

}  // namespace flexure::curvature
