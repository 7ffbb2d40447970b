// The L-BFGS two-loop recursion on a factored initial matrix (optimize/solvers/lbfgs_update.h):
// without pairs it is H₀ itself; with pairs its H_k satisfies the secant equation H_k t = s for
// the newest pair, is symmetric positive definite, and equals the dense BFGS inverse updates;
// pairs of non-positive curvature are skipped and the oldest pair dropped beyond the capacity.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "optimize/solvers/lbfgs_update.h"

namespace flexure {
namespace {

using optimize::LbfgsPairs;

// A symmetric positive definite matrix (A Aᵀ + n I) and its Cholesky factor, as H₀ = A⁻¹.
struct Factored {
  Eigen::MatrixXd matrix;
  Eigen::LLT<Eigen::MatrixXd> factor;
  explicit Factored(int n, unsigned seed) {
    std::srand(seed);
    const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
    matrix = a * a.transpose() + n * Eigen::MatrixXd::Identity(n, n);
    factor.compute(matrix);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const { return factor.solve(b); }
};

// H_k as a dense matrix: columns H_k e_j.
Eigen::MatrixXd denseInverse(const LbfgsPairs& pairs, const Factored& f, int n) {
  Eigen::MatrixXd h(n, n);
  for (int j = 0; j < n; ++j)
    h.col(j) = pairs.apply(Eigen::VectorXd::Unit(n, j),
                           [&](const Eigen::VectorXd& b) { return f.solve(b); });
  return h;
}

TEST(LbfgsPairs, WithoutPairsTheStepIsTheFactorSolve) {
  const int n = 12;
  const Factored f(n, 3);
  const LbfgsPairs pairs(6);
  const Eigen::VectorXd g = Eigen::VectorXd::Random(n);
  const Eigen::VectorXd step =
      pairs.apply(-g, [&](const Eigen::VectorXd& b) { return f.solve(b); });
  EXPECT_LT((step - f.solve(-g)).norm(), 1e-14 * f.solve(g).norm());
}

// Pairs from a quadratic with another SPD Hessian B (t = B s): H_k t_last = s_last, H_k is
// symmetric positive definite, and equals the dense BFGS inverse updates
// H ← (I − ρ s tᵀ) H (I − ρ t sᵀ) + ρ s sᵀ applied to A⁻¹ in order.
TEST(LbfgsPairs, SatisfiesTheSecantEquationAndEqualsDenseBfgs) {
  const int n = 10;
  const Factored f(n, 5), b(n, 7);
  LbfgsPairs pairs(4);
  Eigen::MatrixXd dense = f.factor.solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  std::vector<Eigen::VectorXd> ss, ts;
  for (int k = 0; k < 6; ++k) {
    const Eigen::VectorXd s = Eigen::VectorXd::Random(n), t = b.matrix * s;
    ASSERT_TRUE(pairs.add(s, t));
    ss.push_back(s);
    ts.push_back(t);
    const Eigen::MatrixXd h = denseInverse(pairs, f, n);
    EXPECT_LT((h * t - s).norm(), 1e-12 * s.norm()) << "pair " << k;
    EXPECT_LT((h - h.transpose()).norm(), 1e-12 * h.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues().minCoeff(), 0.0);
  }
  EXPECT_EQ(pairs.size(), 4);  // the two oldest dropped
  for (int k = 2; k < 6; ++k) {
    const double rho = 1.0 / ss[k].dot(ts[k]);
    dense = (identity - rho * ss[k] * ts[k].transpose()) * dense *
                (identity - rho * ts[k] * ss[k].transpose()) +
            rho * ss[k] * ss[k].transpose();
  }
  EXPECT_LT((denseInverse(pairs, f, n) - dense).norm(), 1e-12 * dense.norm());
}

TEST(LbfgsPairs, SkipsPairsWithoutPositiveCurvature) {
  const int n = 5;
  LbfgsPairs pairs(3), none(0);
  const Eigen::VectorXd s = Eigen::VectorXd::Ones(n);
  EXPECT_FALSE(pairs.add(s, -s));                        // sᵀt < 0
  EXPECT_FALSE(pairs.add(s, Eigen::VectorXd::Zero(n)));  // sᵀt = 0
  // sᵀt = 5e-10 ≤ 1e-8 ‖s‖ ‖t‖ (≈ 3.2e-8): too little curvature to trust.
  EXPECT_FALSE(pairs.add(s, Eigen::VectorXd::Unit(n, 0) - Eigen::VectorXd::Unit(n, 1) + 1e-10 * s));
  EXPECT_EQ(pairs.size(), 0);
  EXPECT_TRUE(pairs.add(s, 2.0 * s));
  EXPECT_EQ(pairs.size(), 1);
  EXPECT_FALSE(none.add(s, 2.0 * s));  // capacity 0 keeps none
}

}  // namespace
}  // namespace flexure
