// quadfit — the triangle quadratic fit (slides, seed 000), on faces whose three edges are interior.
// In the rest face's frame (u, v) with origin at the rest centroid, fit
//
//   h(u, v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²
//
// through the heights h_k = (x_k − c_T) · n_T of the six stencil points over the current face
// plane (c_T current centroid, n_T current unit normal). S_T = [[2c3, c4], [c4, 2c5]],
// E = k_B Σ_T Ā_T Ψ_ν(S_T − S̄_T). The 6 × 6 fit matrix depends only on the rest mesh; its
// inverse's rows 3, 4, 5 (which give c3, c4, c5) are precomputed. Blocks: x0, x1, x2, f0, f1, f2.
// On the current metric (current_metric.h) the fit is made in the current face's frame (u, v)
// and solved in every evaluation, and A_T is the current face's.
#pragma once

#include <array>

#include "curvature/current_metric.h"
#include "curvature/koiter_density.h"

namespace flexure::curvature {

struct QuadraticFitResidual {
  static constexpr int kResiduals = 3;
  std::array<int, 6> vertices;                   // v0, v1, v2, f0, f1, f2
  std::array<std::array<double, 6>, 3> fitRows;  // (c3, c4, c5) = fitRows · h
  Sym2<double> restShapeOperator;                // S̄_T
  KoiterWeights weights;       // make(ν, 2 k_B Ā_T); on the current metric make(ν, 2 k_B)
  bool currentMetric = false;  // the fit in the current frame, A_T from x

  template <class T>
  Sym2<T> shapeOperator(T const* const* x) const {
    const Vec3<T> x0 = load(x[0]), x1 = load(x[1]), x2 = load(x[2]);
    const Vec3<T> centroid = T(1.0 / 3.0) * (x0 + x1 + x2);
    Vec3<T> normal = cross(x1 - x0, x2 - x0);
    normal = (T(1.0) / norm(normal)) * normal;
    std::array<T, 6> heights;
    for (int k = 0; k < 6; ++k) heights[k] = dot(load(x[k]) - centroid, normal);
    T c[3] = {T(0.0), T(0.0), T(0.0)};
    if (currentMetric) {
      const CurrentFrame<T> frame = currentFrame(x0, x1, x2);
      // Rows [1, u, v, u², uv, v²] in units of the face size √A (bending_energy.cpp's fit), so
      // c3, c4, c5 carry a factor 1/A.
      using std::sqrt;
      const T unit = sqrt(frame.area);
      std::array<std::array<T, 6>, 6> fit;
      for (int k = 0; k < 6; ++k) {
        const Vec3<T> p = load(x[k]) - centroid;
        const T u = dot(p, frame.u) / unit, v = dot(p, frame.v) / unit;
        fit[k] = {T(1.0), u, v, u * u, u * v, v * v};
      }
      if (!solveSmallSystem(fit, heights)) heights.fill(T(std::nan("")));
      for (int row = 0; row < 3; ++row) c[row] = heights[3 + row] / frame.area;
    } else {
      for (int k = 0; k < 6; ++k)
        for (int row = 0; row < 3; ++row) c[row] += fitRows[row][k] * heights[k];
    }
    return {T(2.0) * c[0], c[1], T(2.0) * c[2]};
  }

  template <class T>
  bool operator()(T const* const* x, T* r) const {
    koiterResiduals(shapeOperator(x), restShapeOperator, weights, r);
    if (currentMetric) scaleByCurrentArea(x, r);
    return isFiniteScalar(r[0]) && isFiniteScalar(r[1]) && isFiniteScalar(r[2]);
  }
};

}  // namespace flexure::curvature
