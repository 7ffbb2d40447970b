// cotan — vertex-averaged cotangent mean curvature (Meyer, Desbrun, Schröder, Barr 2003; slides
// "vertex-averaged"), on every interior vertex v with its counter-clockwise one-ring x_1 .. x_k:
//
//   K_v = ½ Σ_j (cot α_vj + cot β_vj)(x_j − x_v)     (current cotangents; K_v ≈ 2H n Ā_v),
//   n_v = normalized Σ of the unnormalized face normals (x_j − x_v) × (x_{j+1} − x_v),
//   E = k_B Σ_v (K_v · n_v − K̄_v · n̄_v)² / Ā_v.
//
// Face (v, a, b) adds ½ cot∠b (x_a − x_v) + ½ cot∠a (x_b − x_v): the angle at b is opposite the
// edge (v, a). One residual r = √(2 k_B / Ā_v) (K_v·n_v − K̄_v·n̄_v). Blocks: x_v, x_1, …, x_k.
// On the current metric (current_metric.h) the vertex area A_v is the current ring's.
#pragma once

#include <vector>

#include "curvature/current_metric.h"
#include "curvature/kernel_math.h"

namespace flexure::curvature {

// Face (v, a, b)'s terms of the two sums, with a = x_a − x_v and b = x_b − x_v:
// ½ (cot∠b a + cot∠a b) of K_v, and the unnormalized face normal a × b of n_v.
template <class T>
struct CotanFaceTerms {
  Vec3<T> laplacian, normal;
};
template <class T>
CotanFaceTerms<T> cotanFaceTerms(const Vec3<T>& a, const Vec3<T>& b) {
  const Vec3<T> faceNormal = cross(a, b);
  const T twiceArea = norm(faceNormal);
  // cot∠b = (−b)·(a − b) / |…|, cot∠a = (−a)·(b − a) / |…|, with |(a − b) × b| = |a × b| = 2A.
  const T cotB = dot(T(-1.0) * b, a - b) / twiceArea;
  const T cotA = dot(T(-1.0) * a, b - a) / twiceArea;
  return {T(0.5) * (cotB * a + cotA * b), faceNormal};
}

// K_v · n_v from the sums K_v and Σ_j (x_j − x_v) × (x_{j+1} − x_v).
template <class T>
T curvatureNormalOfSums(const Vec3<T>& laplacian, const Vec3<T>& normal) {
  return dot(laplacian, normal) / norm(normal);
}

// K_v · n_v for the vertex x[0] with the closed counter-clockwise ring x[1..k].
template <class T>
T cotanMeanCurvatureNormal(T const* const* x, int k) {
  const Vec3<T> center = load(x[0]);
  Vec3<T> laplacian{T(0.0), T(0.0), T(0.0)}, normal{T(0.0), T(0.0), T(0.0)};
  for (int j = 0; j < k; ++j) {
    const CotanFaceTerms<T> face =
        cotanFaceTerms(load(x[1 + j]) - center, load(x[1 + (j + 1) % k]) - center);
    laplacian = laplacian + face.laplacian;
    normal = normal + face.normal;
  }
  return curvatureNormalOfSums(laplacian, normal);
}

struct CotanMeanCurvatureResidual {
  static constexpr int kResiduals = 1;
  std::vector<int> vertices;   // v, then its ring counter-clockwise
  double sqrtWeight;           // √(2 k_B / Ā_v); on the current metric √(2 k_B)
  double restValue;            // K̄_v · n̄_v
  bool currentMetric = false;  // A_v from x
  bool voronoiArea = true;     // the current A_v mixed Voronoi (else barycentric)

  // r from K_v · n_v and (current metric) the current A_v.
  template <class T>
  T residualOf(const T& curvatureNormal, const T& currentArea) const {
    using std::sqrt;
    const T r = sqrtWeight * (curvatureNormal - T(restValue));
    return currentMetric ? r / sqrt(currentArea) : r;
  }

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    const int ring = static_cast<int>(vertices.size()) - 1;
    const T curvatureNormal = cotanMeanCurvatureNormal(x, ring);
    r[0] = residualOf(curvatureNormal,
                      currentMetric ? currentVertexArea(x, ring, voronoiArea) : T(1.0));
    return isFiniteScalar(r[0]);
  }
};

}  // namespace flexure::curvature
