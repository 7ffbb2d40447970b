// quadfit — the triangle quadratic fit (slides, seed 000), on faces whose three edges are interior.
// In the rest face's frame (u, v) with origin at the rest centroid, fit
//
//   h(u, v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²
//
// through the heights h_k = (x_k − c_T) · n_T of the six stencil points over the current face
// plane (c_T current centroid, n_T current unit normal). S_T = [[2c3, c4], [c4, 2c5]],
// E = k_B Σ_T Ā_T Ψ_ν(S_T − S̄_T). The 6 × 6 fit matrix depends only on the rest mesh; its
// inverse's rows 3, 4, 5 (which give c3, c4, c5) are precomputed. Blocks: x0, x1, x2, f0, f1, f2.
// On the current metric (current_metric.h) the same fit matrix is made in the current face's
// frame (u, v) and solved in every evaluation, and A_T is the current face's.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

#include "curvature/current_metric.h"
#include "curvature/koiter_density.h"

namespace flexure::curvature {

// A pivot below this fraction of the first (the fit matrix's largest entry) means the six points
// admit no unique quadratic: they lie on a conic.
inline constexpr double kQuadraticFitPivotRatio = 1e-9;

// The fit's 6 × 6 matrix in the frame (u, v) of the face x[0], x[1], x[2], origin at `centroid`:
// row k is [1, u, v, u², uv, v²] at stencil point x[k], with (u, v) in units of the face size
// `unit` = √A so that the singularity test is scale-free (c3, c4, c5 then carry a factor 1/A).
// Evaluated once on the rest positions (the rest fit) and in every evaluation on the current
// metric.
template <class T>
std::array<std::array<T, 6>, 6> quadraticFitMatrix(T const* const* x, const Vec3<T>& centroid,
                                                   const CurrentFrame<T>& frame, const T& unit) {
  std::array<std::array<T, 6>, 6> fit;
  for (int k = 0; k < 6; ++k) {
    const Vec3<T> p = load(x[k]) - centroid;
    const T u = dot(p, frame.u) / unit, v = dot(p, frame.v) / unit;
    fit[k] = {T(1.0), u, v, u * u, u * v, v * v};
  }
  return fit;
}

// Solves fit · y = rhs for k right-hand sides (fit overwritten, y returned in rhs) by Gaussian
// elimination with full pivoting on the values. Returns false when a pivot falls to
// kQuadraticFitPivotRatio of the first: the stencil is singular.
template <class T, std::size_t k>
bool solveQuadraticFit(std::array<std::array<T, 6>, 6>& fit, std::array<std::array<T, k>, 6>& rhs) {
  std::array<int, 6> unknownAt = {0, 1, 2, 3, 4, 5};  // column j holds unknown unknownAt[j]
  double first = 0.0;
  for (int col = 0; col < 6; ++col) {
    int pivotRow = col, pivotColumn = col;
    double largest = -1.0;
    for (int row = col; row < 6; ++row) {
      for (int c = col; c < 6; ++c) {
        const double size = std::abs(scalarPart(fit[row][c]));
        if (size > largest) {
          largest = size;
          pivotRow = row;
          pivotColumn = c;
        }
      }
    }
    if (col == 0) first = largest;
    if (!(largest > kQuadraticFitPivotRatio * first)) return false;
    std::swap(fit[col], fit[pivotRow]);
    std::swap(rhs[col], rhs[pivotRow]);
    for (auto& row : fit) std::swap(row[col], row[pivotColumn]);
    std::swap(unknownAt[col], unknownAt[pivotColumn]);
    for (int row = col + 1; row < 6; ++row) {
      const T factor = fit[row][col] / fit[col][col];
      for (int c = col + 1; c < 6; ++c) fit[row][c] -= factor * fit[col][c];
      for (std::size_t j = 0; j < k; ++j) rhs[row][j] -= factor * rhs[col][j];
    }
  }
  for (int row = 5; row >= 0; --row) {
    for (int c = row + 1; c < 6; ++c)
      for (std::size_t j = 0; j < k; ++j) rhs[row][j] -= fit[row][c] * rhs[c][j];
    for (std::size_t j = 0; j < k; ++j) rhs[row][j] = rhs[row][j] / fit[row][row];
  }
  std::array<std::array<T, k>, 6> y;
  for (int j = 0; j < 6; ++j) y[unknownAt[j]] = rhs[j];
  rhs = y;
  return true;
}

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
      using std::sqrt;
      std::array<std::array<T, 6>, 6> fit =
          quadraticFitMatrix(x, centroid, frame, sqrt(frame.area));
      std::array<std::array<T, 1>, 6> solution;
      for (int k = 0; k < 6; ++k) solution[k][0] = heights[k];
      if (!solveQuadraticFit(fit, solution))
        for (auto& value : solution) value[0] = T(std::nan(""));
      for (int row = 0; row < 3; ++row) c[row] = solution[3 + row][0] / frame.area;
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
