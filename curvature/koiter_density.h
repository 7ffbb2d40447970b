// The Koiter bending density Ψ_ν(M) = (1 − ν) tr(M²) + ν (tr M)² of docs/energies.md, as a sum of
// squares so that a Ceres residual can carry it. For M = [[a, b], [b, c]]:
//
//   Ψ_ν(M) = (1 − ν) [ (a − c)²/2 + 2 b² ] + (1 + ν)/2 · (a + c)²,
//
// non-negative for −1 ≤ ν ≤ 1 (ν = 1: the mean-curvature density (a + c)², ν = 0: Frobenius).
#pragma once

#include <cmath>

#include "curvature/kernel_math.h"

namespace flexure::curvature {

// The three weights w such that Σ_k (w_k m_k)² = scale · Ψ_ν(M), m = (a − c, b, a + c).
struct KoiterWeights {
  double deviator;  // on (a − c)
  double twist;     // on b
  double trace;     // on (a + c)

  // For residuals r with ½ Σ r² = scale · Ψ_ν: pass scale = 2 k_B Ā.
  static KoiterWeights make(double poisson, double scale) {
    return {std::sqrt(scale * (1.0 - poisson) / 2.0), std::sqrt(scale * 2.0 * (1.0 - poisson)),
            std::sqrt(scale * (1.0 + poisson) / 2.0)};
  }
};

// Residuals r (3 values) of M = S − S̄ with ½ Σ r² = k_B Ā Ψ_ν(S − S̄) when w = make(ν, 2 k_B Ā).
template <class T>
void koiterResiduals(const Sym2<T>& s, const Sym2<double>& rest, const KoiterWeights& w, T* r) {
  const T a = s.a - rest.a, b = s.b - rest.b, c = s.c - rest.c;
  r[0] = w.deviator * (a - c);
  r[1] = w.twist * b;
  r[2] = w.trace * (a + c);
}

inline double koiterDensity(const Sym2<double>& m, double poisson) {
  const double trace = m.a + m.c;
  return (1.0 - poisson) * (m.a * m.a + 2.0 * m.b * m.b + m.c * m.c) + poisson * trace * trace;
}

}  // namespace flexure::curvature
