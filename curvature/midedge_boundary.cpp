#include "curvature/midedge_boundary.h"

#include <ceres/jet.h>

#include "curvature/midedge_normals.h"

namespace flexure::curvature {
namespace {

using Dual = ceres::Jet<double, 1>;

// The amplitude ε: 1 for the nonlinear clamp, the infinitesimal for its linearization; and what
// the caller wants of ξ: its value, or its derivative in ε.
template <class T>
T amplitude();
template <>
double amplitude<double>() {
  return 1.0;
}
template <>
Dual amplitude<Dual>() {
  return Dual(0.0, 0);
}
double wanted(double value) {
  return value;
}
double wanted(const Dual& value) {
  return value.v[0];
}

// ξ of every boundary edge at positions base + ε δ against the surface ε p (see amplitude()).
template <class T>
Eigen::VectorXd boundaryXi(const modeling::Stencils& s, const modeling::Positions& base,
                           const modeling::Positions* delta, const modeling::PolynomialSurface& p) {
  Eigen::VectorXd xi = Eigen::VectorXd::Zero(s.edgeCount());
  const T epsilon = amplitude<T>();
  const auto point = [&](int v) {
    Vec3<T> x{T(base(v, 0)), T(base(v, 1)), T(base(v, 2))};
    if (delta)
      x = x +
          epsilon * Vec3<T>{T(delta->coeff(v, 0)), T(delta->coeff(v, 1)), T(delta->coeff(v, 2))};
    return x;
  };
  for (int f = 0; f < s.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      if (s.faceFlaps(f, i) >= 0) continue;
      const Vec3<T> xa = point(s.faces(f, (i + 1) % 3)), xb = point(s.faces(f, (i + 2) % 3));
      const Vec3<T> xc = point(s.faces(f, i));
      // The surface's slope at the midpoint's rest (x, y): its normal (−ε p_x, −ε p_y, 1)/|…|.
      const Eigen::Vector2d slope = p.gradient(0.5 * (scalarPart(xa.x) + scalarPart(xb.x)),
                                               0.5 * (scalarPart(xa.y) + scalarPart(xb.y)));
      Vec3<T> normal{-epsilon * slope.x(), -epsilon * slope.y(), T(1.0)};
      normal = (T(1.0) / norm(normal)) * normal;
      const T value = clampedBoundaryXi(xa, xb, xc, normal, s.faceEdgeSigns(f, i));
      xi[s.faceEdges(f, i)] = wanted(value);
    }
  }
  return xi;
}

}  // namespace

Eigen::VectorXd clampedBoundaryXi(const modeling::Stencils& s, const modeling::Positions& x,
                                  const modeling::PolynomialSurface& surface) {
  return boundaryXi<double>(s, x, nullptr, surface);
}

Eigen::VectorXd linearizedClampedBoundaryXi(const modeling::Stencils& s,
                                            const modeling::Positions& rest,
                                            const modeling::Positions& delta,
                                            const modeling::PolynomialSurface& surface) {
  return boundaryXi<Dual>(s, rest, &delta, surface);
}

std::vector<bool> boundaryEdges(const modeling::Stencils& s) {
  std::vector<bool> boundary(s.edgeCount());
  for (int e = 0; e < s.edgeCount(); ++e)
    boundary[e] = s.edgeFaces(e, 0) < 0 || s.edgeFaces(e, 1) < 0;
  return boundary;
}

}  // namespace flexure::curvature
