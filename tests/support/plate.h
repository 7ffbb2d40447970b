// A generated flat plate with one bending energy (and optionally a StVK membrane, xyz) bound to it
// through optimize::buildProblem, nothing held: the set-up of the vibration and dynamics tests.
#pragma once

#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "optimize/problem.h"

namespace flexure::testing {

inline modeling::Mesh generatedPlate(modeling::MeshFamily family, int n) {
  modeling::GeneratorOptions g;
  g.family = family;
  g.n = n;
  return modeling::generateMesh(g);
}

// Nothing held, no boundary values; a StVK membrane of Young's modulus `young` (xyz) when > 0.
inline optimize::ProblemOptions plateProblem(curvature::Discretization d, double young) {
  optimize::ProblemOptions o;
  o.bending.discretization = d;
  o.fixedRings = 0;
  o.boundaryNormals = optimize::BoundaryNormals::Free;
  if (young > 0.0) {
    curvature::MembraneOptions m;
    m.young = young;
    o.membrane = m;
    o.dof = optimize::DofMode::Xyz;
  }
  return o;
}

// Changes to a plate's problem options, made knowing the compiled mesh (e.g. which edges are on
// the boundary).
using AdjustProblem = std::function<void(optimize::ProblemOptions&, const modeling::Stencils&)>;

inline optimize::Problem buildPlateProblem(const modeling::Mesh& mesh,
                                           optimize::ProblemOptions options,
                                           const AdjustProblem& adjust) {
  modeling::Stencils stencils = modeling::compileStencils(mesh);
  modeling::RestState rest = modeling::precomputeRestState(stencils, mesh.positions);
  if (adjust) adjust(options, stencils);
  return optimize::buildProblem(std::move(stencils), std::move(rest), options);
}

// Built in place (its references point into `problem`).
struct Plate {
  modeling::Mesh mesh;
  optimize::Problem problem;
  const modeling::Stencils& stencils = problem.stencils;
  const modeling::RestState& rest = problem.rest;
  const Eigen::VectorXd& restXi = problem.restXi;  // #E (midedge), else empty

  Plate(modeling::MeshFamily family, int n, curvature::Discretization d, double young = 0.0,
        const AdjustProblem& adjust = {})
      : mesh(generatedPlate(family, n)),
        problem(buildPlateProblem(mesh, plateProblem(d, young), adjust)) {}
  Plate(const Plate&) = delete;
  Plate& operator=(const Plate&) = delete;

  std::vector<const curvature::EnergyTerm*> terms() const { return problem.termPointers(); }
};

}  // namespace flexure::testing
