#include "cli/bending_arguments.h"

#include <cctype>
#include <cmath>
#include <functional>

#include "cli/command_files.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::cli {
namespace {

std::string lowercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

curvature::VertexArea parseVertexArea(std::string_view name) {
  const std::string n = lowercase(name);
  if (n == "voronoi") return curvature::VertexArea::Voronoi;
  if (n == "barycentric") return curvature::VertexArea::Barycentric;
  throw InputError("unknown vertex area '" + std::string(name) +
                   "' (expected voronoi or barycentric)");
}

curvature::HingeAngle parseHingeAngle(std::string_view name) {
  const std::string n = lowercase(name);
  if (n == "theta") return curvature::HingeAngle::Theta;
  if (n == "tan") return curvature::HingeAngle::Tan;
  throw InputError("unknown hinge angle '" + std::string(name) + "' (expected theta or tan)");
}

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

curvature::BendingOptions bendingOptions(const BendingArguments& a) {
  curvature::BendingOptions b;
  b.discretization = curvature::parseDiscretization(a.energy);
  b.poisson = a.poisson;
  b.stiffness = a.stiffness;
  b.restCurvature =
      a.flatRest ? curvature::RestCurvature::Flat : curvature::RestCurvature::FromRest;
  const curvature::EnergyEntry& chosen = curvature::energyEntry(b.discretization);
  const auto onlyFor = [&](bool curvature::EnergyEntry::*reads, const std::string& value,
                           const char* option) {
    if (!value.empty() && !(chosen.*reads)) {
      throw InputError(
          std::string(option) + " applies to --energy " +
          curvature::energyNamesWhere([&](const curvature::EnergyEntry& e) { return e.*reads; },
                                      ", ", " or ") +
          " only");
    }
  };
  onlyFor(&curvature::EnergyEntry::readsVertexArea, a.vertexArea, "--vertex-area");
  onlyFor(&curvature::EnergyEntry::readsHingeAngle, a.hingeAngle, "--hinge-angle");
  if (!a.vertexArea.empty()) b.vertexArea = parseVertexArea(a.vertexArea);
  if (!a.hingeAngle.empty()) b.hingeAngle = parseHingeAngle(a.hingeAngle);
  curvature::effectivePoisson(b);  // rejects a ν the energy does not take
  return b;
}

}  // namespace flexure::cli
