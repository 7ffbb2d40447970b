#include "optimize/fairing/fairing_spec.h"

#include <cmath>

#include "curvature/membrane_energy.h"
#include "modeling/errors.h"

namespace flexure::optimize {

curvature::BendingOptions FairingSpec::material() const {
  curvature::BendingSpec flat = bending;
  flat.flatRest = true;
  return flat.options();
}

void FairingSpec::validate() const {
  const FairingMethod chosen = fairingMethod();
  material();
  curvature::parseMembraneModel(membrane);
  parseFairingStart(start);
  parseFairingMetric(metric);
  if (membraneWeight && (!(*membraneWeight > 0.0) || !std::isfinite(*membraneWeight)))
    throw InputError("FairingOptions.membraneWeight " + numberText(*membraneWeight) +
                     ": expected a weight > 0");
  solver.validate();
  remeshing.validate();
  if (!remesh && remeshing.targetEdgeLength)
    throw InputError("RemeshOptions.targetEdgeLength: only with FairingSpec.remesh");
  if (!remesh && remeshing.iterations != modeling::RemeshOptions().iterations)
    throw InputError("RemeshOptions.iterations: only with FairingSpec.remesh");
  if (chosen == FairingMethod::Cgal) {
    if (membraneWeight)
      throw InputError(
          "FairingOptions.membraneWeight: not with FairingOptions.method cgal (CGAL's linear "
          "fair has no membrane)");
    if (allowSlivers)
      throw InputError(
          "FairingSpec.allowSlivers: not with FairingOptions.method cgal (the smallest-angle "
          "rule judges flexure's result only)");
  }
}

FairingOptions FairingSpec::options() const {
  validate();
  FairingOptions o = defaultFairingOptions(parseFairingMetric(metric));
  const curvature::VertexArea metricArea = o.bending.vertexArea;
  o.bending = material();
  if (bending.vertexArea.empty()) o.bending.vertexArea = metricArea;
  o.membrane = curvature::parseMembraneModel(membrane);
  o.membraneWeight = membraneWeight.value_or(o.membraneWeight);
  o.start = parseFairingStart(start);
  o.angleBarrier = !allowSlivers;
  const MinimizeOptions metricSolver = o.solver;
  o.solver = solver;
  o.solver.quasiNewton = solver.quasiNewton || metricSolver.quasiNewton;
  o.solver.keepGaussNewton = solver.keepGaussNewton || metricSolver.keepGaussNewton;
  return o;
}

}  // namespace flexure::optimize
