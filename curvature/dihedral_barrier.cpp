#include "curvature/dihedral_barrier.h"

#include <algorithm>
#include <string>

#include "curvature/element_term.h"
#include "curvature/projected_hessian.h"
#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

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

// The barrier's Gauss–Newton part is its exact Hessian projected (ProjectingSink). The residual
// form's JᵀJ = r'(d)² ∇d ∇dᵀ is only b''(d) / (2 log(d̂ / d)) of the barrier's curvature across
// the wall (b ≈ κ d̂² log(d̂ / d), r'² ≈ κ d̂² / (2 d² log(d̂ / d)) as d → 0) and drops b'(d) ∇²d,
// so Newton steps on it overshoot the wall and the line search creeps up to it: boeing.off's
// holes on the current metric stalled there (|∇E| 1.8e8 after 200 steps).
class DihedralBarrierTerm : public ElementTerm<DihedralBarrierResidual> {
 public:
  using ElementTerm<DihedralBarrierResidual>::ElementTerm;
  void elementHessians(const Positions& x, const Eigen::VectorXd& xi, int begin, int end,
                       Derivatives derivatives, SecondDerivatives kind,
                       ElementHessianSink& sink) const override {
    if (kind != SecondDerivatives::GaussNewton) {
      ElementTerm::elementHessians(x, xi, begin, end, derivatives, kind, sink);
      return;
    }
    ProjectingSink projecting(sink);
    ElementTerm::elementHessians(x, xi, begin, end, derivatives, SecondDerivatives::Exact,
                                 projecting);
  }
};

}  // namespace

std::unique_ptr<EnergyTerm> makeDihedralBarrier(const modeling::Stencils& s,
                                                const std::vector<int>& hinges,
                                                const modeling::Positions& positions,
                                                double stiffness, double maxAngle, double band,
                                                double margin) {
  constexpr double kPi = 3.14159265358979323846;
  if (!(stiffness > 0.0) || !(band > 0.0) || !(margin >= 0.0) || !(maxAngle + margin < kPi)) {
    throw InputError("dihedral barrier: stiffness " + std::to_string(stiffness) + " and band " +
                     std::to_string(band) + " must be positive, the ceiling " +
                     std::to_string(maxAngle) + " plus margin " + std::to_string(margin) +
                     " below pi");
  }
  std::vector<DihedralBarrierResidual> elements;
  std::vector<int> edgeIds;
  for (int h : hinges) {
    const std::array<int, 4> v = {s.hinges(h, 0), s.hinges(h, 1), s.hinges(h, 2), s.hinges(h, 3)};
    const auto at = [&](int i) {
      return Vec3<double>{positions(v[i], 0), positions(v[i], 1), positions(v[i], 2)};
    };
    const double folded = std::abs(bendingAngle(at(0), at(1), at(2), at(3)));
    // Capped below π: a hinge folded flat onto itself at the start gets no barrier.
    const double ceiling = std::min(std::max(maxAngle, folded + band + margin), kPi - 1e-3);
    if (!(ceiling > folded)) continue;
    elements.push_back({v, std::sqrt(2.0 * stiffness), ceiling, band});
    edgeIds.push_back(s.hingeEdges[h]);
  }
  return std::make_unique<DihedralBarrierTerm>("dihedral barrier", "edge", std::move(elements),
                                               std::move(edgeIds), 0.0, false);
}

}  // namespace flexure::curvature
