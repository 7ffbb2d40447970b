// The energies of a convergence study by name: the grammar energy[:option] over the energy
// registry (hinge:tan, cotan:barycentric, midedge:free, …), and the spec's default rows.
#include <algorithm>
#include <string>
#include <vector>

#include "curvature/bending_spec.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "optimize/studies/convergence_study.h"

namespace flexure::optimize {

std::string energyVariantSpecs(bool withBoundaryNormals, std::string_view lastSeparator) {
  std::vector<std::string> specs;
  for (const curvature::EnergyEntry& e : curvature::registeredEnergies()) {
    specs.push_back(e.name);
    if (e.readsHingeAngle) specs.push_back(e.name + ":tan");
    if (e.readsVertexArea) specs.push_back(e.name + ":barycentric");
    if (e.restEdgeUnknowns && withBoundaryNormals) specs.push_back(e.name + ":free");
  }
  std::string joined;
  for (size_t k = 0; k < specs.size(); ++k)
    joined += std::string(k == 0 ? "" : k + 1 == specs.size() ? lastSeparator : ", ") + specs[k];
  return joined;
}

EnergyVariant parseEnergyVariant(std::string_view spec, std::optional<double> poisson) {
  const std::string text(spec);
  const auto colon = text.find(':');
  const std::string name = text.substr(0, colon);
  const std::string option = colon == std::string::npos ? "" : text.substr(colon + 1);
  const auto unknown = [&]() -> InputError {
    return InputError("unknown energy '" + text + "' (expected " +
                      energyVariantSpecs(true, " or ") + ")");
  };
  const auto& energies = curvature::registeredEnergies();
  const auto found = std::find_if(energies.begin(), energies.end(),
                                  [&](const curvature::EnergyEntry& e) { return e.name == name; });
  if (found == energies.end()) throw unknown();
  const curvature::EnergyEntry& e = *found;
  EnergyVariant v;
  v.bending.discretization = curvature::Discretization(static_cast<int>(found - energies.begin()));
  v.label = e.name;
  const auto either = [&](const char* first, const char* second) {
    return option.empty() || option == first || option == second;
  };
  if (e.readsHingeAngle && either("theta", "tan")) {
    if (!option.empty()) v.bending.hingeAngle = curvature::parseHingeAngle(option);
    if (option == "tan") v.label += "(tan)";
  } else if (e.readsVertexArea && either("voronoi", "barycentric")) {
    if (!option.empty()) v.bending.vertexArea = curvature::parseVertexArea(option);
    v.label += std::string("(") + curvature::vertexAreaName(v.bending.vertexArea) + ")";
  } else if (e.restEdgeUnknowns && either("clamped", "free")) {
    v.normals = option == "free" ? BoundaryNormals::Free : BoundaryNormals::Clamped;
    v.label += option == "free" ? "(free)" : "(clamped)";
  } else if (!option.empty()) {
    throw unknown();
  }
  if (e.poissonRule == curvature::PoissonRule::Koiter) v.bending.poisson = poisson;
  curvature::effectivePoisson(v.bending);  // rejects a ν outside [−1, 1]
  return v;
}

std::vector<EnergyVariant> parseEnergyVariants(const std::vector<std::string>& specs,
                                               std::optional<double> poisson) {
  std::vector<EnergyVariant> variants;
  for (const std::string& spec : specs) {
    try {
      variants.push_back(parseEnergyVariant(spec, poisson));
    } catch (const InputError& e) {
      throw InputError(std::string("StudyOptions.energies: ") + e.what());
    }
  }
  return variants;
}

std::vector<modeling::MeshFamily> parseStudyFamilies(const std::vector<std::string>& names) {
  std::vector<modeling::MeshFamily> families;
  for (const std::string& name : names) {
    try {
      families.push_back(modeling::parsePlateFamily(name));
    } catch (const InputError& e) {
      throw InputError(std::string("StudyOptions.families: ") + e.what());
    }
  }
  return families;
}

std::string energyVariantSpec(const EnergyVariant& v) {
  const auto open = v.label.find('(');
  if (open == std::string::npos) return v.label;
  return v.label.substr(0, open) + ":" + v.label.substr(open + 1, v.label.size() - open - 2);
}

std::vector<EnergyVariant> defaultEnergyVariants(std::optional<double> poisson) {
  std::vector<const curvature::EnergyEntry*> entries;
  for (const curvature::EnergyEntry& e : curvature::registeredEnergies()) entries.push_back(&e);
  std::stable_sort(entries.begin(), entries.end(),
                   [](const auto* a, const auto* b) { return a->studyRank < b->studyRank; });
  std::vector<EnergyVariant> variants;
  for (const curvature::EnergyEntry* e : entries)
    for (const std::string& spec : e->studyVariants)
      variants.push_back(parseEnergyVariant(spec, poisson));
  return variants;
}

}  // namespace flexure::optimize
