// triavg — the triangle-averaged shape operator (Gingold, Secord, Han, Grinspun, Zorin 2004;
// seed 002), on faces whose three edges are interior:
//
//   S_T = Σ_i φ_i ℓ̄_i / (2 Ā_T) · n̂_i n̂_iᵀ,   φ_i = 2 tan(θ_i / 2),   E = k_B Σ_T Ā_T Ψ_ν(S_T −
//   S̄_T),
//
// θ_i the bending angle across edge i (opposite vertex i), n̂_i the rest in-plane outward normal
// of edge i. Blocks: x0, x1, x2, then the flap vertices f0, f1, f2 across edges 0, 1, 2.
#pragma once

#include <array>

#include "curvature/bending_angle.h"
#include "curvature/koiter_density.h"

namespace flexure::curvature {

struct TriangleAveragedResidual {
  static constexpr int kResiduals = 3;
  std::array<int, 6> vertices;              // v0, v1, v2, f0, f1, f2
  std::array<Sym2<double>, 3> edgeTensors;  // ℓ̄_i / (2 Ā_T) · n̂_i n̂_iᵀ in the rest frame
  Sym2<double> restShapeOperator;           // S̄_T
  KoiterWeights weights;                    // make(ν, 2 k_B Ā_T)

  template <class T>
  Sym2<T> shapeOperator(T const* const* x) const {
    Sym2<T> s{T(0.0), T(0.0), T(0.0)};
    for (int i = 0; i < 3; ++i) {
      // Edge i runs v_{i+1} → v_{i+2} in T = (v_{i+1}, v_{i+2}, v_i); the flap closes g.
      const T theta =
          bendingAngle(load(x[(i + 1) % 3]), load(x[(i + 2) % 3]), load(x[i]), load(x[3 + i]));
      const T phi = hingeAngleMeasure(theta, HingeAngle::Tan);
      s.a += phi * edgeTensors[i].a;
      s.b += phi * edgeTensors[i].b;
      s.c += phi * edgeTensors[i].c;
    }
    return s;
  }

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    koiterResiduals(shapeOperator(x), restShapeOperator, weights, r);
    return isFiniteScalar(r[0]) && isFiniteScalar(r[1]) && isFiniteScalar(r[2]);
  }
};

}  // namespace flexure::curvature
