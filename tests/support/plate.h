// A generated flat plate with one bending energy (and optionally a StVK membrane) bound to it:
// the set-up of the vibration and dynamics tests.
#pragma once

#include <memory>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/generators.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::testing {

struct Plate {
  modeling::Mesh mesh;
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::unique_ptr<curvature::EnergyTerm> bending;
  std::vector<std::unique_ptr<curvature::EnergyTerm>> membrane;  // empty unless young > 0
  Eigen::VectorXd restXi;                                        // midedge only

  Plate(modeling::MeshFamily family, int n, curvature::Discretization d, double young = 0.0) {
    modeling::GeneratorOptions g;
    g.family = family;
    g.n = n;
    mesh = modeling::generateMesh(g);
    stencils = modeling::compileStencils(mesh);
    rest = modeling::precomputeRestState(stencils, mesh.positions);
    curvature::BendingOptions b;
    b.discretization = d;
    bending = curvature::makeBendingEnergy(stencils, rest, b);
    if (young > 0.0) {
      curvature::MembraneOptions m;
      m.young = young;
      membrane = curvature::makeMembraneEnergy(stencils, rest, m);
    }
    if (d == curvature::Discretization::Midedge)
      restXi = curvature::midedgeRestXi(stencils, rest, b.restCurvature);
  }

  std::vector<const curvature::EnergyTerm*> terms() const {
    std::vector<const curvature::EnergyTerm*> t = {bending.get()};
    for (const auto& term : membrane) t.push_back(term.get());
    return t;
  }
};

}  // namespace flexure::testing
