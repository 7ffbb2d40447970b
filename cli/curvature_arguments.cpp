#include "cli/curvature_arguments.h"

#include "modeling/errors.h"

namespace flexure::cli {
namespace {

bool givesMeanCurvature(const curvature::EnergyEntry& e) {
  return static_cast<bool>(e.meanCurvatureField);
}

}  // namespace

const curvature::EnergyEntry& curvatureEnergy(const std::string& name) {
  if (name.empty()) return curvature::defaultMeanCurvatureEnergy();
  const curvature::EnergyEntry* entry = curvature::findEnergy(name);
  if (!entry || !givesMeanCurvature(*entry))
    throw InputError("--curvature-energy " + name + ": expected " +
                     curvature::energyNamesWhere(givesMeanCurvature));
  return *entry;
}

std::string curvatureEnergyHelp() {
  std::string ways;
  for (const curvature::EnergyEntry& e : curvature::registeredEnergies())
    if (givesMeanCurvature(e))
      ways += (ways.empty() ? "" : "; ") + e.name + ": " + e.meanCurvatureFormula;
  return "Curvature style: the discretization of H (" + ways + "; default " +
         curvature::defaultMeanCurvatureEnergy().name + ")";
}

}  // namespace flexure::cli
