// A bending energy as a person names it — the energy's name and the options that only some
// energies read, as the command's flags and Python's keyword arguments give them — checked once
// against the energy's registry entry.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "curvature/bending_energy.h"

namespace flexure::curvature {

// "voronoi" | "barycentric"; "theta" | "tan". InputError naming the field
// (BendingOptions.vertexArea, BendingOptions.hingeAngle) and listing the names otherwise.
VertexArea parseVertexArea(std::string_view name);
HingeAngle parseHingeAngle(std::string_view name);
const char* vertexAreaName(VertexArea area);
const char* hingeAngleName(HingeAngle angle);

struct BendingSpec {
  std::string energy;  // a registered energy's name
  std::optional<double> poisson;
  double stiffness = 1.0;
  // Read by some energies only (the registry's readsVertexArea, readsHingeAngle); empty: the
  // default (voronoi, theta).
  std::string vertexArea, hingeAngle;
  bool flatRest = false;  // the rest mesh gives only the metric; rest curvature zero

  // The BendingOptions it names. InputError naming the field: an unknown energy, a vertex area or
  // hinge angle that is not a name or that the energy does not read, a ν the energy does not take
  // (effectivePoisson), a stiffness that is not > 0.
  BendingOptions options() const;
};

}  // namespace flexure::curvature
