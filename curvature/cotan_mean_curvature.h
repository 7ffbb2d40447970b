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

// K_v · n_v for the vertex x[0] with the closed counter-clockwise ring x[1..k].
template <class T>
T cotanMeanCurvatureNormal(T const* const* x, int k) {
  const Vec3<T> center = load(x[0]);
  Vec3<T> laplacian{T(0.0), T(0.0), T(0.0)}, normal{T(0.0), T(0.0), T(0.0)};
  for (int j = 0; j < k; ++j) {
    const Vec3<T> a = load(x[1 + j]) - center, b = load(x[1 + (j + 1) % k]) - center;
    const Vec3<T> faceNormal = cross(a, b);
    const T twiceArea = norm(faceNormal);
    // cot∠b = (−b)·(a − b) / |…|, cot∠a = (−a)·(b − a) / |…|, with |(a − b) × b| = |a × b| = 2A.
    const T cotB = dot(T(-1.0) * b, a - b) / twiceArea;
    const T cotA = dot(T(-1.0) * a, b - a) / twiceArea;
    laplacian = laplacian + T(0.5) * (cotB * a + cotA * b);
    normal = normal + faceNormal;
  }
  return dot(laplacian, normal) / norm(normal);
}

struct CotanMeanCurvatureResidual {
  static constexpr int kResiduals = 1;
  std::vector<int> vertices;   // v, then its ring counter-clockwise
  double sqrtWeight;           // √(2 k_B / Ā_v); on the current metric √(2 k_B)
  double restValue;            // K̄_v · n̄_v
  bool currentMetric = false;  // A_v from x
  bool voronoiArea = true;     // the current A_v mixed Voronoi (else barycentric)

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    using std::sqrt;
    const int ring = static_cast<int>(vertices.size()) - 1;
    r[0] = sqrtWeight * (cotanMeanCurvatureNormal(x, ring) - T(restValue));
    if (currentMetric) r[0] = r[0] / sqrt(currentVertexArea(x, ring, voronoiArea));
    return isFiniteScalar(r[0]);
  }
};

}  // namespace flexure::curvature
