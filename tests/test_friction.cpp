// Friction at the contacts (optimize/assembly/friction.h, IPC's lagged smoothed Coulomb
// friction): the mollifier; the assembled gradient and Hessian of one lagged state against finite
// differences, at the analytic obstacles and at the collision mesh's pairs (shell against shell,
// against a moving mesh obstacle); a stiff sheet on a slope tilted by θ — the analytic plane, a
// mesh obstacle, a held sheet of the same mesh — stays for tan θ < μ and slides with the
// acceleration g (sin θ − μ cos θ) for tan θ > μ; μ = 0 and friction without contacts leave a run
// bit for bit unchanged; bad coefficients refused.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "modeling/errors.h"
#include "optimize/assembly/friction.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/assembly/self_contact.h"
#include "optimize/dynamics/time_stepping.h"
#include "support/assembled_derivatives.h"
#include "support/plate.h"

namespace flexure {
namespace {

using curvature::Discretization;
using modeling::Positions;
using optimize::DynamicsOptions;
using optimize::Friction;
using optimize::Obstacle;
using optimize::ObstacleBarrier;
using optimize::obstacleFrictionContacts;

constexpr double pi = 3.14159265358979323846;
constexpr double g = 9.81;

TEST(Friction, MollifierIsC1WithItsDerivative) {
  const double slip = 0.2;
  double f1 = -1.0;
  EXPECT_DOUBLE_EQ(optimize::frictionMollifier(0.0, slip, &f1), slip / 3.0);
  EXPECT_EQ(f1, 0.0);  // no friction force at rest
  for (const double s : {0.05, 0.3, 0.7, 0.99, 1.5}) {
    const double y = s * slip, eps = 1e-6 * slip;
    optimize::frictionMollifier(y, slip, &f1);
    const double fd =
        (optimize::frictionMollifier(y + eps, slip) - optimize::frictionMollifier(y - eps, slip)) /
        (2 * eps);
    EXPECT_NEAR(f1, fd, 1e-8) << "y / ε = " << s;
    EXPECT_GE(f1, 0.0);
    EXPECT_LE(f1, 1.0);
  }
  // f₀ and f₁ continuous at ε (f₀(ε) = ε, f₁(ε) = 1).
  double below = 0.0;
  EXPECT_NEAR(optimize::frictionMollifier(slip * (1 - 1e-12), slip, &below), slip, 1e-12);
  EXPECT_NEAR(below, 1.0, 1e-10);
}

// D of one lagged state (a jittered sheet within the layer of a tilted plane and a sphere, moved
// by tangential and normal displacements both below and beyond ε): its assembled gradient against
// central differences of D, its Hessian against those of the gradient, each contact's block
// positive semidefinite, and the work ∇D·(x − x_n) ≥ 0.
// D, its gradient and Hessian at x on `assembly`'s pattern, the value checked against energy(x).
optimize::HessianEvaluation evaluated(const Friction& friction,
                                      const optimize::HessianAssembly& assembly,
                                      const Positions& x) {
  optimize::HessianEvaluation e;
  e.gradient = Eigen::VectorXd::Zero(assembly.size());
  e.values.assign(assembly.rowIndex().size(), 0.0);
  friction.add(assembly, x, e);
  EXPECT_NEAR(e.energy, friction.energy(x), 1e-14 * std::abs(e.energy));
  return e;
}

TEST(Friction, AssembledGradientAndHessianMatchFiniteDifferences) {
  const testing::Plate plate(modeling::MeshFamily::Patch48, 4, Discretization::Hinge, 1e3);
  const int vertexCount = plate.mesh.vertexCount();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  Positions start = plate.rest.positions;
  for (int v = 0; v < vertexCount; ++v)
    for (int c = 0; c < 3; ++c) start(v, c) += jitter(random);
  const double layer = 0.3, slip = 0.03;
  const std::vector<Obstacle> obstacles = {
      optimize::parseObstacle("--obstacle", "plane:0.2,0.1,1,-0.25"),
      optimize::parseObstacle("--obstacle", "sphere:0.2,0,0.6,0.5")};
  Eigen::VectorXd stiffness(vertexCount);
  for (int v = 0; v < vertexCount; ++v) stiffness[v] = 1.0 + 0.1 * v;
  const ObstacleBarrier barrier(obstacles, layer, stiffness);
  ASSERT_GT(barrier.smallestDistance(start), 0.0);
  std::vector<bool> held(vertexCount, false);
  held[0] = true;  // a pinned vertex has no contact
  const Friction friction(obstacleFrictionContacts(barrier, start, held), start, 0.4, slip);
  ASSERT_GT(friction.contactCount(), 10);

  Positions x = start;
  std::uniform_real_distribution<double> move(-2.0 * slip, 2.0 * slip);
  for (int v = 0; v < vertexCount; ++v)
    for (int c = 0; c < 3; ++c) x(v, c) += v % 3 == 0 ? 0.0 : move(random);  // some at y = 0

  const std::vector<bool> free(3 * vertexCount, true);
  const optimize::HessianAssembly assembly(plate.terms(), free, vertexCount,
                                           curvature::Derivatives::All);
  const optimize::HessianEvaluation e = evaluated(friction, assembly, x);
  ASSERT_GT(e.energy, 0.0);

  const int active = testing::expectAssembledDerivativesMatch(assembly, e, x, friction);
  const Eigen::MatrixXd dense = testing::denseHessian(assembly, e.values);
  EXPECT_GT(active, 10);
  EXPECT_EQ(e.gradient.segment(0, 3).norm(), 0.0);  // the held vertex 0
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(dense);
  EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * eigen.eigenvalues().maxCoeff());
  EXPECT_GT(friction.work(x), 0.0);
  EXPECT_EQ(friction.work(start), 0.0);
  // No coefficient, no contacts.
  EXPECT_TRUE(Friction(obstacleFrictionContacts(barrier, start, held), start, 0.0, slip).empty());
}

// Friction at the collision mesh's pairs (SelfContact::frictionContacts): a sheet lying within the
// layer above another, and a box mesh obstacle moving sideways under the lower one. Every
// contact's weights sum to 0 (a common translation of its vertices moves neither closest point
// relative to the other) unless an obstacle vertex is among them; the assembled gradient and
// Hessian match central differences and the Hessian is positive semidefinite.
TEST(Friction, PairContactsDerivativesMatchFiniteDifferences) {
  const modeling::Mesh sheet = testing::generatedPlate(modeling::MeshFamily::Patch48, 3);
  const int v = sheet.vertexCount(), f = sheet.faceCount();
  modeling::Mesh both;  // apart at rest: nothing exempt
  both.positions.resize(2 * v, 3);
  both.positions << sheet.positions, sheet.positions.rowwise() + Eigen::RowVector3d(0.05, 0.03, 1);
  both.triangles.resize(2 * f, 3);
  both.triangles << sheet.triangles, sheet.triangles.array() + v;
  const modeling::Stencils stencils = modeling::compileStencils(both);
  const double layer = 0.05, slip = 0.01;
  optimize::SelfContact contact(stencils.faces, stencils.edges, both.positions, layer, 2.0);
  modeling::Mesh box;
  box.positions.resize(4, 3);
  box.positions << -1, -1, -0.03, 1, -1, -0.03, 1, 1, -0.03, -1, 1, -0.03;
  box.triangles.resize(2, 3);
  box.triangles << 0, 1, 2, 0, 2, 3;
  contact.addObstacles({{box, optimize::PinMotion::translation({0.3, 0.1, 0}), "slab"}}, true);
  contact.setObstacleTime(0.0);

  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.2 * layer, 0.2 * layer);
  Positions start = both.positions;
  for (int k = v; k < 2 * v; ++k) start(k, 2) = 0.5 * layer + jitter(random);
  const std::vector<optimize::FrictionContact> contacts = contact.frictionContacts(start, 0.1);
  int shellPairs = 0, obstaclePairs = 0;
  for (const optimize::FrictionContact& c : contacts) {
    EXPECT_GT(c.normalForce, 0.0);
    EXPECT_NEAR((c.basis.transpose() * c.basis - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-14);
    const bool onShell =
        (c.vertices[0] >= 0) + (c.vertices[1] >= 0) + (c.vertices[2] >= 0) + (c.vertices[3] >= 0) ==
        4;
    if (onShell) EXPECT_NEAR(c.weights.sum(), 0.0, 1e-12);
    shellPairs += onShell;
    obstaclePairs += !onShell && c.offset.norm() > 0.0;
  }
  EXPECT_GT(shellPairs, 10);
  EXPECT_GT(obstaclePairs, 4);
  const Friction friction(contacts, start, 0.4, slip);

  Positions x = start;
  std::uniform_real_distribution<double> move(-2.0 * slip, 2.0 * slip);
  for (int k = 0; k < 2 * v; ++k)
    for (int c = 0; c < 3; ++c) x(k, c) += k % 3 == 0 ? 0.0 : move(random);
  const std::vector<bool> free(3 * 2 * v, true);
  const optimize::HessianAssembly assembly({}, free, 2 * v, curvature::Derivatives::All,
                                           contact.couplings(start, x - start));
  const optimize::HessianEvaluation e = evaluated(friction, assembly, x);
  ASSERT_GT(e.energy, 0.0);
  EXPECT_GT(testing::expectAssembledDerivativesMatch(assembly, e, x, friction), 20);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(
      testing::denseHessian(assembly, e.values));
  EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * eigen.eigenvalues().maxCoeff());
  EXPECT_EQ(friction.work(start), 0.0);
}

// What the sheet slides on: the analytic plane, a mesh obstacle (one large triangle in the same
// plane, whose edges the sheet never nears: its contacts are vertex–face pairs), or a second,
// larger sheet of the same mesh held in that plane (shell against shell: vertex–face and
// edge–edge pairs).
enum class Slope { Plane, MeshObstacle, HeldSheet };

// A stiff sheet (patch48 n = 3, hinge, StVK E = 1e5) on the plane through the origin tilted by θ
// about y (normal (−sin θ, 0, cos θ)), gravity −z: lying parallel to it at 0.6 d̂, it settles
// under mass damping with backward Euler (μ = 2: it cannot slide), then moves undamped from rest
// with the coefficient μ for `duration` seconds. Returns the mean displacement of its vertices
// down the slope (−(cos θ, 0, sin θ)) after each step of h, and the stepper's balance at the end.
struct Slide {
  std::vector<double> time, downhill;
  optimize::EnergyBalance balance;
  optimize::BalanceVerdict verdict = optimize::BalanceVerdict::Balanced;
  double length = 0.0;  // L, the rest mesh's bounding-box diagonal (the slip speed's unit)
  double mass = 0.0;    // the sliding sheet's
};

// The sheet (rows [0, #sheet)) and, for a held sheet, the 3 × larger patch48 n = 9 (the same edge
// length) after it, 1 above it at rest (apart: nothing exempt).
modeling::Mesh slidingMesh(Slope slope) {
  const modeling::Mesh sheet = testing::generatedPlate(modeling::MeshFamily::Patch48, 3);
  if (slope != Slope::HeldSheet) return sheet;
  const modeling::Mesh ground = testing::generatedPlate(modeling::MeshFamily::Patch48, 9);
  const int v = sheet.vertexCount();
  modeling::Mesh both;
  both.positions.resize(v + ground.vertexCount(), 3);
  both.positions << sheet.positions,
      (3.0 * ground.positions).rowwise() - Eigen::RowVector3d(0, 0, 1);
  both.triangles.resize(sheet.faceCount() + ground.faceCount(), 3);
  both.triangles << sheet.triangles, ground.triangles.array() + v;
  return both;
}

Slide slideOnSlope(double theta, double mu, double duration, double h, Slope slope = Slope::Plane) {
  const Eigen::Vector3d normal(-std::sin(theta), 0.0, std::cos(theta));
  const Eigen::Vector3d down = -Eigen::Vector3d(std::cos(theta), 0.0, std::sin(theta));
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const modeling::Mesh mesh = slidingMesh(slope);
  const int sheetVertices = testing::generatedPlate(modeling::MeshFamily::Patch48, 3).vertexCount();
  const int vertexCount = mesh.vertexCount();
  optimize::ProblemOptions options = testing::plateProblem(Discretization::Hinge, 1e5);
  options.load.gravity = Eigen::Vector3d(0.0, 0.0, -g);
  options.selfContact = slope == Slope::HeldSheet;
  if (slope == Slope::Plane)
    options.obstacles = {optimize::parseObstacle(
        "obstacle",
        "plane:" + std::to_string(normal.x()) + ",0," + std::to_string(normal.z()) + ",0")};
  if (slope == Slope::MeshObstacle) {
    modeling::Mesh triangle;
    triangle.positions.resize(3, 3);
    triangle.positions << -4, -4, 0, -4, 4, 0, 2, 0, 0;
    triangle.positions = (triangle.positions * tilt.transpose()).eval();
    triangle.triangles.resize(1, 3);
    triangle.triangles << 0, 1, 2;
    options.meshObstacles = {{triangle, optimize::PinMotion(), "slope"}};
  }
  const Eigen::RowVector3d centre = mesh.positions.topRows(sheetVertices).colwise().mean();
  Positions x = (mesh.positions.rowwise() - centre) * tilt.transpose();
  if (slope == Slope::HeldSheet) {
    x.bottomRows(vertexCount - sheetVertices) =
        3.0 * testing::generatedPlate(modeling::MeshFamily::Patch48, 9).positions *
        tilt.transpose();
    options.fixedVertex.assign(vertexCount, true);
    std::fill(options.fixedVertex.begin(), options.fixedVertex.begin() + sheetVertices, false);
  }
  if (slope == Slope::HeldSheet) options.boundaryPositions = x;  // the held sheet's place
  const optimize::Problem problem = optimize::buildProblem(mesh, options);

  DynamicsOptions settling;
  settling.integrator = optimize::Integrator::BackwardEuler;
  settling.rayleighMass = 20.0;
  settling.friction = 2.0;
  optimize::TimeStepper settle(problem, settling);
  const double layer =
      slope == Slope::Plane ? settle.barrier().layer() : settle.selfContact().layer();
  x.topRows(sheetVertices).rowwise() += 0.6 * layer * normal.transpose();
  const Positions rest = Positions::Zero(vertexCount, 3);
  settle.start(x, rest, Eigen::VectorXd());
  for (int k = 0; k < 100; ++k) {
    const auto outcome = settle.step(0.005);
    EXPECT_TRUE(outcome.converged) << "settling step " << k << ": " << outcome.failure;
  }

  DynamicsOptions sliding;
  // The strict stop: the settled sheet's energy scale (6e-7) is below what a Newton stop at the
  // default ε_v leaves in the balance (at 1e-4 the mesh obstacle's first step gains 25 % of it,
  // beyond the 5 % tolerance), and a velocity error of ε_v l per second is friction's own slip
  // speed at 1e-3 (friction.h).
  sliding.stepTolerance = 1e-9;
  sliding.integrator = optimize::Integrator::BackwardEuler;
  sliding.friction = mu;
  optimize::TimeStepper stepper(problem, sliding);
  const Positions settled = settle.positions();
  stepper.start(settled, rest, settle.xi());
  Slide slide;
  slide.length = (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).norm();
  slide.mass = stepper.masses().head(sheetVertices).sum();
  const int steps = static_cast<int>(std::lround(duration / h));
  for (int k = 0; k < steps; ++k) {
    const auto outcome = stepper.step(h);
    EXPECT_TRUE(outcome.converged) << "step " << k << ": " << outcome.failure;
    const double closest = slope == Slope::Plane
                               ? stepper.barrier().smallestDistance(stepper.positions())
                               : stepper.selfContact().census(stepper.positions()).smallestDistance;
    EXPECT_GT(closest, 0.0);
    slide.time.push_back(stepper.time());
    slide.downhill.push_back((stepper.positions() - settled)
                                 .topRows(sheetVertices)
                                 .colwise()
                                 .mean()
                                 .dot(down.transpose()));
  }
  slide.balance = stepper.balance();
  slide.verdict = stepper.balanceVerdict();
  return slide;
}

class FrictionOnSlope : public ::testing::TestWithParam<Slope> {};

std::string slopeName(const ::testing::TestParamInfo<Slope>& info) {
  switch (info.param) {
    case Slope::Plane:
      return "Plane";
    case Slope::MeshObstacle:
      return "MeshObstacle";
    case Slope::HeldSheet:
      return "HeldSheet";
  }
  return "";
}

// tan 20° = 0.36 < μ = 0.5: the sheet stays (it creeps below the slip speed ε_v = 1e-3 L/s).
TEST_P(FrictionOnSlope, SheetStaysBelowTheFrictionAngle) {
  const Slide slide = slideOnSlope(20.0 * pi / 180.0, 0.5, 0.5, 0.005, GetParam());
  const double largest = std::abs(slide.downhill.back());
  std::printf("stick: mean displacement down the slope after 0.5 s %.3e (L = %.3g)\n", largest,
              slide.length);
  EXPECT_LT(largest, 1e-3 * slide.length * 0.5);  // slower than the slip speed ε_v = 1e-3 L/s
  EXPECT_NE(slide.verdict, optimize::BalanceVerdict::Gained);
}

// tan 30° = 0.58 > μ = 0.3: the sheet slides with a = g (sin θ − μ cos θ) (the fit of the mean
// displacement to c + b t + ½ a t² over t ≥ 0.05 s: backward Euler adds ½ a h t to the motion
// under a constant force), and the work against friction is μ g cos θ M × the distance slid.
TEST_P(FrictionOnSlope, SheetSlidesBeyondTheFrictionAngle) {
  const double theta = 30.0 * pi / 180.0, mu = 0.3, h = 0.005;
  const Slide slide = slideOnSlope(theta, mu, 0.5, h, GetParam());
  const double expected = g * (std::sin(theta) - mu * std::cos(theta));
  Eigen::MatrixXd basis(0, 3);
  Eigen::VectorXd values(0);
  for (size_t k = 0; k < slide.time.size(); ++k) {
    const double t = slide.time[k];
    if (t < 0.05) continue;
    basis.conservativeResize(basis.rows() + 1, 3);
    values.conservativeResize(values.size() + 1);
    basis.row(basis.rows() - 1) << 1.0, t, 0.5 * t * t;
    values[values.size() - 1] = slide.downhill[k];
  }
  const Eigen::Vector3d fit = basis.colPivHouseholderQr().solve(values);
  const double distance = slide.downhill.back();
  const double work = mu * g * std::cos(theta) * slide.mass * distance;
  std::printf(
      "slide: a = %.6g (expected %.6g), slid %.4g, friction and damping work %.6g (μ g cos θ M "
      "s = %.6g), balance drift %.3g %%\n",
      fit[2], expected, distance, slide.balance.dissipated, work,
      100.0 * slide.balance.relativeDrift());
  EXPECT_NEAR(fit[2], expected, 0.02 * expected);
  // On a held sheet each sliding vertex has several contacts (the faces around the ground vertex
  // beneath it, edge–edge pairs), not all normal to the slope: their friction also takes energy
  // from the sheet's jitter across the ground's edges, measured 7 % above μ g cos θ M s.
  const double share = GetParam() == Slope::HeldSheet ? 0.1 : 0.02;
  EXPECT_NEAR(slide.balance.dissipated, work, share * work);
  EXPECT_NE(slide.verdict, optimize::BalanceVerdict::Gained);
}

INSTANTIATE_TEST_SUITE_P(Surfaces, FrictionOnSlope,
                         ::testing::Values(Slope::Plane, Slope::MeshObstacle, Slope::HeldSheet),
                         slopeName);

// Friction while no vertex is within the layer (a sheet falling towards a plane it does not
// reach) leaves the frictionless run bit for bit; μ = 0 counts no work against friction.
TEST(Friction, NoCoefficientOrNoContactLeavesTheRunUnchanged) {
  const testing::Plate plate(
      modeling::MeshFamily::Patch48, 3, Discretization::Hinge, 1e4,
      [](optimize::ProblemOptions& p, const modeling::Stencils&) {
        p.load.gravity = Eigen::Vector3d(0.0, 0.0, -g);
        p.obstacles = {optimize::parseObstacle("obstacle", "plane:0,0,1,-1")};
      });
  const int vertexCount = plate.mesh.vertexCount();
  const auto run = [&](double mu, double drop) {
    DynamicsOptions o;
    o.friction = mu;
    optimize::TimeStepper stepper(plate.problem, o);
    Positions x = plate.rest.positions;
    x.col(2).array() -= drop;
    stepper.start(x, Positions::Zero(vertexCount, 3), Eigen::VectorXd());
    for (int k = 0; k < 40; ++k) EXPECT_TRUE(stepper.step(0.01).converged);
    return stepper.state();
  };
  // Landing undamped without friction: nothing is counted as dissipated.
  EXPECT_EQ(run(0.0, 0.95).balance.dissipated, 0.0);
  const optimize::TimeStepper::State frictionless = run(0.0, 0.0);
  const optimize::TimeStepper::State high = run(0.8, 0.0);  // falls 0.2 of the 1 in 0.4 s
  EXPECT_EQ(frictionless.x, high.x);
  EXPECT_EQ(frictionless.v, high.v);
  EXPECT_EQ(frictionless.balance.last, high.balance.last);
}

TEST(Friction, BadCoefficientsAreRefused) {
  for (const double mu :
       {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    DynamicsOptions o;
    o.friction = mu;
    try {
      o.validate();
      ADD_FAILURE() << "μ = " << mu << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("DynamicsOptions.friction"), std::string::npos)
          << e.what();
    }
  }
  DynamicsOptions o;
  o.friction = 0.7;
  EXPECT_NO_THROW(o.validate());
}

}  // namespace
}  // namespace flexure
