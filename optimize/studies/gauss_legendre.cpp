// Gauss–Legendre nodes and weights by Newton's method on the Legendre polynomial.
#include "optimize/studies/gauss_legendre.h"

#include <cmath>

namespace flexure::optimize {

void gaussLegendre(int m, std::vector<double>& nodes, std::vector<double>& weights) {
  const double pi = std::acos(-1.0);
  nodes.assign(m, 0.0);
  weights.assign(m, 0.0);
  for (int i = 0; i < m; ++i) {
    double x = std::cos(pi * (i + 0.75) / (m + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      // P_m(x) and P_{m−1}(x) by the three-term recurrence, then
      // P_m'(x) = m (x P_m − P_{m−1}) / (x² − 1).
      double previous = 1.0, value = x;
      for (int k = 2; k <= m; ++k) {
        const double nextValue = ((2 * k - 1) * x * value - (k - 1) * previous) / k;
        previous = value;
        value = nextValue;
      }
      derivative = m * (x * value - previous) / (x * x - 1.0);
      const double step = value / derivative;
      x -= step;
      if (std::abs(step) < 1e-15) break;
    }
    nodes[i] = x;
    weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
  }
}

}  // namespace flexure::optimize
