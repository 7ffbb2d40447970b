// The command-line options that choose a membrane energy (curvature/membrane_energy.h), shared by
// the commands that move every coordinate (minimize --dof xyz, simulate).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "curvature/membrane_energy.h"
#include "modeling/rest_state.h"

namespace flexure::cli {

// The library's defaults (curvature::MembraneOptions) until a flag sets one.
struct MembraneArguments {
  std::string model;  // empty: none given
  double young = curvature::MembraneOptions{}.young;
  double poisson = curvature::MembraneOptions{}.poisson;
  double lengthStiffness = curvature::MembraneOptions{}.lengthStiffness;
  double areaStiffness = curvature::MembraneOptions{}.areaStiffness;
  double shapeStiffness = curvature::MembraneOptions{}.shapeStiffness;
};

// --membrane (with `help`), --young, --membrane-poisson, --length-stiffness, --area-stiffness,
// --shape-stiffness.
void addMembraneArguments(CLI::App& sub, MembraneArguments& arguments, const std::string& help);

// The membrane's options (InputError for an unknown model).
curvature::MembraneOptions membraneOptions(const MembraneArguments& arguments);

// The membrane's terms on the rest state (InputError for an unknown model).
std::vector<std::unique_ptr<curvature::EnergyTerm>> makeMembrane(const MembraneArguments& arguments,
                                                                 const modeling::Stencils& stencils,
                                                                 const modeling::RestState& rest);

}  // namespace flexure::cli
