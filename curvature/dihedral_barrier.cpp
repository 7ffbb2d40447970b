#include "curvature/dihedral_barrier.h"

#include <algorithm>
#include <string>

#include "curvature/barrier_term.h"
#include "modeling/errors.h"

namespace flexure::curvature {

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
  // Its Gauss–Newton Hessian is each hinge's exact one projected (barrier_term.h).
  return std::make_unique<BarrierTerm<DihedralBarrierResidual>>(
      "dihedral barrier", "edge", std::move(elements), std::move(edgeIds), 0.0, false);
}

}  // namespace flexure::curvature
