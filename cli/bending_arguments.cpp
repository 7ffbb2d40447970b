#include "cli/bending_arguments.h"

#include <functional>

#include "cli/command_files.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::cli {

void addBendingArguments(CLI::App& sub, BendingArguments& a,
                         const BendingArgumentChoices& choices) {
  using curvature::EnergyEntry;
  const auto all = [](const EnergyEntry&) { return true; };
  const auto koiter = [](const EnergyEntry& e) {
    return e.poissonRule == curvature::PoissonRule::Koiter;
  };
  const auto readsVertexArea = [](const EnergyEntry& e) { return e.readsVertexArea; };
  const auto readsHingeAngle = [](const EnergyEntry& e) { return e.readsHingeAngle; };
  CLI::Option* energy =
      sub.add_option("--energy", a.energy, curvature::energyNamesWhere(all, " | ", " | "));
  // Checked as the command line is parsed, so that flexure run finds a misspelt name before
  // any step runs.
  energy->check(CLI::Validator(
      [](std::string& name) -> std::string {
        try {
          curvature::parseDiscretization(name);
          return "";
        } catch (const InputError& e) {
          return e.what();
        }
      },
      ""));
  if (choices.defaultEnergy.empty()) {
    energy->required();
  } else {
    a.energy = choices.defaultEnergy;
    energy->capture_default_str();
  }
  sub.add_option("--poisson", a.poisson,
                 "Poisson's ratio nu of the Koiter density (" +
                     curvature::energyNamesWhere(koiter, ", ", ", ") + "; default 0.3)");
  sub.add_option("--stiffness", a.stiffness, "Bending stiffness k_B")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--vertex-area", a.vertexArea,
                 curvature::energyNamesWhere(readsVertexArea, ", ", ", ") +
                     ": voronoi (default) | barycentric");
  sub.add_option(
      "--hinge-angle", a.hingeAngle,
      curvature::energyNamesWhere(readsHingeAngle, ", ", ", ") + ": theta (default) | tan");
  if (choices.restCurvature) {
    sub.add_flag("--flat-rest", a.flatRest,
                 "Take only the metric from the rest mesh; its rest curvature is zero (fairing)");
  }
}

}  // namespace flexure::cli
