// --curvature-energy, shared by the commands that colour a mesh by its mean curvature H
// (render and view): which energy's kernel measures H.
#pragma once

#include <string>

#include "curvature/energy_registry.h"

namespace flexure::cli {

// The energy named by --curvature-energy ("": the registry's default, the first that gives a
// mean-curvature field); InputError naming the energies that do for any other name.
const curvature::EnergyEntry& curvatureEnergy(const std::string& name);

// --curvature-energy's help: each energy that gives H, how, and the default.
std::string curvatureEnergyHelp();

}  // namespace flexure::cli
