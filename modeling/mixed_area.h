// The mixed Voronoi area of a vertex (Meyer, Desbrun, Schröder & Barr 2003, "Discrete
// differential-geometry operators for triangulated 2-manifolds", §3.4), one triangle's share at a
// time. Templated on the scalar: the rest state (rest_state.h) evaluates it on doubles, the
// current-metric kernels (curvature/current_metric.h) on automatic-differentiation numbers.
#pragma once

namespace flexure::modeling {

// The value of a scalar: itself for a double, the value part `a` of an automatic-differentiation
// number (ceres::Jet, curvature::SecondOrderJet).
inline double scalarPart(double v) {
  return v;
}
template <class J>
inline auto scalarPart(const J& v) -> decltype(v.a) {
  return v.a;
}

// The share of triangle (x_0, x_1, x_2)'s area that its corner i contributes to x_i's mixed
// Voronoi area. With 2A = `twiceArea`, cot_j = `cotangents[j]` the cotangent of the angle at
// corner j and ℓ_j² = `squaredLengths[j]` the squared length of the edge opposite corner j:
//   non-obtuse triangle: (ℓ_{i+1}² cot_{i+1} + ℓ_{i+2}² cot_{i+2}) / 8, corner i's Voronoi region;
//   obtuse triangle: A/2 at the obtuse corner, A/4 at the other two.
// The three shares sum to A.
template <class T>
T mixedVoronoiShare(const T& twiceArea, const T (&cotangents)[3], const T (&squaredLengths)[3],
                    int i) {
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  if (scalarPart(cotangents[0]) < 0.0 || scalarPart(cotangents[1]) < 0.0 ||
      scalarPart(cotangents[2]) < 0.0) {
    return scalarPart(cotangents[i]) < 0.0 ? twiceArea / T(4.0) : twiceArea / T(8.0);
  }
  return (squaredLengths[j] * cotangents[j] + squaredLengths[k] * cotangents[k]) / T(8.0);
}

}  // namespace flexure::modeling
