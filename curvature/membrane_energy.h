// The membrane terms of membrane.h, built from the stencils and the rest state.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "curvature/energy_term.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

enum class MembraneModel { Stvk, Springs, Conformal, Mips };

// The defaults make the membrane 1 000 times the default bending stiffness k_B = 1 (per unit
// length², on a unit-sized mesh): stretching is then small next to bending, the nearly
// inextensible regime of thin shells (Y h ≫ D / L²) that the commands and Python inherit.
struct MembraneOptions {
  MembraneModel model = MembraneModel::Stvk;
  double young = 1e3;            // stvk: Y, Young's modulus × thickness
  double poisson = 0.3;          // stvk: ν, in (−1, 1/2]
  double lengthStiffness = 1e3;  // springs: k_L
  double areaStiffness = 1e3;    // springs: k_A
  double shapeStiffness = 1e3;   // conformal and mips: k_S

  // Throws InputError naming the field when one that `model` uses is out of range: Y, k_L, k_A,
  // k_S finite and > 0; ν in (−1, 1/2].
  void validate() const;
};

// "stvk" | "springs" | "conformal" | "mips"
MembraneModel parseMembraneModel(std::string_view name);

// stvk, conformal and mips give one term (faces); springs two (edge springs, area springs).
// Validates `options` first.
std::vector<std::unique_ptr<EnergyTerm>> makeMembraneEnergy(const modeling::Stencils& stencils,
                                                            const modeling::RestState& rest,
                                                            const MembraneOptions& options);

// The angle barrier of membrane.h on `faces`: κ = `stiffness`, α_min and d̂ in radians. Throws
// InputError for a non-positive κ or d̂, and NumericalError naming the face when one of its
// angles is already at or below α_min at `positions` (a barrier needs a feasible start).
std::unique_ptr<EnergyTerm> makeAngleBarrier(const modeling::Stencils& stencils,
                                             const std::vector<int>& faces,
                                             const modeling::Positions& positions, double stiffness,
                                             double minAngle, double band);

}  // namespace flexure::curvature
