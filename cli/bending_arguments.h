// The command-line options that choose a bending energy, shared by the commands that use one
// (energy, minimize, fair).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "curvature/bending_energy.h"
#include "curvature/bending_spec.h"
#include "curvature/energy_registry.h"
#include "optimize/solvers/minimize.h"

namespace flexure::cli {

// The flags map one to one onto the library's spec of a bending energy (its options() holds the
// rules).
using BendingArguments = curvature::BendingSpec;

// --energy, --poisson, --stiffness, --vertex-area, --hinge-angle, and --flat-rest when the
// command has a rest curvature to choose. --energy is required unless `defaultEnergy` is given.
struct BendingArgumentChoices {
  std::string defaultEnergy;  // empty: --energy is required
  bool restCurvature = true;  // offer --flat-rest
};
void addBendingArguments(CLI::App& sub, BendingArguments& arguments,
                         const BendingArgumentChoices& choices = {});

// arguments.options(): an option that does not apply to the chosen energy is an InputError.
inline curvature::BendingOptions bendingOptions(const BendingArguments& arguments) {
  return arguments.options();
}

}  // namespace flexure::cli
