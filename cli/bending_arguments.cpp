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

std::string solverAdvice(const optimize::MinimizeReport& report,
                         const optimize::MinimizeOptions& solver) {
  // Ceres reports a residual that evaluates to inf or NaN as "Evaluation of the residual ...
  // failed" or "Residual and Jacobian evaluation failed".
  if (!std::isfinite(report.initialEnergy) || !std::isfinite(report.finalEnergy) ||
      report.termination.find("valuation") != std::string::npos) {
    return "the energy is not finite (overflow, or a degenerate triangle): values this large do "
           "not fit in double precision; scale the boundary data down, and check the mesh with "
           "flexure info";
  }
  if (report.iterations >= solver.maxIterations) {
    return "the solver used all its iterations (--max-iterations " +
           std::to_string(solver.maxIterations) + "): raise --max-iterations";
  }
  return "the solver stopped early; check the mesh for degenerate triangles (flexure info) or "
         "loosen the tolerances";
}

void addSolverLimits(CLI::App& sub, optimize::MinimizeOptions& solver, bool tolerances) {
  sub.add_option("--max-iterations", solver.maxIterations)
      ->capture_default_str()
      ->check(inRange(1, 1e6));
  if (tolerances) {
    sub.add_option("--function-tolerance", solver.functionTolerance,
                   "ceres: |dE| / E; newton: the predicted decrease of a step / E")
        ->capture_default_str()
        ->check(positive());
    sub.add_option("--gradient-tolerance", solver.gradientTolerance)
        ->capture_default_str()
        ->check(positive());
    sub.add_option("--parameter-tolerance", solver.parameterTolerance)
        ->capture_default_str()
        ->check(positive());
  }
  sub.add_option("--threads", solver.threads)
      ->capture_default_str()
      ->check(inRange(1, maxThreads()));
}

}  // namespace flexure::cli
