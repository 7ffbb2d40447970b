#include "cli/plasticity_arguments.h"

#include "cli/command_files.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::cli {

void addYieldArguments(CLI::App& sub, PlasticityArguments& a) {
  sub.add_option("--yield-curvature", a.yieldCurvature,
                 "Plastic bending: yield curvature kappa_y (a cylinder yields at kappa_y, a sphere "
                 "at kappa_y/sqrt(3)); not " +
                     curvature::energyNamesWhere(
                         [](const curvature::EnergyEntry& e) { return !e.plasticRestCurvature; }));
  sub.add_option("--yield-strain", a.yieldStrain,
                 "Plastic membrane: yield strain epsilon_y (Green strain; a strip stretched with "
                 "its width held yields at epsilon_y); needs --membrane stvk");
  // The values' ranges are the library's (PlasticityOptions::validate names the field).
  sub.add_option("--hardening", a.hardening, "Linear kinematic hardening gamma >= 0")
      ->capture_default_str();
}

void addPlasticityArguments(CLI::App& sub, PlasticityArguments& a) {
  addYieldArguments(sub, a);
  sub.add_option("--load-steps", a.loadSteps,
                 "Plastic forming: reach the boundary values in K equal steps, each a static solve "
                 "and the plastic update (default 1)")
      ->check(positive());
  sub.add_flag("--release", a.release,
               "Plastic forming: then hold only the three vertices of the central face and relax "
               "(the sprung-back shape)");
}

optimize::PlasticityOptions plasticityOptions(const PlasticityArguments& a) {
  if (!a.enabled() && (a.loadSteps || a.release || a.hardening != 0.0))
    throw InputError(
        "--load-steps, --release and --hardening need a yield value: give --yield-curvature "
        "or --yield-strain");
  optimize::PlasticityOptions o;
  o.yieldCurvature = a.yieldCurvature;
  o.yieldStrain = a.yieldStrain;
  o.hardening = a.hardening;
  o.validate();
  return o;
}

optimize::FormingOptions formingOptions(const PlasticityArguments& a) {
  optimize::FormingOptions o;
  o.loadSteps = a.loadSteps.value_or(1);
  o.release = a.release;
  o.validate();
  return o;
}

}  // namespace flexure::cli
