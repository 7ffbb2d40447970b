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
// The Hessian is symmetric, so only its upper triangle is stored and computed (packed).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <utility>

namespace flexure::curvature {

template <int N>
struct SecondOrderJet {
  using Gradient = Eigen::Matrix<double, N, 1>;
  // The Hessian's upper triangle, row by row: entry (i, j ≥ i) at i N − i (i − 1)/2 + j − i.
  static constexpr int kPacked = N * (N + 1) / 2;
  using PackedHessian = std::array<double, kPacked>;

  double a = 0.0;  // the value; named as ceres::Jet's, so scalarPart() reads both
  Gradient v;      // zero unless set (the constructors below)
  PackedHessian h;
  // A constant (the kernels' T(0.5), rest data): its derivatives are zero, and an operation with
  // it is done as one with a double.
  bool constant = true;

  SecondOrderJet() : v(Gradient::Zero()), h{} {}
  explicit SecondOrderJet(double value) : a(value), v(Gradient::Zero()), h{} {}
  // The independent variable k at `value`: ∇ = e_k, ∇² = 0.
  static SecondOrderJet variable(double value, int k) {
    SecondOrderJet x(value);
    x.v[k] = 1.0;
    x.constant = false;
    return x;
  }

  // ∂²f/∂x_i∂x_j.
  double hessian(int i, int j) const {
    if (i > j) std::swap(i, j);
    return h[i * N - i * (i - 1) / 2 + j - i];
  }

  SecondOrderJet& operator+=(const SecondOrderJet& g) { return *this = *this + g; }
  SecondOrderJet& operator-=(const SecondOrderJet& g) { return *this = *this - g; }
  SecondOrderJet& operator*=(const SecondOrderJet& g) { return *this = *this * g; }
  SecondOrderJet& operator/=(const SecondOrderJet& g) { return *this = *this / g; }

  friend SecondOrderJet operator-(const SecondOrderJet& f) { return scaled(f, -1.0); }
  friend SecondOrderJet operator+(const SecondOrderJet& f, const SecondOrderJet& g) {
    if (g.constant) return shifted(f, g.a);
    if (f.constant) return shifted(g, f.a);
    SecondOrderJet r(Uninitialized{});
    r.a = f.a + g.a;
    r.v = f.v + g.v;
    for (int k = 0; k < kPacked; ++k) r.h[k] = f.h[k] + g.h[k];
    return r;
  }
  // f + (−g), written out (negation is exact, so the same bits).
  friend SecondOrderJet operator-(const SecondOrderJet& f, const SecondOrderJet& g) {
    if (g.constant) return shifted(f, -g.a);
    if (f.constant) return shifted(scaled(g, -1.0), f.a);
    SecondOrderJet r(Uninitialized{});
    r.a = f.a + -g.a;
    r.v = f.v - g.v;
    for (int k = 0; k < kPacked; ++k) r.h[k] = f.h[k] - g.h[k];
    return r;
  }
  // ∇²(fg) = f ∇²g + g ∇²f + ∇f ∇gᵀ + ∇g ∇fᵀ.
  friend SecondOrderJet operator*(const SecondOrderJet& f, const SecondOrderJet& g) {
    if (g.constant) return scaled(f, g.a);
    if (f.constant) return scaled(g, f.a);
    SecondOrderJet r(Uninitialized{});
    r.a = f.a * g.a;
    r.v = f.a * g.v + g.a * f.v;
    for (int i = 0, k = 0; i < N; ++i) {
      const double fi = f.v[i], gi = g.v[i];
      for (int j = i; j < N; ++j, ++k)
        r.h[k] = f.a * g.h[k] + g.a * f.h[k] + fi * g.v[j] + gi * f.v[j];
    }
    return r;
  }
  friend SecondOrderJet operator/(const SecondOrderJet& f, const SecondOrderJet& g) {
    if (g.constant) return scaled(f, 1.0 / g.a);
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
    if (f.constant) return SecondOrderJet(value);
    SecondOrderJet r(Uninitialized{});
    r.a = value;
    r.v = first * f.v;
    for (int i = 0, k = 0; i < N; ++i) {
      const double fi = second * f.v[i];
      for (int j = i; j < N; ++j, ++k) r.h[k] = first * f.h[k] + fi * f.v[j];
    }
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
  // log f: g′ = 1/f, g″ = −1/f².
  friend SecondOrderJet log(const SecondOrderJet& f) {
    const double inverse = 1.0 / f.a;
    return chain(f, std::log(f.a), inverse, -inverse * inverse);
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
    if (x.constant && y.constant) return SecondOrderJet(std::atan2(y.a, x.a));
    SecondOrderJet r(Uninitialized{});
    r.a = std::atan2(y.a, x.a);
    r.v = dy * y.v + dx * x.v;
    for (int i = 0, k = 0; i < N; ++i) {
      const double yi = y.v[i], xi = x.v[i];
      for (int j = i; j < N; ++j, ++k) {
        r.h[k] = dy * y.h[k] + dx * x.h[k] + dyy * yi * y.v[j] + dxx * xi * x.v[j] +
                 dxy * (xi * y.v[j] + yi * x.v[j]);
      }
    }
    return r;
  }

 private:
  // A variable whose value, gradient and Hessian the caller fills in full (no zeroing first).
  struct Uninitialized {};
  explicit SecondOrderJet(Uninitialized) : constant(false) {}

  static SecondOrderJet shifted(SecondOrderJet f, double s) {
    f.a += s;
    return f;
  }
  static SecondOrderJet scaled(SecondOrderJet f, double s) {
    f.a *= s;
    if (f.constant) return f;
    f.v *= s;
    for (double& entry : f.h) entry *= s;
    return f;
  }
};

}  // namespace flexure::curvature
