#include "curvature/energy_registry.h"

#include <cctype>
#include <stdexcept>

#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

std::string lowercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

struct Registry {
  std::deque<EnergyEntry> entries;
  size_t builtinCount = 0;
};

Registry& registryWithBuiltins() {
  // The built-ins, one line each, at the indices Discretization::Hinge … QuadraticFit name.
  static Registry r = [] {
    Registry built;
    built.entries = {
        hingeEnergyEntry(),   triangleAveragedEnergyEntry(), cotanEnergyEntry(),
        midedgeEnergyEntry(), quadraticFitEnergyEntry(),
    };
    built.builtinCount = built.entries.size();
    return built;
  }();
  return r;
}

std::deque<EnergyEntry>& registry() {
  return registryWithBuiltins().entries;
}

// The registry index of the energy of that name (case-insensitive); −1 when none.
int indexOf(std::string_view name) {
  const std::string wanted = lowercase(name);
  const std::deque<EnergyEntry>& entries = registry();
  for (size_t k = 0; k < entries.size(); ++k)
    if (entries[k].name == wanted) return static_cast<int>(k);
  return -1;
}

}  // namespace

std::string_view elementKindName(ElementKind kind) {
  switch (kind) {
    case ElementKind::Edge:
      return "edge";
    case ElementKind::Face:
      return "face";
    case ElementKind::Vertex:
      return "vertex";
  }
  return "element";
}

const std::deque<EnergyEntry>& registeredEnergies() {
  return registry();
}

const EnergyEntry& energyEntry(Discretization d) {
  const std::deque<EnergyEntry>& entries = registry();
  if (d.index() < 0 || d.index() >= static_cast<int>(entries.size()))
    throw std::logic_error("energyEntry: no energy registered at index " +
                           std::to_string(d.index()));
  return entries[static_cast<size_t>(d.index())];
}

std::vector<Discretization> builtinDiscretizations() {
  std::vector<Discretization> builtins;
  for (size_t k = 0; k < registryWithBuiltins().builtinCount; ++k)
    builtins.emplace_back(static_cast<int>(k));
  return builtins;
}

const EnergyEntry* findEnergy(std::string_view name) {
  const int index = indexOf(name);
  return index < 0 ? nullptr : &registry()[static_cast<size_t>(index)];
}

const EnergyEntry& defaultMeanCurvatureEnergy() {
  for (const EnergyEntry& e : registry())
    if (e.meanCurvatureField) return e;
  throw std::logic_error("defaultMeanCurvatureEnergy: no energy gives a mean-curvature field");
}

std::vector<std::string> energyNameList() {
  std::vector<std::string> names;
  for (const EnergyEntry& e : registry()) names.push_back(e.name);
  return names;
}

std::string registeredEnergyNames(std::string_view separator, std::string_view lastSeparator) {
  return energyNamesWhere([](const EnergyEntry&) { return true; }, separator, lastSeparator);
}

std::string energyNamesWhere(const std::function<bool(const EnergyEntry&)>& selects,
                             std::string_view separator, std::string_view lastSeparator) {
  std::vector<std::string> names;
  for (const EnergyEntry& e : registry())
    if (selects(e)) names.push_back(e.name);
  std::string joined;
  for (size_t k = 0; k < names.size(); ++k) {
    if (k > 0) joined += k + 1 == names.size() ? lastSeparator : separator;
    joined += names[k];
  }
  return joined;
}

Discretization parseDiscretization(std::string_view name) {
  const int index = indexOf(name);
  if (index >= 0) return Discretization(index);
  throw InputError("unknown energy '" + std::string(name) + "' (expected " +
                   registeredEnergyNames() + ")");
}

std::string_view discretizationName(Discretization d) {
  return energyEntry(d).name;
}

Discretization registerEnergy(EnergyEntry entry) {
  std::deque<EnergyEntry>& entries = registry();
  entry.name = lowercase(entry.name);
  if (entry.name.empty()) throw InputError("EnergyEntry.name is empty");
  if (!entry.make) throw InputError("EnergyEntry.make is empty for energy '" + entry.name + "'");
  for (const EnergyEntry& e : entries)
    if (e.name == entry.name)
      throw InputError("EnergyEntry.name '" + entry.name + "' is already registered");
  entries.push_back(std::move(entry));
  return Discretization(static_cast<int>(entries.size()) - 1);
}

Eigen::VectorXd restEdgeUnknowns(const modeling::Stencils& stencils,
                                 const modeling::RestState& rest, const BendingOptions& options) {
  const EnergyEntry& entry = energyEntry(options.discretization);
  if (!entry.restEdgeUnknowns) return Eigen::VectorXd::Zero(stencils.edgeCount());
  return entry.restEdgeUnknowns(stencils, rest, options.restCurvature);
}

}  // namespace flexure::curvature
