// Forward-mode automatic differentiation to second order: a scalar carried with its gradient and
// Hessian with respect to N independent variables,
//
//   f ↦ (f, ∇f, ∇²f),
//
// so that the element kernels written for T = double and T = ceres::Jet (first order) also give
// exact second derivatives. Every operation applies the chain rule to second order: for a unary
// g, ∇g(f) = g′ ∇f and ∇²g(f) = g′ ∇²f + g″ ∇f ∇fᵀ; for a product, ∇²(fh) = f ∇²h + h ∇²f +
// ∇f ∇hᵀ + ∇h ∇fᵀ. The kernels use only +, −, ×, ÷, sqrt, tan and atan2, which is all this type
// provides. (A nested ceres::Jet<Jet<double, N>, N> would do the same, but Ceres 2.1's Jet has no
// implicit construction from a double, which the kernels' T(0.0) and double × T need.)
//
// The Hessian is stored whole (N × N); every update keeps it symmetric.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace flexure::curvature {

template <int N>
struct SecondOrderJet {
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Hessian = Eigen::Matrix<double, N, N>;

  double a = 0.0;  // the value; named as ceres::Jet's, so scalarPart() reads both
  Gradient v = Gradient::Zero();
  Hessian h = Hessian::Zero();

  SecondOrderJet() = default;
  explicit SecondOrderJet(double value) : a(value) {}
  // The independent variable k at `value`: ∇ = e_k, ∇² = 0.
  static SecondOrderJet variable(double value, int k) {
    SecondOrderJet x(value);
    x.v[k] = 1.0;
    return x;
  }

  SecondOrderJet& operator+=(const SecondOrderJet& g) { return *this = *this + g; }
  SecondOrderJet& operator-=(const SecondOrderJet& g) { return *this = *this - g; }
  SecondOrderJet& operator*=(const SecondOrderJet& g) { return *this = *this * g; }
  SecondOrderJet& operator/=(const SecondOrderJet& g) { return *this = *this / g; }

  friend SecondOrderJet operator-(const SecondOrderJet& f) {
    SecondOrderJet r;
    r.a = -f.a;
    r.v = -f.v;
    r.h = -f.h;
    return r;
  }
  friend SecondOrderJet operator+(const SecondOrderJet& f, const SecondOrderJet& g) {
    SecondOrderJet r;
    r.a = f.a + g.a;
    r.v = f.v + g.v;
    r.h = f.h + g.h;
    return r;
  }
  friend SecondOrderJet operator-(const SecondOrderJet& f, const SecondOrderJet& g) {
    SecondOrderJet r;
    r.a = f.a - g.a;
    r.v = f.v - g.v;
    r.h = f.h - g.h;
    return r;
  }
  friend SecondOrderJet operator*(const SecondOrderJet& f, const SecondOrderJet& g) {
    SecondOrderJet r;
    r.a = f.a * g.a;
    r.v = f.a * g.v + g.a * f.v;
    r.h = f.a * g.h + g.a * f.h;
    r.h.noalias() += f.v * g.v.transpose();
    r.h.noalias() += g.v * f.v.transpose();
    return r;
  }
  friend SecondOrderJet operator/(const SecondOrderJet& f, const SecondOrderJet& g) {
    return f * reciprocal(g);
  }

  // With a constant s: linear, so the Hessian only scales.
  friend SecondOrderJet operator+(const SecondOrderJet& f, double s) { return shifted(f, s); }
  friend SecondOrderJet operator+(double s, const SecondOrderJet& f) { return shifted(f, s); }
  friend SecondOrderJet operator-(const SecondOrderJet& f, double s) { return shifted(f, -s); }
  friend SecondOrderJet operator-(double s, const SecondOrderJet& f) { return shifted(-f, s); }
  friend SecondOrderJet operator*(const SecondOrderJet& f, double s) { return scaled(f, s); }
  friend SecondOrderJet operator*(double s, const SecondOrderJet& f) { return scaled(f, s); }
  friend SecondOrderJet operator/(const SecondOrderJet& f, double s) { return scaled(f, 1.0 / s); }
  friend SecondOrderJet operator/(double s, const SecondOrderJet& f) {
    return scaled(reciprocal(f), s);
  }

  // g(f) for a unary g with g(f.a) = value, g′(f.a) = first, g″(f.a) = second.
  friend SecondOrderJet chain(const SecondOrderJet& f, double value, double first, double second) {
    SecondOrderJet r;
    r.a = value;
    r.v = first * f.v;
    r.h = first * f.h;
    r.h.noalias() += second * (f.v * f.v.transpose());
    return r;
  }
  // 1/f: g′ = −1/f², g″ = 2/f³.
  friend SecondOrderJet reciprocal(const SecondOrderJet& f) {
    const double inverse = 1.0 / f.a;
    return chain(f, inverse, -inverse * inverse, 2.0 * inverse * inverse * inverse);
  }
  // √f: g′ = 1/(2√f), g″ = −1/(4 f √f).
  friend SecondOrderJet sqrt(const SecondOrderJet& f) {
    const double root = std::sqrt(f.a);
    return chain(f, root, 0.5 / root, -0.25 / (f.a * root));
  }
  // tan f: g′ = 1 + tan² f, g″ = 2 tan f (1 + tan² f).
  friend SecondOrderJet tan(const SecondOrderJet& f) {
    const double t = std::tan(f.a), first = 1.0 + t * t;
    return chain(f, t, first, 2.0 * t * first);
  }
  // atan2(y, x), with ρ = x² + y²: ∂/∂y = x/ρ, ∂/∂x = −y/ρ; ∂²/∂y² = −2xy/ρ², ∂²/∂x² = 2xy/ρ²,
  // ∂²/∂x∂y = (y² − x²)/ρ².
  friend SecondOrderJet atan2(const SecondOrderJet& y, const SecondOrderJet& x) {
    const double rho = x.a * x.a + y.a * y.a, rho2 = rho * rho;
    const double dy = x.a / rho, dx = -y.a / rho;
    const double dyy = -2.0 * x.a * y.a / rho2, dxx = -dyy, dxy = (y.a * y.a - x.a * x.a) / rho2;
    SecondOrderJet r;
    r.a = std::atan2(y.a, x.a);
    r.v = dy * y.v + dx * x.v;
    r.h = dy * y.h + dx * x.h;
    r.h.noalias() += dyy * (y.v * y.v.transpose());
    r.h.noalias() += dxx * (x.v * x.v.transpose());
    r.h.noalias() += dxy * (x.v * y.v.transpose());
    r.h.noalias() += dxy * (y.v * x.v.transpose());
    return r;
  }

 private:
  static SecondOrderJet shifted(SecondOrderJet f, double s) {
    f.a += s;
    return f;
  }
  static SecondOrderJet scaled(SecondOrderJet f, double s) {
    f.a *= s;
    f.v *= s;
    f.h *= s;
    return f;
  }
};

}  // namespace flexure::curvature
