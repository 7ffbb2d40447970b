// The momentum of a free body under gravity and Rayleigh damping C = α M + β K̄, and the bound
// Newmark's stepper keeps it within: the known answer of the pin-release tests (a piece let go at
// T is free from then on).
//
// Neither the elastic forces nor β K̄ exert a net force on a free body (K̄ = JᵀJ at rest, and the
// energies' residuals do not change under a translation t, so J t = 0 and 1ᵀ K̄ v = 0 per
// direction), so its momentum p = Σ m v obeys dp/dt = M g − α p:
//   p(s) = p(T) e^{−α s} + M g (1 − e^{−α s}) / α,  s = t − T   (α = 0: p(T) + M g s).
// Newmark's γ = ½ advances Σ m v by the trapezoidal rule, p_{n+1} = p_n + ½ h (F_n + F_{n+1}),
// F = M g − α p, so q = p − M g / α shrinks by r = (1 − z/2)/(1 + z/2) per step, z = α h, and
// ln r = −z − z³/12 − z⁵/80 − …, i.e. −z − δ with δ ≤ z³/(12 (1 − z²/4)). After n = s/h steps
//   |p_n − p(s)| = |q(T)| e^{−α s} (1 − e^{−n δ}) ≤ |q(T)| α s (α h)² / (12 (1 − (α h)²/4)),
// plus Newton's: each step stops with x within ε_v L h per coordinate (DynamicsOptions::
// stepTolerance ε_v, L the rest diagonal), and v = v̂ + γ h (x − x̂)/(β h²) is off by γ/(β h) of
// that, so Σ m v by √3 γ/β ε_v L M per step.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "optimize/dynamics/time_stepping.h"

namespace flexure::testing {

class DampedFreeBody {
 public:
  // Let go with momentum `p0` and mass `mass` under gravity `g`, damping α, steps h of a stepper
  // with Newmark's and Newton's `options`, on a body of rest diagonal `diagonal`.
  DampedFreeBody(const Eigen::Vector3d& p0, double mass, const Eigen::Vector3d& g, double alpha,
                 double h, const optimize::DynamicsOptions& options, double diagonal)
      : p0_(p0),
        mass_(mass),
        g_(g),
        alpha_(alpha),
        h_(h),
        q0_(alpha > 0.0 ? Eigen::Vector3d(p0 - mass * g / alpha) : p0),
        newtonPerStep_(std::sqrt(3.0) * options.gamma / options.beta * options.stepTolerance *
                       diagonal * mass) {}

  // p(s), s the time since the release.
  Eigen::Vector3d momentum(double s) const {
    const double growth = alpha_ > 0.0 ? -std::expm1(-alpha_ * s) / alpha_ : s;
    return p0_ * std::exp(-alpha_ * s) + mass_ * g_ * growth;
  }

  // The bound on |p_n − p(s)| after `steps` steps of h (s = steps h).
  double tolerance(double s, int steps) const {
    const double z = alpha_ * h_;
    return q0_.norm() * alpha_ * s * z * z / (12.0 * (1.0 - 0.25 * z * z)) + steps * newtonPerStep_;
  }

 private:
  Eigen::Vector3d p0_;
  double mass_;
  Eigen::Vector3d g_;
  double alpha_, h_;
  Eigen::Vector3d q0_;
  double newtonPerStep_;
};

}  // namespace flexure::testing
