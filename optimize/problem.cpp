#include "optimize/problem.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::optimize {

void ProblemOptions::validate() const {
  if (dof == DofMode::Height && membrane)
    throw InputError(
        "ProblemOptions.membrane applies to ProblemOptions.dof xyz (height mode keeps x and y at "
        "rest)");
  if (dof == DofMode::Xyz && !membrane)
    throw InputError(
        "ProblemOptions.dof xyz needs a membrane (ProblemOptions.membrane): bending alone has no "
        "stiffness against sliding in the surface");
  if (fixedVertex.empty() && fixedRings < 0)
    throw InputError("ProblemOptions.fixedRings must be >= 0 (got " + std::to_string(fixedRings) +
                     ")");
  if (boundarySurface && boundaryPositions.size() > 0)
    throw InputError(
        "ProblemOptions.boundarySurface and ProblemOptions.boundaryPositions both give the held "
        "vertices' values: give one");
  if (membraneRest.size() > 0 && !membrane)
    throw InputError(
        "ProblemOptions.membraneRest is the rest shape of a membrane, which is not given");
  if (membraneRest.size() > 0 && !membraneRest.allFinite())
    throw InputError("ProblemOptions.membraneRest has a coordinate that is not finite");
  if (boundaryPositions.size() > 0 && !boundaryPositions.allFinite())
    throw InputError("ProblemOptions.boundaryPositions has a coordinate that is not finite");
  if (selfContact && dof != DofMode::Xyz)
    throw InputError(
        "ProblemOptions.selfContact moves every coordinate: expected ProblemOptions.dof xyz");
  if (!meshObstacles.empty() && dof != DofMode::Xyz)
    throw InputError(
        "ProblemOptions.meshObstacles move the shell in every coordinate: expected "
        "ProblemOptions.dof xyz");
  validateMeshObstacles(meshObstacles);
  if (!(contactOffset >= 0.0) || !std::isfinite(contactOffset))
    throw InputError("ProblemOptions.contactOffset " + numberText(contactOffset) +
                     ": expected a length > 0");
  const curvature::EnergyEntry& entry = curvature::energyEntry(bending.discretization);
  if (!fixedEdge.empty() && !entry.restEdgeUnknowns)
    throw InputError("ProblemOptions.fixedEdge holds edge unknowns, which " + entry.name +
                     " does not have");
  if (!fixedEdge.empty() && boundarySurface)
    throw InputError(
        "ProblemOptions.fixedEdge and ProblemOptions.boundarySurface both give the held ξ: give "
        "one");
  if (entry.takesBoundarySurface && fixedEdge.empty() &&
      boundaryNormals == BoundaryNormals::Clamped && !boundarySurface)
    throw InputError(
        "ProblemOptions.boundaryNormals clamped takes the normals from "
        "ProblemOptions.boundarySurface, which is not given: give one, or free normals");
  if (load.gravity && !load.gravity->allFinite())
    throw InputError("ProblemOptions.load.gravity must be finite");
  if (!(load.density > 0.0) || !std::isfinite(load.density))
    throw InputError("ProblemOptions.load.density must be positive (got " +
                     numberText(load.density) + ")");
}

namespace {

std::vector<bool> heldVertices(const modeling::Stencils& stencils, const ProblemOptions& o) {
  if (o.fixedVertex.empty())
    return o.fixedRings > 0 ? fixedRings(stencils, o.fixedRings)
                            : std::vector<bool>(stencils.vertexCount(), false);
  if (static_cast<int>(o.fixedVertex.size()) != stencils.vertexCount())
    throw InputError("ProblemOptions.fixedVertex has " + std::to_string(o.fixedVertex.size()) +
                     " entries, the mesh " + std::to_string(stencils.vertexCount()) + " vertices");
  return o.fixedVertex;
}

// Held vertices at their values; midedge boundary ξ clamped to the surface's normals or free.
BoundaryConditions boundaryConditions(const Problem& p, const ProblemOptions& o) {
  const std::vector<bool> fixed = heldVertices(p.stencils, o);
  if (o.boundarySurface)
    return surfaceBoundary(p.stencils, p.rest.positions, p.restXi, fixed, *o.boundarySurface,
                           o.boundaryNormals, o.linearizedClamp);
  BoundaryConditions bc;
  bc.fixedVertex = fixed;
  bc.start = p.rest.positions;
  if (o.boundaryPositions.size() > 0) {
    if (o.boundaryPositions.rows() != p.rest.positions.rows())
      throw InputError("ProblemOptions.boundaryPositions has " +
                       std::to_string(o.boundaryPositions.rows()) + " rows, the mesh " +
                       std::to_string(p.rest.positions.rows()) + " vertices");
    bc.start = o.boundaryPositions;
  }
  bc.xi = p.restXi;
  bc.fixedEdge.assign(p.restXi.size(), false);
  if (!o.fixedEdge.empty()) {
    if (o.fixedEdge.size() != bc.fixedEdge.size())
      throw InputError("ProblemOptions.fixedEdge has " + std::to_string(o.fixedEdge.size()) +
                       " entries, the mesh " + std::to_string(bc.fixedEdge.size()) + " edges");
    bc.fixedEdge = o.fixedEdge;
  }
  return bc;
}

}  // namespace

std::vector<const curvature::EnergyTerm*> Problem::termPointers() const {
  std::vector<const curvature::EnergyTerm*> pointers;
  for (const auto& term : terms) pointers.push_back(term.get());
  return pointers;
}

std::vector<bool> Problem::freeUnknowns() const {
  return freeUnknownMask(boundary.fixedVertex,
                         usesEdgeUnknowns() ? boundary.fixedEdge : std::vector<bool>(), dof);
}

Problem buildProblem(modeling::Stencils stencils, modeling::RestState rest,
                     const ProblemOptions& options) {
  options.validate();
  Problem p;
  p.stencils = std::move(stencils);
  p.rest = std::move(rest);
  p.dof = options.dof;
  p.terms.push_back(curvature::makeBendingEnergy(p.stencils, p.rest, options.bending));
  if (options.membraneRest.size() > 0) {
    if (options.membraneRest.rows() != p.rest.positions.rows())
      throw InputError("ProblemOptions.membraneRest has " +
                       std::to_string(options.membraneRest.rows()) + " rows, the mesh " +
                       std::to_string(p.rest.positions.rows()) + " vertices");
    p.membraneRest = std::make_unique<modeling::RestState>(
        modeling::precomputeRestState(p.stencils, options.membraneRest));
  }
  if (options.membrane)
    for (auto& term : curvature::makeMembraneEnergy(
             p.stencils, p.membraneRest ? *p.membraneRest : p.rest, *options.membrane))
      p.terms.push_back(std::move(term));
  // The one place ξ̄ is computed: for the term that owns edge unknowns.
  for (const auto& term : p.terms)
    if (term->usesEdgeUnknowns())
      p.restXi = curvature::midedgeRestXi(p.stencils, p.rest, options.bending.restCurvature);
  p.boundary = boundaryConditions(p, options);
  p.linearizedClamp = options.linearizedClamp;
  p.gravity = options.load.gravity.value_or(Eigen::Vector3d::Zero());
  p.mass = modeling::lumpedVertexMasses(p.rest, options.load.mass, options.load.density);
  if (options.load.gravity) p.externalForce = p.mass * p.gravity.transpose();
  if (!options.obstacles.empty())
    p.obstacles = makeObstacleBarrier(options.obstacles, p.rest, p.mass, p.gravity);
  if (options.selfContact || !options.meshObstacles.empty())
    p.selfContact =
        makeSelfContact(p.stencils, p.rest.positions, p.mass, p.gravity, options.contactOffset,
                        options.meshObstacles, options.selfContact);
  return p;
}

Problem buildProblem(const modeling::Mesh& rest, const ProblemOptions& options) {
  options.validate();  // before the mesh is compiled
  modeling::Stencils stencils = modeling::compileStencils(rest);
  modeling::RestState restState = modeling::precomputeRestState(stencils, rest.positions);
  return buildProblem(std::move(stencils), std::move(restState), options);
}

}  // namespace flexure::optimize
