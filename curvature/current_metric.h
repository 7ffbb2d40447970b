// The current surface's metric, for bending energies that measure curvature in it
// (CurvatureMetric::Current in bending_energy.h) rather than in the rest mesh's: areas, lengths,
// in-plane edge normals and fit matrices become functions of x inside the templated kernels, so
// the energy is a geometric functional of the surface alone and its derivatives (autodiff) include
// the metric's. With flat rest curvature each energy then discretizes ∫ (4H² − 2(1 − ν)K), whose
// critical points are Willmore surfaces (spheres, the Clifford torus): what fairing wants.
//
// Frames: a face's current frame is (u, v, n) with u along x1 − x0, n = (x1 − x0) × (x2 − x0)
// normalized, v = n × u (face_frame.h's convention on the current face). The energies use only
// the invariants of their shape operators, so the frame's choice does not matter.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

#include "curvature/kernel_math.h"
#include "modeling/mixed_area.h"

namespace flexure::curvature {

// A face's current frame: the unit normal and the in-plane axes u, v.
template <class T>
struct CurrentFrame {
  Vec3<T> u, v, normal;
  T area;
};

template <class T>
CurrentFrame<T> currentFrame(const Vec3<T>& x0, const Vec3<T>& x1, const Vec3<T>& x2) {
  const Vec3<T> areaVector = cross(x1 - x0, x2 - x0);
  const T twiceArea = norm(areaVector);
  const Vec3<T> normal = (T(1.0) / twiceArea) * areaVector;
  const Vec3<T> u = (T(1.0) / norm(x1 - x0)) * (x1 - x0);
  return {u, cross(normal, u), normal, T(0.5) * twiceArea};
}

// r_k ← √A_T r_k for the three Koiter residuals (koiter_density.h) of the face x[0], x[1], x[2]:
// on the current metric their weights are made per unit area, and A_T is the current face's.
template <class T>
void scaleByCurrentArea(T const* const* x, T* r) {
  using std::sqrt;
  const T root = sqrt(T(0.5) * norm(cross(load(x[1]) - load(x[0]), load(x[2]) - load(x[0]))));
  for (int k = 0; k < 3; ++k) r[k] = root * r[k];
}

// The secure metric on slivers. Every metric factor of the face energies is a multiple of an
// edge's ℓ_i² / (2 A_T) = cot α_j + cot α_k (α_j, α_k the face's angles at the edge's ends; e.g.
// ℓ_i / A_T = 2 (ℓ_i² / 2A_T) / ℓ_i). On a sliver it grows without bound, as 1 / sin of its
// smallest angle, and with it the curvature read from the sliver's bending angles, whose
// derivatives already grow as 1 / (the sliver's height): the current metric's Hessian grows as the
// square of both. The secure metric caps it at 2 cot α_s, α_s = arccos 0.999 = 2.5626°: the bound
// CGAL's secure cotangent weights put on each cotangent (|cos| ≤ 0.999, CGAL
// Weights/cotangent_weights.h). A face whose angles are all at least α_s keeps its exact metric
// (cot α_j + cot α_k ≤ 2 cot α_s there; its factors are multiplied by exactly 1); on a sliver the
// factor is that of a face of angles α_s at the edge. It does not bound the bending angles' own
// derivatives.
inline constexpr double kSecureAngleDegrees = 2.5626;
// 2 cot α_s, with cot α_s = 0.999 / √(1 − 0.999²) = 22.3439.
inline constexpr double kSecureEdgeFactor = 2.0 * 22.3439;

// min(1, kSecureEdgeFactor / (ℓ² / 2A)): what multiplies the exact ℓ² / (2A) of an edge of
// squared length ℓ² in a face of twice the area 2A.
template <class T>
T secureEdgeScale(const T& squaredLength, const T& twiceArea) {
  const T factor = squaredLength / twiceArea;
  return scalarPart(factor) > kSecureEdgeFactor ? T(kSecureEdgeFactor) / factor : T(1.0);
}

// ℓ_i n̂_i n̂_iᵀ for the edges i = 0, 1, 2 of (x0, x1, x2) (edge i runs x_{i+1} → x_{i+2}), n̂_i its
// outward unit normal in the face's plane, in the current frame. With e_i = (e_u, e_v) in the
// frame, ℓ_i n̂_i = e_i × n = (e_v, −e_u), so ℓ_i n̂_i n̂_iᵀ = (e_v², −e_u e_v, e_u²) / ℓ_i.
// `secure`: times secureEdgeScale, so that (ℓ_i / A_T) n̂_i n̂_iᵀ, the face energies'
// shape-operator tensors, is at most 2 kSecureEdgeFactor / ℓ_i.
template <class T>
std::array<Sym2<T>, 3> currentEdgeTensors(const Vec3<T> (&x)[3], const CurrentFrame<T>& frame,
                                          bool secure = false) {
  std::array<Sym2<T>, 3> tensors;
  for (int i = 0; i < 3; ++i) {
    const Vec3<T> e = x[(i + 2) % 3] - x[(i + 1) % 3];
    const T eu = dot(e, frame.u), ev = dot(e, frame.v);
    const T length = norm(e);
    tensors[i] = {ev * ev / length, T(-1.0) * eu * ev / length, eu * eu / length};
    if (secure) {
      const T scale = secureEdgeScale(dot(e, e), T(2.0) * frame.area);
      tensors[i] = {scale * tensors[i].a, scale * tensors[i].b, scale * tensors[i].c};
    }
  }
  return tensors;
}

// The hinge's metric factor 3 ℓ_e² / (A_f + A_g) at (x_i, x_j, x_k, x_l) (hinge_bending.h).
// `secure`: each face's c = ℓ² / 2A capped at kSecureEdgeFactor, i.e. 3 ℓ² / (A_f + A_g) =
// 6 / (1 / c_f + 1 / c_g) with c → c s, s = secureEdgeScale: 2A → 2A / s in the sum below.
template <class T>
T hingeMetricFactor(const Vec3<T>& xi, const Vec3<T>& xj, const Vec3<T>& xk, const Vec3<T>& xl,
                    bool secure = false) {
  const Vec3<T> e = xj - xi;
  const T squaredLength = dot(e, e);
  // 2A_f + 2A_g = |e × (x_k − x_i)| + |(x_l − x_i) × e|.
  T twiceAreaF = norm(cross(e, xk - xi)), twiceAreaG = norm(cross(xl - xi, e));
  if (secure) {
    twiceAreaF = twiceAreaF / secureEdgeScale(squaredLength, twiceAreaF);
    twiceAreaG = twiceAreaG / secureEdgeScale(squaredLength, twiceAreaG);
  }
  return T(6.0) * squaredLength / (twiceAreaF + twiceAreaG);
}

// The share of the face (x_v, x_a, x_b) in x_v's area, with a = x_a − x_v and b = x_b − x_v:
// mixed Voronoi (modeling/mixed_area.h, the rest state's formula on the current positions) or
// barycentric (a third of the face).
template <class T>
T currentFaceVertexArea(const Vec3<T>& a, const Vec3<T>& b, bool voronoi) {
  const T twiceArea = norm(cross(a, b));
  if (!voronoi) return twiceArea / T(6.0);
  // cot of the angles at the center, at a and at b; squared lengths of the edges opposite them
  // (the center's own share does not read the first).
  const T cotangents[3] = {dot(a, b) / twiceArea, dot(T(-1.0) * a, b - a) / twiceArea,
                           dot(T(-1.0) * b, a - b) / twiceArea};
  const T squaredLengths[3] = {T(0.0), dot(b, b), dot(a, a)};
  return modeling::mixedVoronoiShare(twiceArea, cotangents, squaredLengths, 0);
}

// The area of vertex x[0] with the closed ring x[1..k]: the sum of its faces' shares.
template <class T>
T currentVertexArea(T const* const* x, int k, bool voronoi) {
  const Vec3<T> center = load(x[0]);
  T area(0.0);
  for (int j = 0; j < k; ++j)
    area +=
        currentFaceVertexArea(load(x[1 + j]) - center, load(x[1 + (j + 1) % k]) - center, voronoi);
  return area;
}

}  // namespace flexure::curvature
