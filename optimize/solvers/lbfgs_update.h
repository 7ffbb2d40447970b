// The limited-memory BFGS inverse-Hessian product with a factored initial matrix (Nocedal &
// Wright 2006, Algorithm 7.4, the two-loop recursion; Liu, Bouaziz & Kavan 2017, "Quasi-Newton
// methods for real-time simulation of hyperelastic materials", and Li et al. 2019, DOT's
// L-BFGS-H, take H₀ = F⁻¹ for a kept Cholesky factor F of an earlier Hessian).
//
// With pairs (s_i, t_i), s_i = y_{i+1} − y_i and t_i = ∇f_{i+1} − ∇f_i of the last m accepted
// steps (oldest first) and ρ_i = 1 / s_iᵀt_i, the BFGS inverse update
//   H_{i+1} = (I − ρ_i s_i t_iᵀ) H_i (I − ρ_i t_i s_iᵀ) + ρ_i s_i s_iᵀ
// applied to a vector q is: for i newest to oldest, a_i = ρ_i s_iᵀq, q ← q − a_i t_i; r = H₀ q;
// for i oldest to newest, b = ρ_i t_iᵀr, r ← r + (a_i − b) s_i. H_k is symmetric positive
// definite when H₀ is and every s_iᵀt_i > 0, and satisfies the secant equation H_k t = s for the
// newest pair. A pair whose curvature s_iᵀt_i ≤ 10⁻⁸ ‖s_i‖ ‖t_i‖ is skipped (f not convex along
// it: a barrier that switched on, a buckling membrane).
#pragma once

#include <Eigen/Core>
#include <deque>
#include <functional>

namespace flexure::optimize {

class LbfgsPairs {
 public:
  // At most `capacity` pairs are kept, the oldest dropped first; 0 keeps none.
  explicit LbfgsPairs(int capacity) : capacity_(capacity) {}

  // Adds the pair (s, t) unless its curvature is below the skip bound above; whether it was kept.
  bool add(const Eigen::VectorXd& s, const Eigen::VectorXd& t);
  void clear() { pairs_.clear(); }
  int size() const { return static_cast<int>(pairs_.size()); }
  int capacity() const { return capacity_; }
  // The pairs' vector length (0 without pairs).
  long dimension() const { return pairs_.empty() ? 0 : pairs_.front().s.size(); }

  // H_k q, H₀ given by its product (a solve with the kept factor).
  Eigen::VectorXd apply(
      const Eigen::VectorXd& q,
      const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& initial) const;

 private:
  struct Pair {
    Eigen::VectorXd s, t;
    double rho = 0.0;  // 1 / sᵀt
  };
  int capacity_ = 0;
  std::deque<Pair> pairs_;  // oldest first
};

}  // namespace flexure::optimize
