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

struct MembraneOptions {
  MembraneModel model = MembraneModel::Stvk;
  double young = 1.0;            // stvk: Y, Young's modulus × thickness
  double poisson = 0.3;          // stvk: ν, in (−1, 1/2]
  double lengthStiffness = 1.0;  // springs: k_L
  double areaStiffness = 1.0;    // springs: k_A
  double shapeStiffness = 1.0;   // conformal and mips: k_S
};

// "stvk" | "springs" | "conformal" | "mips"
MembraneModel parseMembraneModel(std::string_view name);

// stvk, conformal and mips give one term (faces); springs two (edge springs, area springs).
std::vector<std::unique_ptr<EnergyTerm>> makeMembraneEnergy(const modeling::Stencils& stencils,
                                                            const modeling::RestState& rest,
                                                            const MembraneOptions& options);

}  // namespace flexure::curvature
