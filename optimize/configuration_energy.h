// The bending energy of a configuration against its rest mesh, with nothing held: what
// `flexure energy` and Python's flexure.energy report. Midedge's ξ are unknowns of the energy,
// not of the configuration: E is the minimum over the free ξ, the boundary ones clamped to a
// boundary surface's normals when one is given (else free).
//
// Nonlinear: E(x) = min_ξ E(x, ξ). Linearized: E_lin(δ) = ½ |J u|² with J the residual Jacobian
// at rest and u = (δ, ξ − ξ̄), δ = x − x̄, minimized over the free ξ (the clamp linearized too).
#pragma once

#include <optional>
#include <string>

#include "curvature/bending_energy.h"
#include "modeling/mesh.h"
#include "modeling/polynomial_surface.h"

namespace flexure::optimize {

struct ConfigurationEnergyOptions {
  curvature::BendingOptions bending;
  std::optional<modeling::PolynomialSurface> boundarySurface;  // midedge's clamp; empty: free ξ
  bool linearized = false;

  // InputError naming the field: a boundary surface for an energy without edge unknowns.
  void validate() const;
};

struct ConfigurationEnergy {
  double energy = 0.0;
  int elements = 0;
  std::string elementKind;   // "face", "vertex", "edge"
  double coveredArea = 0.0;  // the rest area the elements cover
  std::string boundaryXi;    // midedge: "clamped to <surface>" or "free"; else empty

  double perArea() const { return coveredArea > 0 ? energy / coveredArea : 0.0; }
};

// The energy of `current` (#V by 3) on `rest`'s connectivity and rest state. InputError for bad
// options, a vertex count that differs from the rest mesh's, or a degenerate rest element.
ConfigurationEnergy configurationEnergy(const modeling::Mesh& rest,
                                        const modeling::Positions& current,
                                        const ConfigurationEnergyOptions& options);

}  // namespace flexure::optimize
