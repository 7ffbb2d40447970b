// optimize::buildProblem against the hand-built path it replaces (stencils, rest state,
// makeBendingEnergy, makeMembraneEnergy, midedgeRestXi, surfaceBoundary, the lumped load), and
// ProblemOptions::validate naming its fields.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/vertex_quantities.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"
#include "optimize/solvers/static_energy.h"
#include "support/energy_fixtures.h"

namespace flexure {
namespace {

using curvature::Discretization;
using modeling::Mesh;
using modeling::Positions;
using optimize::BoundaryNormals;
using optimize::DofMode;
using optimize::ProblemOptions;

Mesh curvedPatch() {
  std::mt19937 rng(11);
  return testing::lifted(modeling::generateMesh({modeling::MeshFamily::Delaunay, 5, 7, {}}),
                         testing::randomCubic(rng, 0.5));
}

// A current state near rest: another cubic on the same x̄, ȳ, jittered.
Positions currentState(const Mesh& rest) {
  std::mt19937 rng(12);
  Mesh flat = rest;
  flat.positions.col(2).setZero();
  return testing::jittered(testing::lifted(flat, testing::randomCubic(rng, 0.5)).positions, rng,
                           0.01);
}

ProblemOptions optionsFor(Discretization d, DofMode dof) {
  ProblemOptions o;
  o.bending.discretization = d;
  o.dof = dof;
  if (dof == DofMode::Xyz) o.membrane = curvature::MembraneOptions{};
  o.boundarySurface = modeling::PolynomialSurface::parse("quadratic:0.3,-0.2,0.4");
  o.boundaryNormals = BoundaryNormals::Clamped;
  return o;
}

std::string whatOf(const ProblemOptions& o) {
  try {
    o.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Every energy, height and xyz: the same terms (energies at a current state, element counts), ξ̄
// and boundary conditions as built by hand from the same mesh.
TEST(Problem, BuildsWhatTheHandBuiltPathBuilds) {
  const Mesh mesh = curvedPatch();
  const Positions x = currentState(mesh);
  const modeling::Stencils stencils = modeling::compileStencils(mesh);
  const modeling::RestState rest = modeling::precomputeRestState(stencils, mesh.positions);
  for (Discretization d : testing::kAllDiscretizations) {
    for (DofMode dof : {DofMode::Height, DofMode::Xyz}) {
      SCOPED_TRACE(std::string(curvature::discretizationName(d)) +
                   (dof == DofMode::Xyz ? " xyz" : " height"));
      const ProblemOptions o = optionsFor(d, dof);
      const optimize::Problem problem = optimize::buildProblem(mesh, o);

      std::vector<std::unique_ptr<curvature::EnergyTerm>> terms;
      terms.push_back(curvature::makeBendingEnergy(stencils, rest, o.bending));
      if (o.membrane)
        for (auto& t : curvature::makeMembraneEnergy(stencils, rest, *o.membrane))
          terms.push_back(std::move(t));
      const bool midedge = d == Discretization::Midedge;
      const Eigen::VectorXd restXi =
          midedge ? curvature::midedgeRestXi(stencils, rest, o.bending.restCurvature)
                  : Eigen::VectorXd();
      const std::vector<bool> fixed = optimize::fixedRings(stencils, 2);
      const optimize::BoundaryConditions bc = optimize::surfaceBoundary(
          stencils, rest.positions, restXi, fixed, *o.boundarySurface, o.boundaryNormals, false);

      EXPECT_EQ(problem.dof, dof);
      EXPECT_EQ(problem.rest.positions, rest.positions);
      ASSERT_EQ(problem.terms.size(), terms.size());
      EXPECT_EQ(problem.termPointers().front(), &problem.bending());
      EXPECT_EQ(problem.usesEdgeUnknowns(), midedge);
      ASSERT_EQ(problem.restXi.size(), restXi.size());
      EXPECT_EQ(problem.restXi, restXi);
      const Eigen::VectorXd xi = midedge ? Eigen::VectorXd(restXi.array() + 0.05) : restXi;
      for (size_t k = 0; k < terms.size(); ++k) {
        EXPECT_EQ(problem.terms[k]->name(), terms[k]->name());
        EXPECT_EQ(problem.terms[k]->elementCount(), terms[k]->elementCount());
        const double e = terms[k]->energy(x, xi);
        EXPECT_GT(e, 0.0);
        EXPECT_EQ(problem.terms[k]->energy(x, xi), e);
      }
      EXPECT_EQ(problem.boundary.fixedVertex, bc.fixedVertex);
      EXPECT_EQ(problem.boundary.start, bc.start);
      EXPECT_EQ(problem.boundary.fixedEdge, bc.fixedEdge);
      EXPECT_EQ(problem.boundary.xi, bc.xi);
      if (midedge) {
        EXPECT_GT(std::count(bc.fixedEdge.begin(), bc.fixedEdge.end(), true), 0);
      }
      EXPECT_EQ(problem.externalForce.size(), 0);
      EXPECT_TRUE(problem.obstacles.empty());
    }
  }
}

// The one ξ̄ of a curved rest: midedgeRestXi's, not zero there.
TEST(Problem, MidedgeRestXiIsTheRestMinimizer) {
  const Mesh mesh = curvedPatch();
  ProblemOptions o;
  o.bending.discretization = Discretization::Midedge;
  o.boundaryNormals = BoundaryNormals::Free;
  const optimize::Problem problem = optimize::buildProblem(mesh, o);
  const Eigen::VectorXd expected =
      curvature::midedgeRestXi(problem.stencils, problem.rest, curvature::RestCurvature::FromRest);
  ASSERT_EQ(problem.restXi.size(), problem.stencils.edgeCount());
  EXPECT_GT(expected.lpNorm<Eigen::Infinity>(), 1e-3);
  EXPECT_EQ(problem.restXi, expected);
  // Free normals: every ξ free, starting at ξ̄; the rest is an equilibrium of the problem.
  EXPECT_EQ(problem.boundary.xi, expected);
  EXPECT_EQ(std::count(problem.boundary.fixedEdge.begin(), problem.boundary.fixedEdge.end(), true),
            0);
  EXPECT_LE(problem.bending().energy(mesh.positions, problem.restXi), 1e-24);
}

// Held vertices by mask and by rings; given boundary positions; the gravity load m_v g and the
// obstacle barrier of the stated rule.
TEST(Problem, BoundaryValuesAndLoads) {
  const Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Patch48, 6, 1, {}});
  ProblemOptions o;
  o.bending.discretization = Discretization::Hinge;
  o.fixedRings = 1;
  Positions given = mesh.positions;
  given.col(2).setConstant(0.25);
  o.boundaryPositions = given;
  o.load.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  o.load.density = 2.0;
  optimize::Obstacle floor;
  floor.scalar = -1.0;  // z = −1
  o.obstacles = {floor};
  const optimize::Problem ringed = optimize::buildProblem(mesh, o);
  EXPECT_EQ(ringed.boundary.fixedVertex, optimize::fixedRings(ringed.stencils, 1));
  EXPECT_EQ(ringed.boundary.start, given);
  const Eigen::VectorXd mass =
      modeling::lumpedVertexMasses(ringed.rest, modeling::MassLumping::Barycentric, o.load.density);
  ASSERT_EQ(ringed.externalForce.rows(), mesh.vertexCount());
  EXPECT_EQ(ringed.externalForce.col(2), -9.81 * mass);
  EXPECT_EQ(ringed.externalForce.col(0).cwiseAbs().maxCoeff(), 0.0);
  // The total weight is ρ g times the plate's area (the unit square).
  EXPECT_NEAR(ringed.externalForce.col(2).sum(), -9.81 * 2.0, 1e-12);
  ASSERT_FALSE(ringed.obstacles.empty());
  EXPECT_GT(ringed.obstacles.layer(), 0.0);

  o.fixedVertex.assign(mesh.vertexCount(), false);
  o.fixedVertex[3] = true;
  const optimize::Problem masked = optimize::buildProblem(mesh, o);
  EXPECT_EQ(masked.boundary.fixedVertex, o.fixedVertex);
  o.fixedVertex.pop_back();
  EXPECT_THAT(
      [&] { optimize::buildProblem(mesh, o); },
      ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("ProblemOptions.fixedVertex has")));
  o.fixedVertex.clear();
  o.boundaryPositions = given.topRows(5);
  EXPECT_THAT([&] { optimize::buildProblem(mesh, o); },
              ::testing::ThrowsMessage<InputError>(
                  ::testing::HasSubstr("ProblemOptions.boundaryPositions has 5 rows")));
}

// A midedge clamp built for a nonlinear solve is refused by a linearized one, and the other way.
// Held ξ by mask (at ξ̄) and a membrane whose rest shape is not the rest mesh's: its energy
// vanishes there, not at rest; masses and gravity are the load's.
TEST(Problem, HeldEdgesMembraneRestAndMasses) {
  const Mesh mesh = curvedPatch();
  ProblemOptions o = optionsFor(Discretization::Midedge, DofMode::Xyz);
  o.boundarySurface.reset();
  o.boundaryNormals = BoundaryNormals::Free;
  const optimize::Problem free = optimize::buildProblem(mesh, o);
  o.fixedEdge.assign(free.stencils.edgeCount(), false);
  o.fixedEdge[2] = o.fixedEdge[5] = true;
  Positions stretched = mesh.positions * 1.1;
  o.membraneRest = stretched;
  o.load.density = 3.0;
  const optimize::Problem p = optimize::buildProblem(mesh, o);
  EXPECT_EQ(p.boundary.fixedEdge, o.fixedEdge);
  EXPECT_EQ(p.boundary.xi, p.restXi);
  ASSERT_EQ(p.terms.size(), 2u);
  EXPECT_GT(p.terms[1]->energy(mesh.positions, p.restXi), 1e-6);
  EXPECT_LE(p.terms[1]->energy(stretched, p.restXi), 1e-20);
  EXPECT_EQ(p.mass, modeling::lumpedVertexMasses(p.rest, modeling::MassLumping::Barycentric, 3.0));
  EXPECT_EQ(p.gravity, Eigen::Vector3d::Zero());
  EXPECT_EQ(p.externalForce.size(), 0);
  o.fixedEdge.pop_back();
  EXPECT_THAT(
      [&] { optimize::buildProblem(mesh, o); },
      ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("ProblemOptions.fixedEdge has")));
  o.fixedEdge.clear();
  o.membraneRest = stretched.topRows(3);
  EXPECT_THAT([&] { optimize::buildProblem(mesh, o); },
              ::testing::ThrowsMessage<InputError>(
                  ::testing::HasSubstr("ProblemOptions.membraneRest has 3")));
}

TEST(Problem, MinimizeRefusesAClampForTheOtherSolve) {
  ProblemOptions o = optionsFor(Discretization::Midedge, DofMode::Height);
  const Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Patch48, 6, 1, {}});
  optimize::MinimizeOptions linearized;
  linearized.linearized = true;
  const optimize::Problem nonlinearClamp = optimize::buildProblem(mesh, o);
  EXPECT_THAT(
      [&] { optimize::minimize(nonlinearClamp, linearized); },
      ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("ProblemOptions.linearizedClamp")));
  o.linearizedClamp = true;
  const optimize::Problem linearClamp = optimize::buildProblem(mesh, o);
  EXPECT_TRUE(optimize::minimize(linearClamp, linearized).report.converged);
  EXPECT_THROW(optimize::minimize(linearClamp, {}), InputError);
  // Free normals hold no ξ: either solve takes the problem.
  o.boundaryNormals = BoundaryNormals::Free;
  EXPECT_TRUE(optimize::minimize(optimize::buildProblem(mesh, o), linearized).report.converged);
}

// An objective's unknowns of another length are refused with both counts, not read past.
TEST(Problem, ObjectiveRefusesUnknownsOfAnotherLength) {
  const optimize::Problem problem =
      optimize::buildProblem(curvedPatch(), optionsFor(Discretization::Hinge, DofMode::Height));
  const std::vector<const curvature::EnergyTerm*> terms = problem.termPointers();
  const optimize::HessianAssembly assembly(terms, problem.freeUnknowns(),
                                           static_cast<int>(problem.rest.positions.rows()),
                                           curvature::Derivatives::HeightOnly);
  optimize::StaticEnergy objective(assembly, {problem.boundary.start, {}}, terms,
                                   problem.externalForce, problem.obstacles,
                                   optimize::HessianProjection::Exact);
  const Eigen::VectorXd right = Eigen::VectorXd::Zero(assembly.size());
  EXPECT_TRUE(std::isfinite(objective.evaluate(right, curvature::SecondDerivatives::None).energy));
  const Eigen::VectorXd longer = Eigen::VectorXd::Zero(assembly.size() + 1);
  EXPECT_THAT([&] { objective.evaluate(longer, curvature::SecondDerivatives::None); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr(
                  "x has " + std::to_string(assembly.size() + 1) + " entries, the problem " +
                  std::to_string(assembly.size()) + " free unknowns")));
}

TEST(Problem, BadOptionsNameTheField) {
  const ProblemOptions good = optionsFor(Discretization::Midedge, DofMode::Height);
  EXPECT_EQ(whatOf(good), "");
  ProblemOptions o = good;
  o.membrane = curvature::MembraneOptions{};
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.membrane applies to"));
  o = good;
  o.dof = DofMode::Xyz;
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.dof xyz needs a membrane"));
  o = good;
  o.fixedRings = -1;
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.fixedRings"));
  o = good;
  o.boundaryPositions = Positions::Zero(4, 3);
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.boundarySurface and"));
  o = good;
  o.boundarySurface.reset();
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.boundaryNormals clamped"));
  o.bending.discretization = Discretization::Hinge;  // no normals to clamp
  EXPECT_EQ(whatOf(o), "");
  o = good;
  o.load.density = 0.0;
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.load.density"));
  o = good;
  o.load.gravity = Eigen::Vector3d(0.0, 0.0, std::nan(""));
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.load.gravity"));
  o = good;
  o.fixedEdge = {true};
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.fixedEdge and"));
  o.boundarySurface.reset();
  EXPECT_EQ(whatOf(o), "");  // held ξ without a surface: no clamp needed
  o.bending.discretization = Discretization::Hinge;
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.fixedEdge holds edge unknowns"));
  o = good;
  o.membraneRest = Positions::Zero(4, 3);
  EXPECT_THAT(whatOf(o), ::testing::HasSubstr("ProblemOptions.membraneRest is the rest shape"));
  // buildProblem validates before compiling the mesh.
  o = good;
  o.dof = DofMode::Xyz;
  EXPECT_THROW(optimize::buildProblem(curvedPatch(), o), InputError);
}

}  // namespace
}  // namespace flexure
