// What is solved, apart from how (as Ceres keeps Problem apart from Solver::Options): the rest
// mesh compiled into stencils and rest state, the energy terms bound to it, the edge unknowns the
// discretization owns (midedge's ξ and their rest values ξ̄), the unknown layout (height or xyz;
// free or held vertices and ξ), the boundary values, the external load and the obstacles.
// buildProblem is the one place that turns options into these; the solvers take termPointers().
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/mesh.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "modeling/vertex_quantities.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/assembly/self_contact.h"
#include "optimize/boundary_conditions.h"

namespace flexure::optimize {

// A constant load: gravity on the lumped vertex masses, f_v = m_v g (m_v = ρ × the vertex's rest
// area, lumpedVertexMasses).
struct LoadOptions {
  std::optional<Eigen::Vector3d> gravity;  // g; empty: no load
  double density = 1.0;                    // ρ, mass per unit rest area
  modeling::MassLumping mass = modeling::MassLumping::Barycentric;
};

struct ProblemOptions {
  curvature::BendingOptions bending;
  std::optional<curvature::MembraneOptions> membrane;  // xyz mode only
  // The membrane's rest shape (#V by 3) when it is not the rest mesh's (fairing keeps the start's
  // triangles); empty: the rest mesh.
  Positions membraneRest;
  // Height: z free, x and y held at rest. Xyz: every coordinate free (needs a membrane: bending
  // alone has no stiffness against sliding in the surface).
  DofMode dof = DofMode::Height;
  // The held vertices: `fixedVertex` (#V) when given, else rings 0 .. fixedRings − 1 (ring 0 =
  // the boundary; 2 rings hold positions and slopes; 0: none).
  std::vector<bool> fixedVertex;
  int fixedRings = 2;
  // The held vertices' values, one of: the rest x̄, ȳ lifted onto z = p(x̄, ȳ) (the free vertices
  // start at rest), or `boundaryPositions` (#V by 3: the held vertices' values and the free ones'
  // start). Neither: the rest positions.
  std::optional<modeling::PolynomialSurface> boundarySurface;
  Positions boundaryPositions;
  // Midedge: boundary ξ clamped to `boundarySurface`'s normals (held), or free (natural). The
  // clamp is linearized about rest when `linearizedClamp` (for a linearized solve).
  BoundaryNormals boundaryNormals = BoundaryNormals::Clamped;
  // Midedge without a boundary surface: the ξ held at their rest values ξ̄ (#E; empty: none), e.g.
  // every boundary edge with two rings held, the clamp that keeps the rest boundary normals.
  std::vector<bool> fixedEdge;
  bool linearizedClamp = false;
  LoadOptions load;
  std::vector<Obstacle> obstacles;  // the barrier of makeObstacleBarrier keeps vertices outside
  // Self-contact (assembly/self_contact.h): every vertex–face and edge–edge pair of the mesh
  // repels; xyz only. The time steps honour it; a static solve does not read it.
  bool selfContact = false;
  // The self-contact's offset d̂ (> 0): pairs closer than d̂ repel; 0 for the rule's ¼ of the mean
  // rest edge length.
  double contactOffset = 0.0;
  // Rigid mesh obstacles, static or moving (assembly/mesh_obstacles.h): they repel the shell
  // through the self-contact's barrier and offset, with self-contact on or off; xyz only, and
  // honoured by the time steps alone.
  std::vector<MeshObstacle> meshObstacles;

  // InputError naming the field ("ProblemOptions.dof …") for options no mesh can satisfy.
  void validate() const;
};

struct Problem {
  modeling::Stencils stencils;
  modeling::RestState rest;  // rest.positions: #V by 3
  DofMode dof = DofMode::Height;
  // The membrane's rest state when ProblemOptions.membraneRest gives one (else null: `rest`).
  std::unique_ptr<modeling::RestState> membraneRest;
  // The bending term first, then the membrane's (none, one or two); a caller may append more (an
  // angle barrier).
  std::vector<std::unique_ptr<curvature::EnergyTerm>> terms;
  // #E: ξ̄ when a term owns edge unknowns (midedge), else empty.
  Eigen::VectorXd restXi;
  // Held vertices (#V) and their values (start, #V by 3); held ξ (#E) and their values.
  BoundaryConditions boundary;
  bool linearizedClamp = false;  // the held ξ are the clamp linearized about rest
  Positions externalForce;       // #V by 3: m_v g; empty without a load
  // The lumped vertex masses m_v = ρ × the vertex's rest area (#V, ProblemOptions.load's ρ and
  // lumping) and the gravity g (zero without a load): the load's, the dynamics' inertia.
  Eigen::VectorXd mass;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  ObstacleBarrier obstacles;  // the stated rule's barrier of ProblemOptions.obstacles; empty: none
  // The rule's self-contact when ProblemOptions.selfContact, with ProblemOptions.meshObstacles;
  // empty: neither.
  SelfContact selfContact;

  const curvature::EnergyTerm& bending() const { return *terms.front(); }
  bool usesEdgeUnknowns() const { return restXi.size() > 0; }
  // The unknowns a static solve moves (freeUnknownMask of the held vertices and ξ, in `dof`).
  std::vector<bool> freeUnknowns() const;
  // Non-owning, in `terms`' order: what the solvers and evaluations take.
  std::vector<const curvature::EnergyTerm*> termPointers() const;
};

// Validates `options`, compiles the stencils and rest state of `rest`, and builds the problem.
// InputError naming the field or the element for what the mesh cannot take (a vertex mask or
// boundary positions of the wrong size, a degenerate rest element).
Problem buildProblem(const modeling::Mesh& rest, const ProblemOptions& options);
// The same from a mesh already compiled (`stencils` and `rest` of one mesh).
Problem buildProblem(modeling::Stencils stencils, modeling::RestState rest,
                     const ProblemOptions& options);

}  // namespace flexure::optimize
