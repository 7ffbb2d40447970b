// dihedral barrier — a ceiling on how far a hinge may fold: for the bending angle θ_e of a hinge
// (bending_angle.h, the turn between its faces' normals), with d = θ_max,e − |θ_e| and a band d̂,
//
//   b(θ) = −κ (d − d̂)² log(d / d̂)   for 0 < d < d̂,   0 for d ≥ d̂,
//
// the angle barrier's smooth log barrier (membrane.h; Li et al. 2020) on the dihedral angle: C²
// where it switches on, +∞ as |θ| → θ_max. Why fairing on the current metric needs it: a discrete
// bending energy prices a fold finitely — the midedge or hinge cost of a hinge folded by θ is
// ≈ ℓ² θ² / (A_f + A_g) ≤ π² ℓ² / (A_f + A_g), where the smooth Willmore energy of a crease is
// infinite — and the shape membranes (C = FᵀF) do not see a face swing over its edge, a rotation
// in space. So a minimizer of the geometric energy may fold a face over rather than bend a coarse
// region smoothly (flexure fair, CGAL's corner_tris_with_hole.off: one vertex pushed over a held
// edge, its face turned 127° against both neighbours, E lower than unfolded). A solve that never
// raises its energy keeps every |θ_e| below θ_max,e. Residual r = √(2κ) (d̂ − d) √(−log(d / d̂)),
// ½ r² = b (logBarrierResidual, membrane.h); d ≤ 0 is infeasible (evaluation fails, the line
// search backs off).
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "curvature/bending_angle.h"
#include "curvature/energy_term.h"
#include "curvature/membrane.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

struct DihedralBarrierResidual {
  static constexpr int kResiduals = 1;
  using BlockSizes = std::integer_sequence<int, 3, 3, 3, 3>;
  std::array<int, 4> vertices;  // the hinge (i, j, k, l) of Stencils::hinges
  double sqrtWeight;            // √(2κ)
  double maxAngle;              // θ_max,e, radians, < π
  double band;                  // d̂, radians

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    const T theta = bendingAngle(load(x[0]), load(x[1]), load(x[2]), load(x[3]));
    const T d = T(maxAngle) - (scalarPart(theta) < 0.0 ? T(-1.0) * theta : theta);
    return logBarrierResidual(d, band, sqrtWeight, r[0]) && isFiniteScalar(r[0]);
  }
};

// The dihedral barrier on the hinges `hinges` (indices into stencils.hinges): κ = `stiffness`, and
// per hinge θ_max,e = min(max(maxAngle, |θ_e(positions)| + band + margin), π − 10⁻³), in radians:
// zero at `positions` (but for a hinge folded within d̂ of the cap there), and a hinge folded
// sharper than maxAngle − d̂ there may fold a band further. Throws InputError for a non-positive κ
// or d̂, or a maxAngle + margin not below π.
std::unique_ptr<EnergyTerm> makeDihedralBarrier(const modeling::Stencils& stencils,
                                                const std::vector<int>& hinges,
                                                const modeling::Positions& positions,
                                                double stiffness, double maxAngle, double band,
                                                double margin);

}  // namespace flexure::curvature
