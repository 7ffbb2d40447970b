// The conditions' measures shared with the study's runs (internal to optimize/studies/).
#pragma once

#include "modeling/polynomial_surface.h"

namespace flexure::optimize {

// C1's measure of an energy per area against the continuum density, relative to
// |∇²p|² = tr (∇²p)², which is positive for any non-zero quadratic even where Ψ_ν(∇²p) = 0.
double c1Measure(double energyPerArea, const modeling::PolynomialSurface& p, double poisson);

}  // namespace flexure::optimize
