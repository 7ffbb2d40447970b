// Gauss–Legendre quadrature on [−1, 1] (internal to optimize/studies/).
#pragma once

#include <vector>

namespace flexure::optimize {

// Gauss–Legendre nodes and weights on [−1, 1] (m points, exact for degree 2m − 1): the roots of
// P_m by Newton's method from Tricomi's initial guesses, w = 2 / ((1 − x²) P_m'(x)²).
void gaussLegendre(int m, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace flexure::optimize
