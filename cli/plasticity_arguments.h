// The command-line options of plasticity (optimize/inelastic/plasticity.h): the yield values and
// hardening, and for minimize the quasi-static forming (load steps, release).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>

#include "optimize/inelastic/plasticity.h"

namespace flexure::cli {

struct PlasticityArguments {
  std::optional<double> yieldCurvature, yieldStrain;
  double hardening = 0.0;
  std::optional<int> loadSteps;
  bool release = false;

  bool enabled() const { return yieldCurvature.has_value() || yieldStrain.has_value(); }
};

// --yield-curvature, --yield-strain, --hardening (minimize and simulate).
void addYieldArguments(CLI::App& sub, PlasticityArguments& arguments);
// The yield arguments and minimize's forming: --load-steps, --release.
void addPlasticityArguments(CLI::App& sub, PlasticityArguments& arguments);

// InputError when forming options come without a yield value.
optimize::PlasticityOptions plasticityOptions(const PlasticityArguments& arguments);
optimize::FormingOptions formingOptions(const PlasticityArguments& arguments);

}  // namespace flexure::cli
