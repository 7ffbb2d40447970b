// The continuum plate of a convergence study: the density Ψ_ν(∇²u) of a polynomial u, its
// integral over the square by Gauss–Legendre quadrature, and the polynomial helpers (scaling,
// zero, the bilaplacian Δ²u of a plate solution).
#include "optimize/studies/plate_polynomials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "curvature/koiter_density.h"
#include "optimize/studies/convergence_study.h"
#include "optimize/studies/gauss_legendre.h"

namespace flexure::optimize {
using modeling::PolynomialSurface;

namespace {

// Ψ_ν of the Hessian of u at (x, y).
double hessianDensity(const PolynomialSurface& u, double poisson, double x, double y) {
  const Eigen::Matrix2d h = u.hessian(x, y);
  return curvature::koiterDensity({h(0, 0), h(0, 1), h(1, 1)}, poisson);
}

}  // namespace

PolynomialSurface scaledSurface(const PolynomialSurface& p, double scale) {
  std::vector<modeling::Monomial> terms = p.terms();
  for (modeling::Monomial& term : terms) term.coefficient *= scale;
  return PolynomialSurface(std::move(terms));
}

bool isZero(const PolynomialSurface& p) {
  return std::all_of(p.terms().begin(), p.terms().end(),
                     [](const modeling::Monomial& m) { return m.coefficient == 0.0; });
}

double relativeBilaplacian(const PolynomialSurface& u) {
  std::map<std::pair<int, int>, double> bilaplacian;
  double scale = 0.0;
  for (const modeling::Monomial& m : u.terms()) {
    const double i = m.xPower, j = m.yPower, c = m.coefficient;
    scale = std::max(scale, std::abs(c) * std::pow(i + j, 4));
    if (m.xPower >= 4) bilaplacian[{m.xPower - 4, m.yPower}] += c * i * (i - 1) * (i - 2) * (i - 3);
    if (m.xPower >= 2 && m.yPower >= 2)
      bilaplacian[{m.xPower - 2, m.yPower - 2}] += 2 * c * i * (i - 1) * j * (j - 1);
    if (m.yPower >= 4) bilaplacian[{m.xPower, m.yPower - 4}] += c * j * (j - 1) * (j - 2) * (j - 3);
  }
  double largest = 0.0;
  for (const auto& [powers, coefficient] : bilaplacian)
    largest = std::max(largest, std::abs(coefficient));
  return scale > 0.0 ? largest / scale : 0.0;
}

double plateDensity(const PolynomialSurface& p, double poisson, double x, double y) {
  return hessianDensity(p, poisson, x, y);
}

double hessianSquaredNorm(const PolynomialSurface& p, double x, double y) {
  return hessianDensity(p, 0.0, x, y);  // Ψ_0(M) = tr M²
}

double squarePlateEnergy(const PolynomialSurface& u, double poisson) {
  // Ψ_ν(∇²u) has degree ≤ 2 d in each variable (d the largest power of u): d + 1 points suffice.
  int degree = 0;
  for (const modeling::Monomial& m : u.terms()) degree = std::max({degree, m.xPower, m.yPower});
  std::vector<double> nodes, weights;
  gaussLegendre(degree + 1, nodes, weights);
  // [−1, 1] → [−½, ½]: x = t / 2, dx = dt / 2.
  double sum = 0.0;
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t j = 0; j < nodes.size(); ++j)
      sum += weights[i] * weights[j] * hessianDensity(u, poisson, nodes[i] / 2, nodes[j] / 2);
  return sum / 4.0;
}

}  // namespace flexure::optimize
