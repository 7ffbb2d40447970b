// Shared set-ups of the energy tests: a bending term bound to a rest mesh, random smooth surfaces
// and rigid motions, and the unknown vector (positions row by row, then ξ) of
// optimize/assembly/energy_evaluation.h.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/energy_registry.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/linear/least_squares.h"
#include "optimize/problem.h"

namespace flexure::testing {

using curvature::BendingOptions;
using curvature::Discretization;
using curvature::RestCurvature;
using modeling::Positions;

// The built-in energies, from the registry (energies registered by a test are not among them).
inline const std::vector<Discretization> kAllDiscretizations = curvature::builtinDiscretizations();

inline BendingOptions bendingOptions(Discretization d,
                                     RestCurvature restCurvature = RestCurvature::FromRest) {
  BendingOptions o;
  o.discretization = d;
  o.restCurvature = restCurvature;
  return o;
}

// A problem with nothing held: one bending term on a rest mesh (optimize::buildProblem), with its
// rest ξ̄ (midedge; else empty).
inline optimize::ProblemOptions unheldProblem(const BendingOptions& options) {
  optimize::ProblemOptions o;
  o.bending = options;
  o.fixedRings = 0;
  o.boundaryNormals = optimize::BoundaryNormals::Free;
  return o;
}

// Built in place (its references point into `problem`).
struct BendingSetup {
  optimize::Problem problem;
  const modeling::Stencils& stencils = problem.stencils;
  const modeling::RestState& rest = problem.rest;
  const std::unique_ptr<curvature::EnergyTerm>& term = problem.terms.front();
  const Eigen::VectorXd& restXi = problem.restXi;  // #E (midedge), else empty

  BendingSetup(const modeling::Mesh& restMesh, const BendingOptions& options)
      : problem(optimize::buildProblem(restMesh, unheldProblem(options))) {}
  BendingSetup(const BendingSetup&) = delete;
  BendingSetup& operator=(const BendingSetup&) = delete;

  std::vector<const curvature::EnergyTerm*> terms() const { return problem.termPointers(); }

  // ξ minimizing E at positions x over every edge (boundary edges free); ξ̄ for other terms.
  Eigen::VectorXd minimizedXi(const Positions& x) const {
    if (!term->usesEdgeUnknowns()) return restXi;
    const std::vector<bool> allFree(stencils.edgeCount(), true);
    return optimize::minimizeEdgeUnknowns(terms(), x, restXi, allFree);
  }

  // E at x, with ξ minimized for midedge.
  double relaxedEnergy(const Positions& x) const {
    return optimize::relaxedEnergy(terms(), x, restXi,
                                   std::vector<bool>(stencils.edgeCount(), true));
  }
};

inline modeling::Mesh lifted(modeling::Mesh mesh, const modeling::PolynomialSurface& p) {
  modeling::applyHeightField(p, mesh.positions);
  return mesh;
}

// z = Σ c_ij x^i y^j over 1 ≤ i + j ≤ 3 with c_ij uniform in [−scale, scale].
inline modeling::PolynomialSurface randomCubic(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> coefficient(-scale, scale);
  std::vector<modeling::Monomial> terms;
  for (int degree = 1; degree <= 3; ++degree)
    for (int i = 0; i <= degree; ++i) terms.push_back({coefficient(rng), i, degree - i});
  return modeling::PolynomialSurface(std::move(terms));
}

// A uniformly random rotation (normalized Gaussian quaternion).
inline Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  Eigen::Quaterniond q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
  return q.normalized().toRotationMatrix();
}

// x ↦ s R x + t, row by row.
inline Positions transformed(const Positions& x, const Eigen::Matrix3d& rotation,
                             const Eigen::Vector3d& translation, double scale = 1.0) {
  Positions y(x.rows(), 3);
  for (int v = 0; v < x.rows(); ++v)
    y.row(v) = (scale * rotation * x.row(v).transpose() + translation).transpose();
  return y;
}

// Adds uniform noise in [−amplitude, amplitude] to every coordinate.
inline Positions jittered(Positions x, std::mt19937& rng, double amplitude) {
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  for (int v = 0; v < x.rows(); ++v)
    for (int c = 0; c < 3; ++c) x(v, c) += noise(rng);
  return x;
}

}  // namespace flexure::testing
