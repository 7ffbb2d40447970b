// The command-line options that choose a bending energy, shared by the commands that use one
// (energy, minimize, fair).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "curvature/bending_energy.h"
#include "curvature/energy_registry.h"
#include "optimize/solvers/minimize.h"

namespace flexure::cli {

struct BendingArguments {
  std::string energy;
  std::optional<double> poisson;
  std::string vertexArea, hingeAngle;
  double stiffness = 1.0;
  bool flatRest = false;
};

// --energy, --poisson, --stiffness, --vertex-area, --hinge-angle, and --flat-rest when the
// command has a rest curvature to choose. --energy is required unless `defaultEnergy` is given.
struct BendingArgumentChoices {
  std::string defaultEnergy;  // empty: --energy is required
  bool restCurvature = true;  // offer --flat-rest
};
void addBendingArguments(CLI::App& sub, BendingArguments& arguments,
                         const BendingArgumentChoices& choices = {});

// "voronoi" | "barycentric" and "theta" | "tan" (case-insensitive); InputError listing them.
curvature::VertexArea parseVertexArea(std::string_view name);
curvature::HingeAngle parseHingeAngle(std::string_view name);

// Checked options: an option that does not apply to the chosen energy is an InputError.
curvature::BendingOptions bendingOptions(const BendingArguments& arguments);

}  // namespace flexure::cli
