// A potential of the vertex positions assembled on a Hessian pattern (obstacles, self-contact,
// friction) against central differences: over every free unknown u, the gradient entry against
// (E(x + ε e_u) − E(x − ε e_u)) / 2ε, and the Hessian's column u on the pattern against the
// same difference of the gradient.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "optimize/assembly/hessian_assembly.h"

namespace flexure::testing {

struct DerivativeTolerance {
  double step = 1e-7;      // ε
  double gradient = 1e-6;  // |g − g_fd| ≤ gradient (1 + |g_fd|)
  double hessian = 1e-5;   // |H − H_fd| ≤ hessian (1 + |H_fd|)
};

// `potential` has energy(x) and addGradient(x, gradient) (#V by 3); `e` is its evaluation at x on
// `assembly`. Returns how many gradient entries are not zero.
template <class Potential>
int expectAssembledDerivativesMatch(const optimize::HessianAssembly& assembly,
                                    const optimize::HessianEvaluation& e,
                                    const modeling::Positions& x, const Potential& potential,
                                    const DerivativeTolerance& tolerance = {}) {
  const double eps = tolerance.step;
  int active = 0;
  for (int k = 0; k < assembly.size(); ++k) {
    const int u = assembly.freeUnknowns()[k];
    modeling::Positions plus = x, minus = x;
    plus.data()[u] += eps;
    minus.data()[u] -= eps;
    const double fd = (potential.energy(plus) - potential.energy(minus)) / (2 * eps);
    EXPECT_NEAR(e.gradient[k], fd, tolerance.gradient * (1.0 + std::abs(fd))) << "unknown " << u;
    active += e.gradient[k] != 0.0;
    modeling::Positions gPlus = modeling::Positions::Zero(x.rows(), 3), gMinus = gPlus;
    potential.addGradient(plus, gPlus);
    potential.addGradient(minus, gMinus);
    for (int p = assembly.columnStart()[k]; p < assembly.columnStart()[k + 1]; ++p) {
      const int row = assembly.freeUnknowns()[assembly.rowIndex()[p]];
      const double fdh = (gPlus.data()[row] - gMinus.data()[row]) / (2 * eps);
      EXPECT_NEAR(e.values[p], fdh, tolerance.hessian * (1.0 + std::abs(fdh))) << row << ", " << u;
    }
  }
  return active;
}

// The dense symmetric Hessian of an evaluation on `assembly`'s pattern (upper triangle stored).
inline Eigen::MatrixXd denseHessian(const optimize::HessianAssembly& assembly,
                                    const std::vector<double>& values) {
  const int n = assembly.size();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int p = assembly.columnStart()[j]; p < assembly.columnStart()[j + 1]; ++p)
      h(assembly.rowIndex()[p], j) = h(j, assembly.rowIndex()[p]) = values[p];
  return h;
}

}  // namespace flexure::testing
