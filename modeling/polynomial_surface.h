// Polynomial height fields z = p(x, y) with exact derivatives and normals: the boundary data and
// reference solutions of the test problems.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

// One term  coefficient · x^xPower · y^yPower.
struct Monomial {
  double coefficient = 0.0;
  int xPower = 0;
  int yPower = 0;
};

class PolynomialSurface {
 public:
  PolynomialSurface() = default;  // p = 0
  // Keeps the terms as given (no merging); throws InputError for a non-finite coefficient or a
  // negative power.
  explicit PolynomialSurface(std::vector<Monomial> terms);

  // z = a x² + b x y + c y², the quadratics of the convergence conditions C1/C2.
  static PolynomialSurface quadratic(double a, double b, double c);

  // Parses "quadratic:a,b,c" or "polynomial:EXPR" where EXPR is a sum of monomials such as
  // "x^3-3*x*y^2" or "0.5*x^2*y+y". Throws InputError quoting the spec and what is wrong.
  static PolynomialSurface parse(std::string_view spec);

  double height(double x, double y) const;
  Eigen::Vector2d gradient(double x, double y) const;  // (p_x, p_y)
  Eigen::Matrix2d hessian(double x, double y) const;   // [[p_xx, p_xy], [p_xy, p_yy]]
  // Unit upward normal of the graph: (−p_x, −p_y, 1) / |(−p_x, −p_y, 1)|.
  Eigen::Vector3d unitNormal(double x, double y) const;

  const std::vector<Monomial>& terms() const { return terms_; }
  // A string parse() turns back into the same terms: "quadratic:a,b,c" for the three terms of
  // quadratic(), otherwise "polynomial:..." with shortest round-trip coefficients.
  std::string spec() const;

 private:
  std::vector<Monomial> terms_;
};

// Sets every vertex's z to p(x, y), keeping x and y.
void applyHeightField(const PolynomialSurface& surface, Positions& positions);

}  // namespace flexure::modeling
