// A generated flat plate with one bending energy (and optionally a StVK membrane, xyz) bound to it
// through optimize::buildProblem, nothing held: the set-up of the vibration and dynamics tests.
#pragma once

#include <memory>
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

// Built in place (its references point into `problem`).
struct Plate {
  modeling::Mesh mesh;
  optimize::Problem problem;
  const modeling::Stencils& stencils = problem.stencils;
  const modeling::RestState& rest = problem.rest;
  const Eigen::VectorXd& restXi = problem.restXi;  // #E (midedge), else empty

  Plate(modeling::MeshFamily family, int n, curvature::Discretization d, double young = 0.0)
      : mesh(generatedPlate(family, n)),
        problem(optimize::buildProblem(mesh, plateProblem(d, young))) {}
  Plate(const Plate&) = delete;
  Plate& operator=(const Plate&) = delete;

  std::vector<const curvature::EnergyTerm*> terms() const { return problem.termPointers(); }
};

}  // namespace flexure::testing
