#include "optimize/configuration_energy.h"

#include <vector>

#include "curvature/energy_registry.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/linear/least_squares.h"
#include "optimize/problem.h"

namespace flexure::optimize {

void ConfigurationEnergyOptions::validate() const {
  if (boundarySurface && !curvature::energyEntry(bending.discretization).takesBoundarySurface)
    throw InputError(
        "ConfigurationEnergyOptions.boundarySurface applies to an energy with edge unknowns (" +
        curvature::energyNamesWhere(&curvature::EnergyEntry::takesBoundarySurface) + ") only");
}

namespace {

// E at x: ξ start at ξ̄ (the boundary ones at the surface's normals at x) and are minimized over
// the free ones.
double nonlinearEnergy(const Problem& problem, const modeling::Positions& x,
                       const std::optional<modeling::PolynomialSurface>& surface,
                       const std::vector<bool>& onBoundary, const std::vector<bool>& freeEdge) {
  Eigen::VectorXd xi = problem.restXi;
  if (problem.usesEdgeUnknowns() && surface) {
    const Eigen::VectorXd clamped = curvature::clampedBoundaryXi(problem.stencils, x, *surface);
    for (int e = 0; e < problem.stencils.edgeCount(); ++e)
      if (onBoundary[e]) xi[e] = clamped[e];
  }
  return relaxedEnergy(problem.termPointers(), x, xi, freeEdge);
}

double linearizedEnergy(const Problem& problem, const modeling::Positions& x,
                        const std::optional<modeling::PolynomialSurface>& surface,
                        const std::vector<bool>& freeEdge) {
  const modeling::Positions& rest = problem.rest.positions;
  const SparseMatrix jacobian = residualJacobian(problem.termPointers(), rest, problem.restXi);
  const modeling::Positions delta = x - rest;
  Eigen::VectorXd deltaXi;
  if (problem.usesEdgeUnknowns() && surface)
    deltaXi = curvature::linearizedClampedBoundaryXi(problem.stencils, rest, delta, *surface);
  return linearizedEnergyOfDisplacement(jacobian, rest, delta, deltaXi, freeEdge);
}

}  // namespace

ConfigurationEnergy configurationEnergy(const modeling::Mesh& rest,
                                        const modeling::Positions& current,
                                        const ConfigurationEnergyOptions& options) {
  options.validate();
  if (current.rows() != rest.positions.rows())
    throw InputError("the configuration has " + std::to_string(current.rows()) +
                     " vertices, the rest mesh " + std::to_string(rest.positions.rows()));
  ProblemOptions p;  // nothing held; midedge's boundary ξ are set above
  p.bending = options.bending;
  p.fixedRings = 0;
  p.boundaryNormals = BoundaryNormals::Free;
  const Problem problem = buildProblem(rest, p);
  const std::optional<modeling::PolynomialSurface>& surface = options.boundarySurface;
  const std::vector<bool> onBoundary = curvature::boundaryEdges(problem.stencils);
  std::vector<bool> freeEdge(problem.stencils.edgeCount(), true);
  if (surface)
    for (int e = 0; e < problem.stencils.edgeCount(); ++e) freeEdge[e] = !onBoundary[e];

  const curvature::EnergyTerm& term = problem.bending();
  ConfigurationEnergy result;
  result.energy = options.linearized
                      ? linearizedEnergy(problem, current, surface, freeEdge)
                      : nonlinearEnergy(problem, current, surface, onBoundary, freeEdge);
  result.elements = term.elementCount();
  result.elementKind = std::string(term.elementKind());
  result.coveredArea = term.coveredArea();
  if (term.usesEdgeUnknowns())
    result.boundaryXi = surface ? "clamped to " + surface->spec() : "free";
  return result;
}

}  // namespace flexure::optimize
