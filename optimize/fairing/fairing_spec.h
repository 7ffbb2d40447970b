// A fairing run as a person names it, said once for the command and for Python: the method, the
// bending energy, the membrane and its weight, the start, the metric, the smallest-angle rule, the
// region's remeshing and the solver's limits. Plain data; validate() holds every rule on one field
// and between fields, each message naming the fields (FairingOptions.membraneWeight), so that the
// front ends map their words to fields and the fields of a message back to their words, and hold no
// rule of their own.
#pragma once

#include <optional>
#include <string>

#include "curvature/bending_spec.h"
#include "modeling/region_remeshing.h"
#include "optimize/fairing/fairing.h"
#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

struct FairingSpec {
  FairingSpec() { bending.energy = "midedge"; }

  std::string method = "flexure";  // parseFairingMethod's names
  // The energy of flexure's solve and of the measures; its rest curvature is flat whatever
  // flatRest says. An empty vertexArea is the metric's default (defaultFairingOptions).
  curvature::BendingSpec bending;        // midedge unless given
  std::string membrane = "mips";         // curvature::parseMembraneModel's names
  std::optional<double> membraneWeight;  // empty: the metric's default
  std::string start = "best";            // parseFairingStart's names
  std::string metric = "input";          // parseFairingMetric's names
  // No angle barrier, and a result below the smallest-angle rule accepted (SliverCheck).
  bool allowSlivers = false;
  // The region remeshed before the fair (modeling::remeshRegion), never without being asked:
  // the faces touching it become those of CGAL's isotropic remeshing, their border held.
  bool remesh = false;
  modeling::RemeshOptions remeshing;  // its options; given only with remesh
  MinimizeOptions solver;             // its dof and start are fairing's own

  // Every rule of a fairing run before its mesh is read (InputError naming the fields): the
  // names, the energy (curvature::BendingSpec::options), a membrane weight > 0, the solver's
  // limits; the remeshing's options (RemeshOptions::validate), given only with remesh; and with
  // method cgal, which solves no energy, no membrane weight and no smallest-angle
  // rule to waive (FairingSpec.allowSlivers).
  void validate() const;

  FairingMethod fairingMethod() const { return parseFairingMethod(method); }
  // The energy as given, with a flat rest: what the measures of every column use.
  curvature::BendingOptions material() const;
  // The options of flexure's solve: defaultFairingOptions(metric) with the spec's choices, the
  // energy's vertex area the metric's default unless one is given. Calls validate().
  FairingOptions options() const;
};

}  // namespace flexure::optimize
