// Membrane energies, for solves that move x and y (bending alone has no stiffness against
// in-plane sliding). All vanish, with their gradients, at rest.
//
// stvk — plane-stress St. Venant–Kirchhoff: with F the 3×2 deformation gradient of the affine map
// from the rest triangle (in its 2D frame) to the current one and ε = ½(FᵀF − I) the Green strain,
//
//   E = Y / (2 (1 − ν²)) Σ_T Ā_T Ψ_ν(ε_T),
//
// Y Young's modulus times thickness, ν Poisson's ratio (Ψ_ν as for bending).
//
// springs — Discrete Shells' membrane (Grinspun et al. 2003; seed 001), edge and area springs:
//
//   E = k_L Σ_e (ℓ_e − ℓ̄_e)² / ℓ̄_e + k_A Σ_T (A_T − Ā_T)² / Ā_T
//
// (the seed's ½ dropped, as for every energy in docs/energies.md).
//
// conformal — each triangle's change of shape, not of size: with C = FᵀF (F as for stvk),
//
//   q_T = ((C₁₁ − C₂₂)² + 4 C₁₂²) / (C₁₁ + C₂₂)² = 1 − 4 det C / (tr C)²  ∈ [0, 1),
//   E = k_S Σ_T q_T,
//
// q_T = 0 exactly when the triangle is similar to its rest shape (F a rotation times a scale) and
// → 1 as it collapses. Dimensionless and unchanged by scaling the mesh: a surface may shrink or
// grow under it, as fairing needs, while its triangles keep their angles.
//
// mips — the same change of shape measured as a barrier: with λ₁, λ₂ the eigenvalues of C,
//
//   p_T = ((C₁₁ − C₂₂)² + 4 C₁₂²) / (4 det C) = (λ₁ − λ₂)² / (4 λ₁ λ₂) = q_T / (1 − q_T),
//   E = k_S Σ_T p_T,
//
// = ¼ (σ₁/σ₂ − σ₂/σ₁)² = ¼ (M² − 4), M = σ₁/σ₂ + σ₂/σ₁ the MIPS energy of Hormann & Greiner
// (2000), σᵢ = √λᵢ the singular values of F. Equal to q_T to second order at rest, but → ∞ as the
// triangle collapses (det C → 0): no solve that decreases E can make a triangle degenerate, so its
// angles stay away from 0 — the angle barrier fairing uses to keep triangle quality.
#pragma once

#include <array>

#include "curvature/koiter_density.h"

namespace flexure::curvature {

// C = FᵀF, as (C₁₁, C₁₂, C₂₂), of the affine map from the rest triangle (rest edge matrix D̄ = [ū1 −
// ū0, ū2 − ū0] in its 2D frame, `restEdgeInverse` = D̄⁻¹ row-major) to the current one x[0..2]: the
// columns of F = [x1 − x0, x2 − x0] D̄⁻¹.
template <class T>
Sym2<T> rightCauchyGreen(T const* const* x, const std::array<double, 4>& m) {
  const Vec3<T> x0 = load(x[0]), e1 = load(x[1]) - x0, e2 = load(x[2]) - x0;
  const Vec3<T> fu = m[0] * e1 + m[2] * e2;
  const Vec3<T> fv = m[1] * e1 + m[3] * e2;
  return {dot(fu, fu), dot(fu, fv), dot(fv, fv)};
}

struct StvkMembraneResidual {
  static constexpr int kResiduals = 3;
  std::array<int, 3> vertices;
  std::array<double, 4> restEdgeInverse;  // D̄⁻¹ row-major, D̄ = [ū1 − ū0, ū2 − ū0] (2 × 2)
  KoiterWeights weights;                  // make(ν, 2 Y/(2(1 − ν²)) Ā_T)
  // P_T, the plastic rest strain (energy_term.h, RestMetricState): Ψ_ν reads ε − P_T.
  Sym2<double> restStrain{0.0, 0.0, 0.0};

  // The Green strain ε = ½(FᵀF − I) in the rest frame.
  template <class T>
  Sym2<T> strain(T const* const* x) const {
    const Sym2<T> g = rightCauchyGreen(x, restEdgeInverse);  // (C₁₁, C₁₂, C₂₂)
    return {T(0.5) * (g.a - T(1.0)), T(0.5) * g.b, T(0.5) * (g.c - T(1.0))};
  }

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    koiterResiduals(strain(x), restStrain, weights, r);
    return true;
  }
};

// conformal and mips: r = √(2 k_S) (C₁₁ − C₂₂, 2 C₁₂) / d with d = tr C (q_T) or 2 √det C (p_T).
struct ConformalMembraneResidual {
  static constexpr int kResiduals = 2;
  std::array<int, 3> vertices;
  std::array<double, 4> restEdgeInverse;  // D̄⁻¹ row-major, as for stvk
  double sqrtWeight;                      // √(2 k_S): ½ |r|² = k_S q_T (or k_S p_T)
  bool barrier = false;                   // mips: p_T

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    const Sym2<T> g = rightCauchyGreen(x, restEdgeInverse);  // (C₁₁, C₁₂, C₂₂)
    using std::sqrt;
    const T d = barrier ? T(2.0) * sqrt(g.a * g.c - g.b * g.b) : g.a + g.c;
    r[0] = sqrtWeight * (g.a - g.c) / d;
    r[1] = sqrtWeight * T(2.0) * g.b / d;
    return isFiniteScalar(r[0]) && isFiniteScalar(r[1]);
  }
};

// The log barrier's residual at distance d from the limit: r = √(2κ) (d̂ − d) √(−log(d / d̂)) for
// 0 < d < d̂, 0 for d ≥ d̂, so that ½ r² = b(d) = −κ (d − d̂)² log(d / d̂) (the barrier of Li et al.
// 2020, "Incremental Potential Contact"); false for d ≤ 0 (infeasible). Shared by the angle
// barrier below and the dihedral barrier (dihedral_barrier.h).
template <class T>
bool logBarrierResidual(const T& d, double band, double sqrtWeight, T& r) {
  using std::log;
  using std::sqrt;
  if (!(scalarPart(d) > 0.0)) return false;
  r = scalarPart(d) < band ? sqrtWeight * (T(band) - d) * sqrt(-log(d / T(band))) : T(0.0);
  return true;
}

// angle barrier — a floor under a triangle's angles (fairing's triangle-quality rule): for each
// corner angle α of the face, with d = α − α_min and a band d̂,
//
//   b(α) = −κ (d − d̂)² log(d / d̂)   for 0 < d < d̂,   0 for d ≥ d̂,
//
// the smooth log barrier of incremental-potential contact (Li et al. 2020) on the angle: C² at
// d = d̂ where it switches on, +∞ as α → α_min. A solve that never raises its energy (every line
// search here) keeps every angle above α_min. Residual r = √(2κ) (d̂ − d) √(−log(d / d̂)), ½ r² = b;
// d ≤ 0 is infeasible (evaluation fails, the line search backs off).
struct AngleBarrierResidual {
  static constexpr int kResiduals = 3;
  std::array<int, 3> vertices;
  double sqrtWeight;  // √(2κ)
  double minAngle;    // α_min, radians
  double band;        // d̂, radians

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    const Vec3<T> p[3] = {load(x[0]), load(x[1]), load(x[2])};
    for (int i = 0; i < 3; ++i) {
      const Vec3<T> a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
      if (!logBarrierResidual(angleBetween(a, b) - T(minAngle), band, sqrtWeight, r[i]))
        return false;
    }
    return true;
  }
};

struct EdgeSpringResidual {
  static constexpr int kResiduals = 1;
  std::array<int, 2> vertices;
  double sqrtWeight;  // √(2 k_L / ℓ̄_e)
  double restLength;  // ℓ̄_e

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    r[0] = sqrtWeight * (norm(load(x[1]) - load(x[0])) - T(restLength));
    return isFiniteScalar(r[0]);
  }
};

struct AreaSpringResidual {
  static constexpr int kResiduals = 1;
  std::array<int, 3> vertices;
  double sqrtWeight;  // √(2 k_A / Ā_T)
  double restArea;    // Ā_T

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    const Vec3<T> x0 = load(x[0]);
    r[0] = sqrtWeight * (T(0.5) * norm(cross(load(x[1]) - x0, load(x[2]) - x0)) - T(restArea));
    return isFiniteScalar(r[0]);
  }
};

}  // namespace flexure::curvature
