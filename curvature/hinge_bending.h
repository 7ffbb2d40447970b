// hinge — Discrete Shells (Grinspun, Hirani, Desbrun, Schröder 2003; seeds 000, 003):
//
//   E = k_B Σ_{interior e} (φ(θ_e) − φ(θ̄_e))² · 3 ℓ̄_e² / (Ā_f + Ā_g),
//
// φ(θ) = θ or 2 tan(θ/2) (BendingOptions.hingeAngle). 3ℓ̄²/(Ā_f + Ā_g) is ℓ̄/h̄ with h̄ a third of the
// mean of the two triangle heights on e. One residual per hinge: r = √(2 k_B 3ℓ̄²/(Ā_f + Ā_g)) (φ −
// φ̄). On the current metric (current_metric.h) the factor 3ℓ²/(A_f + A_g) is the current hinge's.
#pragma once

#include <array>

#include "curvature/bending_angle.h"
#include "curvature/current_metric.h"

namespace flexure::curvature {

struct HingeBendingResidual {
  static constexpr int kResiduals = 1;
  std::array<int, 4> vertices;  // (i, j, k, l): blocks 0..3, each x, y, z
  double sqrtWeight;   // √(2 k_B 3 ℓ̄² / (Ā_f + Ā_g)); on the current metric √(2 k_B)
  double restMeasure;  // φ(θ̄_e)
  HingeAngle measure;
  bool currentMetric = false;  // the factor 3ℓ²/(A_f + A_g) from x
  bool secureMetric = true;    // with the current metric: the factor capped on slivers

  template <class T>
  T angle(T const* const* x) const {
    return bendingAngle(load(x[0]), load(x[1]), load(x[2]), load(x[3]));
  }

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    using std::sqrt;
    r[0] = sqrtWeight * (hingeAngleMeasure(angle(x), measure) - T(restMeasure));
    if (currentMetric)
      r[0] = r[0] *
             sqrt(hingeMetricFactor(load(x[0]), load(x[1]), load(x[2]), load(x[3]), secureMetric));
    return isFiniteScalar(r[0]);
  }
};

}  // namespace flexure::curvature
