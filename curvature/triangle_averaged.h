// triavg — the triangle-averaged shape operator (Gingold, Secord, Han, Grinspun, Zorin 2004;
// seed 002), on faces whose three edges are interior:
//
//   S_T = Σ_i φ_i ℓ̄_i / (2 Ā_T) · n̂_i n̂_iᵀ,   φ_i = 2 tan(θ_i / 2),   E = k_B Σ_T Ā_T Ψ_ν(S_T −
//   S̄_T),
//
// θ_i the bending angle across edge i (opposite vertex i), n̂_i the rest in-plane outward normal
// of edge i. Blocks: x0, x1, x2, then the flap vertices f0, f1, f2 across edges 0, 1, 2. On the
// current metric (current_metric.h) ℓ_i, A_T and n̂_i are the current face's.
#pragma once

#include <array>

#include "curvature/bending_angle.h"
#include "curvature/current_metric.h"
#include "curvature/koiter_density.h"

namespace flexure::curvature {

struct TriangleAveragedResidual {
  static constexpr int kResiduals = 3;
  std::array<int, 6> vertices;              // v0, v1, v2, f0, f1, f2
  std::array<Sym2<double>, 3> edgeTensors;  // ℓ̄_i / (2 Ā_T) · n̂_i n̂_iᵀ in the rest frame
  Sym2<double> restShapeOperator;           // S̄_T
  KoiterWeights weights;       // make(ν, 2 k_B Ā_T); on the current metric make(ν, 2 k_B)
  bool currentMetric = false;  // ℓ_i / (2 A_T) n̂_i n̂_iᵀ and A_T from x
  bool secureMetric = true;    // with the current metric: ℓ_i / A_T capped on slivers

  // φ_i, the measure of the bending angle across edge i.
  template <class T>
  T edgeMeasure(T const* const* x, int i) const {
    // Edge i runs v_{i+1} → v_{i+2} in T = (v_{i+1}, v_{i+2}, v_i); the flap closes g.
    const T theta =
        bendingAngle(load(x[(i + 1) % 3]), load(x[(i + 2) % 3]), load(x[i]), load(x[3 + i]));
    return hingeAngleMeasure(theta, HingeAngle::Tan);
  }

  template <class T>
  Sym2<T> shapeOperator(T const* const* x) const {
    Sym2<T> s{T(0.0), T(0.0), T(0.0)};
    if (currentMetric) {
      const Vec3<T> face[3] = {load(x[0]), load(x[1]), load(x[2])};
      const CurrentFrame<T> frame = currentFrame(face[0], face[1], face[2]);
      const std::array<Sym2<T>, 3> tensors = currentEdgeTensors(face, frame, secureMetric);
      for (int i = 0; i < 3; ++i)
        addScaled(s, edgeMeasure(x, i) / (T(2.0) * frame.area), tensors[i]);
      return s;
    }
    for (int i = 0; i < 3; ++i) addScaled(s, edgeMeasure(x, i), edgeTensors[i]);
    return s;
  }

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    koiterResiduals(shapeOperator(x), restShapeOperator, weights, r);
    if (currentMetric) scaleByCurrentArea(x, r);
    return isFiniteScalar(r[0]) && isFiniteScalar(r[1]) && isFiniteScalar(r[2]);
  }
};

}  // namespace flexure::curvature
