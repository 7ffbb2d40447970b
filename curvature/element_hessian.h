// Exact second derivatives of one element's energy E_e = ½ |r_e|², from the same templated
// residual functor that gives its values and Jacobian, evaluated with SecondOrderJet scalars:
//
//   ∇E_e = Σ_i r_i ∇r_i,   ∇²E_e = Σ_i (∇r_i ∇r_iᵀ + r_i ∇²r_i),
//
// over the element's unknowns: a vertex's x, y, z (Derivatives::All) or its z alone (HeightOnly,
// x and y held), and a midedge ξ, in the order the element reads its blocks. At rest (r = 0) the
// Hessian is the Gauss–Newton matrix JᵀJ exactly.
#pragma once

#include <ceres/jet.h>
#include <Eigen/Core>
#include <array>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "curvature/cotan_mean_curvature.h"
#include "curvature/height_only_cost.h"
#include "curvature/hinge_bending.h"
#include "curvature/membrane.h"
#include "curvature/midedge_normals.h"
#include "curvature/quadratic_fit.h"
#include "curvature/second_order_jet.h"
#include "curvature/triangle_averaged.h"
#include "modeling/errors.h"

namespace flexure::curvature {

// One element's energy, gradient and Hessian; unknowns[k] is the global unknown of local slot k
// (3v + c for coordinate c of vertex v, 3 #V + e for ξ_e). A vertex read through two slots
// (shared_block_cost.h) has two local slots with the same global unknown: a sum over slots
// assembles it correctly.
struct ElementHessian {
  std::vector<long> unknowns;  // n
  double energy = 0.0;
  Eigen::VectorXd gradient;  // n
  Eigen::MatrixXd hessian;   // n by n, symmetric
};

// Which second derivatives: the exact ∇²E_e; the Gauss–Newton part J_eᵀJ_e alone (first
// derivatives only, by Ceres' autodiff: much cheaper), which equals ∇²E_e where r_e = 0, e.g. at
// a stress-free rest state; or none (energy and gradient only; the hessian is left empty).
// Projected: each exact ∇²E_e projected to positive semidefinite (projected_hessian.h), asked of
// the assembly; it hands the elements Exact.
enum class SecondDerivatives { Exact, GaussNewton, None, Projected };
// The names users give them: "exact", "gauss-newton", "none", "projected". InputError otherwise.
inline SecondDerivatives parseSecondDerivatives(std::string_view name) {
  if (name == "exact") return SecondDerivatives::Exact;
  if (name == "gauss-newton") return SecondDerivatives::GaussNewton;
  if (name == "none") return SecondDerivatives::None;
  if (name == "projected") return SecondDerivatives::Projected;
  throw InputError("second derivatives " + std::string(name) +
                   ": expected exact, gauss-newton, none or projected");
}

// Receives the elements' Hessians one at a time.
class ElementHessianSink {
 public:
  virtual ~ElementHessianSink() = default;
  virtual void add(const ElementHessian& element) = 0;
};

// The most unknowns an element of each type has (Derivatives::All); cotan rings have as many as
// their valence allows: 3 (k + 1) for valence k. A residual type that declares its blocks' sizes
// (`using BlockSizes = std::integer_sequence<int, 3, 3, 3>;`) has their sum.
template <int... Sizes>
constexpr int sumOfBlockSizes(std::integer_sequence<int, Sizes...>) {
  return (0 + ... + Sizes);
}
template <class Residual, class = void>
struct DeclaredElementUnknowns {
  static constexpr int value = 48;
};
template <class Residual>
struct DeclaredElementUnknowns<Residual, std::void_t<typename Residual::BlockSizes>> {
  static constexpr int value = sumOfBlockSizes(typename Residual::BlockSizes());
};
template <class Residual>
constexpr int kMaxElementUnknowns = DeclaredElementUnknowns<Residual>::value;
template <>
constexpr int kMaxElementUnknowns<HingeBendingResidual> = 12;
template <>
constexpr int kMaxElementUnknowns<TriangleAveragedResidual> = 18;
template <>
constexpr int kMaxElementUnknowns<QuadraticFitResidual> = 18;
template <>
constexpr int kMaxElementUnknowns<MidedgeResidual> = 21;
template <>
constexpr int kMaxElementUnknowns<StvkMembraneResidual> = 9;
template <>
constexpr int kMaxElementUnknowns<ConformalMembraneResidual> = 9;
template <>
constexpr int kMaxElementUnknowns<AreaSpringResidual> = 9;
template <>
constexpr int kMaxElementUnknowns<AngleBarrierResidual> = 9;
template <>
constexpr int kMaxElementUnknowns<EdgeSpringResidual> = 6;
// Larger than any element's: a cotan vertex of valence 16 or more in xyz mode.
inline constexpr int kMaxHessianUnknowns = 48;

// Calls f(std::integral_constant<int, N>()) with the smallest jet size N ≥ count among a few
// sizes (each one instantiation of the kernels), up to the one that holds `Limit`. Unused slots
// of a jet stay zero. Returns false when count exceeds every size.
template <int Limit, class F>
bool withJetSize(int count, F&& f) {
  if (count <= 4) return f(std::integral_constant<int, 4>());
  if constexpr (Limit > 4)
    if (count <= 6) return f(std::integral_constant<int, 6>());
  if constexpr (Limit > 6)
    if (count <= 9) return f(std::integral_constant<int, 9>());
  if constexpr (Limit > 9)
    if (count <= 12) return f(std::integral_constant<int, 12>());
  if constexpr (Limit > 12)
    if (count <= 18) return f(std::integral_constant<int, 18>());
  if constexpr (Limit > 18)
    if (count <= 21) return f(std::integral_constant<int, 21>());
  if constexpr (Limit > 21)
    if (count <= 27) return f(std::integral_constant<int, 27>());
  if constexpr (Limit > 27)
    if (count <= 36) return f(std::integral_constant<int, 36>());
  if constexpr (Limit > 36)
    if (count <= 48) return f(std::integral_constant<int, 48>());
  return false;
}

// Whether coordinate c of a block of `size` values is an unknown: all of them, or in height mode
// a vertex's z and a ξ (the last value of a block).
inline bool isElementUnknown(Derivatives derivatives, int c, int size) {
  return derivatives == Derivatives::All || c == size - 1;
}

// The global unknowns of an element reading blocks of `sizes` whose first unknowns are
// `firstUnknown`, in slot order.
inline void elementUnknowns(const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                            Derivatives derivatives, std::vector<long>& out) {
  out.clear();
  for (size_t b = 0; b < sizes.size(); ++b)
    for (int c = 0; c < sizes[b]; ++c)
      if (isElementUnknown(derivatives, c, sizes[b])) out.push_back(firstUnknown[b] + c);
}

// Fills `out` for the element `residual` reading `blocks` (block b holds sizes[b] values, and its
// first global unknown is firstUnknown[b]). Returns false where the element is degenerate (a
// residual is not finite) or has more unknowns than kMaxHessianUnknowns (out.unknowns then holds
// them all, so the caller can tell the two apart).
// The independent variable `slot` at `value` (∂/∂slot = 1) as each kind of jet spells it.
template <int N>
ceres::Jet<double, N> variableJet(const ceres::Jet<double, N>*, double value, int slot) {
  return ceres::Jet<double, N>(value, slot);
}
template <int N>
SecondOrderJet<N> variableJet(const SecondOrderJet<N>*, double value, int slot) {
  return SecondOrderJet<N>::variable(value, slot);
}

// The element's jets: block b's values, unknowns seeded slot by slot, the rest constants; in
// per-thread scratch, reused from element to element without allocating.
template <class Jet>
const Jet* const* seededBlocks(const std::vector<const double*>& blocks,
                               const std::vector<int>& sizes, Derivatives derivatives) {
  thread_local std::vector<std::array<Jet, 3>> values;
  thread_local std::vector<const Jet*> pointers;
  values.resize(blocks.size());
  pointers.resize(blocks.size());
  int slot = 0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    for (int c = 0; c < sizes[b]; ++c)
      values[b][c] = isElementUnknown(derivatives, c, sizes[b])
                         ? variableJet(static_cast<const Jet*>(nullptr), blocks[b][c], slot++)
                         : Jet(blocks[b][c]);
    pointers[b] = values[b].data();
  }
  return pointers.data();
}

// First derivatives only, by forward-mode jets (ceres::Jet, as Ceres' autodiff): E_e, ∇E_e and,
// with `gaussNewton`, J_eᵀJ_e (= Σ_i ∇r_i ∇r_iᵀ); out.hessian empty otherwise. Returns false
// where the residual functor refuses the element (degenerate), and when it has more unknowns
// than any jet size here (the caller then uses Ceres' own cost function). Values are not checked
// for being finite: a line search rejects a trial point whose energy is not.
template <class Residual>
bool elementFirstDerivatives(const Residual& residual, const std::vector<const double*>& blocks,
                             const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                             Derivatives derivatives, bool gaussNewton, ElementHessian& out) {
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  const int count = static_cast<int>(out.unknowns.size());
  return withJetSize<kMaxElementUnknowns<Residual>>(count, [&](auto size) {
    constexpr int N = decltype(size)::value;
    using Jet = ceres::Jet<double, N>;
    std::array<Jet, Residual::kResiduals> r;
    if (!residual(seededBlocks<Jet>(blocks, sizes, derivatives), r.data())) return false;
    Eigen::Matrix<double, N, 1> gradient = Eigen::Matrix<double, N, 1>::Zero();
    out.energy = 0.0;
    for (const Jet& ri : r) {
      out.energy += 0.5 * ri.a * ri.a;
      gradient += ri.a * ri.v;
    }
    out.gradient = gradient.head(count);
    if (!gaussNewton) {
      out.hessian.resize(0, 0);
      return true;
    }
    Eigen::Matrix<double, N, N> normal = Eigen::Matrix<double, N, N>::Zero();
    for (const Jet& ri : r) normal.noalias() += ri.v * ri.v.transpose();
    out.hessian = normal.topLeftCorner(count, count);
    return true;
  });
}

template <class Residual>
bool elementHessian(const Residual& residual, const std::vector<const double*>& blocks,
                    const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                    Derivatives derivatives, ElementHessian& out) {
  elementUnknowns(sizes, firstUnknown, derivatives, out.unknowns);
  const int count = static_cast<int>(out.unknowns.size());
  return withJetSize<kMaxElementUnknowns<Residual>>(count, [&](auto size) {
    constexpr int N = decltype(size)::value;
    using Jet = SecondOrderJet<N>;
    std::array<Jet, Residual::kResiduals> r;
    if (!residual(seededBlocks<Jet>(blocks, sizes, derivatives), r.data())) return false;
    Eigen::Matrix<double, N, 1> gradient = Eigen::Matrix<double, N, 1>::Zero();
    Eigen::Matrix<double, N, N> hessian = Eigen::Matrix<double, N, N>::Zero();
    out.energy = 0.0;
    for (const Jet& ri : r) {
      out.energy += 0.5 * ri.a * ri.a;
      gradient += ri.a * ri.v;
      hessian.noalias() += ri.v * ri.v.transpose();
      for (int i = 0; i < count; ++i)
        for (int j = i; j < count; ++j) hessian(i, j) += ri.a * ri.hessian(i, j);
    }
    hessian.template triangularView<Eigen::StrictlyLower>() = hessian.transpose();
    out.gradient = gradient.head(count);
    out.hessian = hessian.topLeftCorner(count, count);
    return out.gradient.allFinite() && out.hessian.allFinite();
  });
}

// The hinge's element (hinge_bending.h) on the rest metric from the closed-form derivatives of θ
// (hinge_angle_derivatives.h) instead of jets: with r = w (φ(θ) − φ̄), ∇r = w φ′ ∇θ and
//
//   ∇E_e = r ∇r,   ∇²E_e = ∇r ∇rᵀ + r w (φ″ ∇θ ∇θᵀ + φ′ ∇²θ);
//
// in height mode the rows and columns of the z's. On the current metric (r also scaled by the
// hinge's metric factor) the jets above. Same contracts as the templates they overload.
bool elementFirstDerivatives(const HingeBendingResidual& residual,
                             const std::vector<const double*>& blocks,
                             const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                             Derivatives derivatives, bool gaussNewton, ElementHessian& out);
bool elementHessian(const HingeBendingResidual& residual, const std::vector<const double*>& blocks,
                    const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                    Derivatives derivatives, ElementHessian& out);

// Exact Hessians of the partially separable elements by the chain rule through their sums: an
// element whose residual is r = g(y) with each intermediate y_m a sum of parts, each part a
// function of a few of the element's unknowns, has
//
//   ∇r = Jᵀ ∇g,   ∇²r = Jᵀ ∇²g J + Σ_m ∂g/∂y_m ∇²y_m,   J = ∂y/∂x,
//
// and each ∇²y_m is the sum of its parts' small blocks: second-order jets of a part's unknowns
// (or a closed form) instead of jets of all the element's. Same results as the templates to
// roundoff; same contracts. Cotan (cotan_element_hessian.cpp): y = (K_v, Σ face normals, and on
// the current metric A_v), sums over the ring's faces of 9 unknowns each. Midedge
// (midedge_element_hessian.cpp): γ_i = θ_i / 2 + σ_i ξ_i, each θ_i a hinge angle of 12 unknowns
// with closed-form derivatives (hinge_angle_derivatives.h); on the rest metric r is affine in γ,
// on the current metric y = (γ, the face's edge tensors and area of 9 unknowns).
bool elementHessian(const CotanMeanCurvatureResidual& residual,
                    const std::vector<const double*>& blocks, const std::vector<int>& sizes,
                    const std::vector<long>& firstUnknown, Derivatives derivatives,
                    ElementHessian& out);
bool elementHessian(const MidedgeResidual& residual, const std::vector<const double*>& blocks,
                    const std::vector<int>& sizes, const std::vector<long>& firstUnknown,
                    Derivatives derivatives, ElementHessian& out);

}  // namespace flexure::curvature
