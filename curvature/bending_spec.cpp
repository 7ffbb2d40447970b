#include "curvature/bending_spec.h"

#include <cmath>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

// InputError when `value` is given to an energy whose entry does not read it.
void requireRead(const EnergyEntry& chosen, bool EnergyEntry::*reads, const std::string& value,
                 const char* field) {
  if (value.empty() || chosen.*reads) return;
  throw InputError(std::string(field) + " applies to BendingOptions.discretization " +
                   energyNamesWhere([&](const EnergyEntry& e) { return e.*reads; }) +
                   " only (not " + chosen.name + ")");
}

}  // namespace

const char* vertexAreaName(VertexArea area) {
  return area == VertexArea::Voronoi ? "voronoi" : "barycentric";
}

const char* hingeAngleName(HingeAngle angle) {
  return angle == HingeAngle::Theta ? "theta" : "tan";
}

VertexArea parseVertexArea(std::string_view name) {
  if (name == "voronoi") return VertexArea::Voronoi;
  if (name == "barycentric") return VertexArea::Barycentric;
  throw InputError("BendingOptions.vertexArea " + std::string(name) +
                   ": expected voronoi or barycentric");
}

HingeAngle parseHingeAngle(std::string_view name) {
  if (name == "theta") return HingeAngle::Theta;
  if (name == "tan") return HingeAngle::Tan;
  throw InputError("BendingOptions.hingeAngle " + std::string(name) + ": expected theta or tan");
}

BendingOptions BendingSpec::options() const {
  BendingOptions b;
  b.discretization = parseDiscretization(energy);
  b.poisson = poisson;
  if (!(stiffness > 0.0) || !std::isfinite(stiffness))
    throw InputError("BendingOptions.stiffness " + numberText(stiffness) +
                     ": expected a stiffness > 0");
  b.stiffness = stiffness;
  b.restCurvature = flatRest ? RestCurvature::Flat : RestCurvature::FromRest;
  const EnergyEntry& chosen = energyEntry(b.discretization);
  requireRead(chosen, &EnergyEntry::readsVertexArea, vertexArea, "BendingOptions.vertexArea");
  requireRead(chosen, &EnergyEntry::readsHingeAngle, hingeAngle, "BendingOptions.hingeAngle");
  if (!vertexArea.empty()) b.vertexArea = parseVertexArea(vertexArea);
  if (!hingeAngle.empty()) b.hingeAngle = parseHingeAngle(hingeAngle);
  effectivePoisson(b);  // rejects a ν the energy does not take
  return b;
}

}  // namespace flexure::curvature
