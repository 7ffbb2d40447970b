// The command-line options of a gravity load, shared by minimize (static) and simulate (dynamic):
// --gravity gx,gy,gz, --density ρ (mass per unit rest area) and --mass (the lumping).
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>
#include <vector>

#include "modeling/rest_state.h"
#include "optimize/vibration_modes.h"

namespace flexure::cli {

struct LoadArguments {
  std::string gravity;  // empty: none
  double density = 1.0;
  std::string mass = "barycentric";
};

void addLoadArguments(CLI::App& sub, LoadArguments& arguments);

// `count` comma-separated finite numbers; InputError quoting `option` and the text otherwise.
std::vector<double> parseNumbers(const std::string& option, const std::string& text, size_t count);

// g (zero when --gravity is not given).
Eigen::Vector3d gravityVector(const LoadArguments& arguments);
optimize::MassLumping massLumping(const LoadArguments& arguments);

// #V by 3: the weights m_v g of the lumped masses (empty when --gravity is not given).
modeling::Positions gravityLoad(const LoadArguments& arguments, const modeling::RestState& rest);

}  // namespace flexure::cli
