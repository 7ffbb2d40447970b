// The command-line options that choose a bending energy, shared by the commands that use one
// (energy, minimize).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "curvature/bending_energy.h"

namespace flexure::cli {

struct BendingArguments {
  std::string energy;
  std::optional<double> poisson;
  std::string vertexArea, hingeAngle;
  double stiffness = 1.0;
  bool flatRest = false;
};

// --energy (required), --poisson, --stiffness, --vertex-area, --hinge-angle, --flat-rest.
void addBendingArguments(CLI::App& sub, BendingArguments& arguments);

// Checked options: an option that does not apply to the chosen energy is an InputError.
curvature::BendingOptions bendingOptions(const BendingArguments& arguments);

}  // namespace flexure::cli
