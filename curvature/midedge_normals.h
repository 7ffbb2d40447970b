// midedge — the midedge-normal shape operator (Grinspun, Gingold, Reisman, Zorin 2006,
// "Computing discrete shape operators on general meshes"), on every face:
//
//   γ_i = θ_i / 2 + σ_{T,i} ξ_{e(i)},   S_T = Σ_i γ_i ℓ̄_i / Ā_T · n̂_i n̂_iᵀ,
//   E = k_B Σ_T Ā_T Ψ_ν(S_T − S̄_T),
//
// θ_i = 0 on a boundary edge; σ = +1 in the face whose half-edge along e runs from the lower to
// the higher vertex index. γ_i is the signed angle from the midedge normal m_e to the face normal
// n_T about T's direction ê_{T,i} along edge i: with ξ = 0, m_e bisects the hinge; the same m_e
// is seen from both faces, since σ flips with ê.
//
// Blocks: ξ0, ξ1, ξ2 (one double each), x0, x1, x2, then the flap vertices of the interior edges
// in edge order (0 to 3 of them). On the current metric (current_metric.h) ℓ_i, A_T and n̂_i are
// the current face's, ℓ_i / A_T capped on slivers (the secure metric).
#pragma once

#include <array>
#include <cmath>

#include "curvature/bending_angle.h"
#include "curvature/current_metric.h"
#include "curvature/koiter_density.h"

namespace flexure::curvature {

struct MidedgeResidual {
  static constexpr int kResiduals = 3;
  std::array<int, 6> vertices;  // v0, v1, v2, then flapCount flaps
  int flapCount;
  std::array<int, 3> edges;                 // e(i), the ξ block of edge i
  std::array<double, 3> signs;              // σ_{T,i}
  std::array<bool, 3> hasFlap;              // edge i interior
  std::array<Sym2<double>, 3> edgeTensors;  // ℓ̄_i / Ā_T · n̂_i n̂_iᵀ in the rest frame
  Sym2<double> restShapeOperator;           // S̄_T
  KoiterWeights weights;       // make(ν, 2 k_B Ā_T); on the current metric make(ν, 2 k_B)
  bool currentMetric = false;  // ℓ_i / A_T n̂_i n̂_iᵀ and A_T from x
  bool secureMetric = true;    // with the current metric: ℓ_i / A_T capped on slivers

  template <class T>
  Sym2<T> shapeOperator(T const* const* b) const {
    std::array<T, 3> gamma;
    int flap = 6;
    for (int i = 0; i < 3; ++i) {
      T theta(0.0);
      if (hasFlap[i]) {
        theta = bendingAngle(load(b[3 + (i + 1) % 3]), load(b[3 + (i + 2) % 3]), load(b[3 + i]),
                             load(b[flap++]));
      }
      gamma[i] = theta / T(2.0) + signs[i] * b[i][0];
    }
    Sym2<T> s{T(0.0), T(0.0), T(0.0)};
    if (currentMetric) {
      const Vec3<T> face[3] = {load(b[3]), load(b[4]), load(b[5])};
      const CurrentFrame<T> frame = currentFrame(face[0], face[1], face[2]);
      const std::array<Sym2<T>, 3> tensors = currentEdgeTensors(face, frame, secureMetric);
      for (int i = 0; i < 3; ++i) addScaled(s, gamma[i] / frame.area, tensors[i]);
      return s;
    }
    for (int i = 0; i < 3; ++i) addScaled(s, gamma[i], edgeTensors[i]);
    return s;
  }

  template <class T>
  bool operator()(T const* const* b, T* r) const {
    koiterResiduals(shapeOperator(b), restShapeOperator, weights, r);
    if (currentMetric) scaleByCurrentArea(b + 3, r);
    return isFiniteScalar(r[0]) && isFiniteScalar(r[1]) && isFiniteScalar(r[2]);
  }
};

// The ξ of a boundary edge clamped to a surface normal N at its midpoint: the edge's only face T
// sees it from the side x_a → x_b (a = v_{i+1}, b = v_{i+2}), with sign σ; γ = signed angle from
// N to n_T about ê, and ξ = σ γ since θ = 0 on the boundary.
template <class T>
T clampedBoundaryXi(const Vec3<T>& xa, const Vec3<T>& xb, const Vec3<T>& xOpposite,
                    const Vec3<T>& surfaceNormal, double sign) {
  using std::atan2;
  const Vec3<T> e = xb - xa;
  const Vec3<T> faceNormal = cross(e, xOpposite - xa);
  const T gamma =
      atan2(dot(cross(surfaceNormal, faceNormal), e) / norm(e), dot(surfaceNormal, faceNormal));
  return sign * gamma;
}

}  // namespace flexure::curvature
