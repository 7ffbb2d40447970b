#include "cli/bending_arguments.h"

#include <cmath>

#include "cli/command_files.h"
#include "modeling/errors.h"

namespace flexure::cli {

void addBendingArguments(CLI::App& sub, BendingArguments& a,
                         const BendingArgumentChoices& choices) {
  CLI::Option* energy =
      sub.add_option("--energy", a.energy, "hinge | triavg | cotan | midedge | quadfit");
  if (choices.defaultEnergy.empty()) {
    energy->required();
  } else {
    a.energy = choices.defaultEnergy;
    energy->capture_default_str();
  }
  sub.add_option(
      "--poisson", a.poisson,
      "Poisson's ratio nu of the Koiter density (triavg, midedge, quadfit; default 0.3)");
  sub.add_option("--stiffness", a.stiffness, "Bending stiffness k_B")
      ->capture_default_str()
      ->check(positive());
  sub.add_option("--vertex-area", a.vertexArea, "cotan: voronoi (default) | barycentric");
  sub.add_option("--hinge-angle", a.hingeAngle, "hinge: theta (default) | tan");
  if (choices.restCurvature) {
    sub.add_flag("--flat-rest", a.flatRest,
                 "Take only the metric from the rest mesh; its rest curvature is zero (fairing)");
  }
}

curvature::BendingOptions bendingOptions(const BendingArguments& a) {
  using curvature::Discretization;
  curvature::BendingOptions b;
  b.discretization = curvature::parseDiscretization(a.energy);
  b.poisson = a.poisson;
  b.stiffness = a.stiffness;
  b.restCurvature =
      a.flatRest ? curvature::RestCurvature::Flat : curvature::RestCurvature::FromRest;
  const auto onlyFor = [&](Discretization d, const std::string& value, const char* option) {
    if (!value.empty() && b.discretization != d) {
      throw InputError(std::string(option) + " applies to --energy " +
                       std::string(curvature::discretizationName(d)) + " only");
    }
  };
  onlyFor(Discretization::Cotan, a.vertexArea, "--vertex-area");
  onlyFor(Discretization::Hinge, a.hingeAngle, "--hinge-angle");
  if (!a.vertexArea.empty()) b.vertexArea = curvature::parseVertexArea(a.vertexArea);
  if (!a.hingeAngle.empty()) b.hingeAngle = curvature::parseHingeAngle(a.hingeAngle);
  curvature::effectivePoisson(b);  // rejects a ν the energy does not take
  return b;
}

}  // namespace flexure::cli
