#include "optimize/fairing.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "modeling/cgal_fair.h"
#include "modeling/errors.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/biharmonic.h"
#include "optimize/energy_evaluation.h"

namespace flexure::optimize {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The patch compiled once: its stencils and its rest state (the input's metric).
struct CompiledPatch {
  modeling::Stencils stencils;
  modeling::RestState rest;
  std::vector<int> regionFaces;  // faces touching a moving vertex
};

CompiledPatch compilePatch(const modeling::FairingPatch& patch) {
  CompiledPatch c;
  c.stencils = modeling::compileStencils(patch.mesh);
  c.rest = modeling::precomputeRestState(c.stencils, patch.mesh.positions);
  for (int f = 0; f < c.stencils.faceCount(); ++f) {
    const auto t = c.stencils.faces.row(f);
    if (patch.moves[t(0)] || patch.moves[t(1)] || patch.moves[t(2)]) c.regionFaces.push_back(f);
  }
  return c;
}

curvature::BendingOptions flatRest(curvature::BendingOptions b) {
  b.restCurvature = curvature::RestCurvature::Flat;
  return b;
}

// E_bend of one discretization at `x`, midedge ξ minimized for x.
double bendingEnergy(const CompiledPatch& c, const curvature::BendingOptions& b,
                     const Positions& x) {
  const std::unique_ptr<curvature::EnergyTerm> term =
      curvature::makeBendingEnergy(c.stencils, c.rest, b);
  return relaxedEnergy({term.get()}, x, Eigen::VectorXd::Zero(c.stencils.edgeCount()),
                       std::vector<bool>(c.stencils.edgeCount(), true));
}

TriangleQuality triangleQuality(const CompiledPatch& c, const Positions& x) {
  TriangleQuality q;
  q.minAngleDegrees = 180.0;
  q.minShape = 1.0;
  double shapeSum = 0.0;
  for (int f : c.regionFaces) {
    const auto t = c.stencils.faces.row(f);
    const Eigen::Vector3d p[3] = {x.row(t(0)), x.row(t(1)), x.row(t(2))};
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    double squares = 0.0;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
      squares += a.squaredNorm();
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
      q.minAngleDegrees = std::min(q.minAngleDegrees, angle);
    }
    const double shape = squares > 0.0 ? 4.0 * std::sqrt(3.0) * area / squares : 0.0;
    q.minShape = std::min(q.minShape, shape);
    shapeSum += shape;
  }
  q.meanShape = c.regionFaces.empty() ? 0.0 : shapeSum / static_cast<double>(c.regionFaces.size());
  return q;
}

// The linear fair: each coordinate minimizes Σ_v (L x)_v² / Ā_v with the held vertices fixed.
Positions fairBiharmonic(const modeling::FairingPatch& patch, const CompiledPatch& c) {
  std::vector<bool> held(patch.moves.size());
  for (std::size_t v = 0; v < held.size(); ++v) held[v] = !patch.moves[v];
  Positions x = patch.mesh.positions;
  for (int k = 0; k < 3; ++k) x.col(k) = solveBiharmonic(c.stencils, c.rest, held, x.col(k));
  return x;
}

}  // namespace

curvature::MembraneOptions fairingMembrane(curvature::MembraneModel model, double weight,
                                           double bendingStiffness, double meanEdgeLength) {
  if (!(weight > 0.0) || !std::isfinite(weight))
    throw InputError("--membrane-weight must be positive (got " + std::to_string(weight) + ")");
  const double l = meanEdgeLength;
  curvature::MembraneOptions m;
  m.model = model;
  m.shapeStiffness = weight * bendingStiffness;
  m.young = weight * bendingStiffness / (l * l);
  m.poisson = 0.3;
  m.lengthStiffness = weight * bendingStiffness / l;
  m.areaStiffness = weight * bendingStiffness / (l * l);
  return m;
}

Positions fairBiharmonic(const modeling::FairingPatch& patch) {
  const CompiledPatch c = compilePatch(patch);
  return fairBiharmonic(patch, c);
}

FairingResult fairNonlinear(const modeling::FairingPatch& patch, const FairingOptions& options) {
  const CompiledPatch c = compilePatch(patch);
  const curvature::BendingOptions b = flatRest(options.bending);
  const std::unique_ptr<curvature::EnergyTerm> bending =
      curvature::makeBendingEnergy(c.stencils, c.rest, b);

  BoundaryConditions bc;
  FairingStart start = options.start;
  if (start == FairingStart::Input) {
    bc.start = patch.mesh.positions;
  } else {
    bc.start = fairBiharmonic(patch, c);
    if (start == FairingStart::Best) {
      const bool inputLower =
          bendingEnergy(c, b, patch.mesh.positions) < bendingEnergy(c, b, bc.start);
      start = inputLower ? FairingStart::Input : FairingStart::Biharmonic;
      if (inputLower) bc.start = patch.mesh.positions;
    }
  }
  // The membrane keeps the triangles as they are at the start (their rest state is the start's).
  const modeling::RestState startShape = modeling::precomputeRestState(c.stencils, bc.start);
  double edgeLengthSum = 0.0;
  for (int f : c.regionFaces)
    for (int i = 0; i < 3; ++i) edgeLengthSum += startShape.edgeLengths[c.stencils.faceEdges(f, i)];
  const double meanEdge = edgeLengthSum / (3.0 * static_cast<double>(c.regionFaces.size()));
  const std::vector<std::unique_ptr<curvature::EnergyTerm>> membrane =
      curvature::makeMembraneEnergy(
          c.stencils, startShape,
          fairingMembrane(options.membrane, options.membraneWeight, b.stiffness, meanEdge));
  std::vector<const curvature::EnergyTerm*> terms = {bending.get()};
  for (const auto& term : membrane) terms.push_back(term.get());

  bc.fixedVertex.resize(patch.moves.size());
  for (std::size_t v = 0; v < patch.moves.size(); ++v) bc.fixedVertex[v] = !patch.moves[v];
  Eigen::VectorXd restXi;
  if (bending->usesEdgeUnknowns()) {
    restXi = Eigen::VectorXd::Zero(c.stencils.edgeCount());
    bc.fixedEdge.assign(c.stencils.edgeCount(), false);
    bc.xi = minimizeEdgeUnknowns(terms, bc.start, restXi,
                                 std::vector<bool>(c.stencils.edgeCount(), true));
  }
  MinimizeOptions solver = options.solver;
  solver.dof = DofMode::Xyz;
  solver.linearized = false;
  solver.start = Start::AsGiven;
  MinimizeResult result = minimize(terms, bc, c.rest.positions, restXi, solver);
  return {std::move(result.positions), result.report, start};
}

Positions fairCgal(const modeling::FairingPatch& patch) {
  return modeling::cgalFair(patch.mesh, patch.moves, 1);
}

FairingMeasures measureFairing(const modeling::FairingPatch& patch, const Positions& positions,
                               const curvature::BendingOptions& material) {
  const CompiledPatch c = compilePatch(patch);
  FairingMeasures m;
  for (curvature::Discretization d : curvature::kDiscretizations) {
    curvature::BendingOptions b = flatRest(material);
    b.discretization = d;
    b.vertexArea = material.vertexArea;
    b.hingeAngle = material.hingeAngle;
    if (d == curvature::Discretization::Hinge || d == curvature::Discretization::Cotan)
      b.poisson.reset();
    EnergyMeasure e{std::string(curvature::discretizationName(d)), 0.0, ""};
    try {
      e.value = bendingEnergy(c, b, positions);
    } catch (const std::exception& error) {
      e.value = std::numeric_limits<double>::quiet_NaN();
      e.error = error.what();
    }
    m.bending.push_back(e);
  }
  m.quality = triangleQuality(c, positions);
  m.maxDisplacement = (positions - patch.mesh.positions).rowwise().norm().maxCoeff();
  return m;
}

}  // namespace flexure::optimize
