// The polynomial data of a convergence study (internal to optimize/studies/): scaled and zero
// polynomials and the bilaplacian test of a plate solution.
#pragma once

#include "modeling/polynomial_surface.h"

namespace flexure::optimize {

modeling::PolynomialSurface scaledSurface(const modeling::PolynomialSurface& p, double scale);

bool isZero(const modeling::PolynomialSurface& p);

// The largest coefficient of Δ²u, relative to the largest |c| (i + j)⁴ of u's terms c xⁱ yʲ:
// Δ²(xⁱ yʲ) = i(i−1)(i−2)(i−3) xⁱ⁻⁴ yʲ + 2 i(i−1) j(j−1) xⁱ⁻² yʲ⁻² + j(j−1)(j−2)(j−3) xⁱ yʲ⁻⁴.
double relativeBilaplacian(const modeling::PolynomialSurface& u);

}  // namespace flexure::optimize
