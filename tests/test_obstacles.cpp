// Obstacles (optimize/assembly/obstacles.h): the barrier's derivatives against finite differences,
// the closed-form contact times, the adaptive stiffness, a sheet dropped on a plane that comes to
// rest on it without a vertex ever inside, and a static minimizer under gravity held up by a
// sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "modeling/errors.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/solvers/minimize.h"
#include "support/assembled_derivatives.h"
#include "support/plate.h"

namespace flexure {
namespace {

using curvature::Discretization;
using modeling::Positions;
using optimize::Obstacle;
using optimize::ObstacleBarrier;

TEST(Obstacles, BarrierPotentialDerivativesMatchFiniteDifferences) {
  const double layer = 0.3;
  for (const double t : {0.01, 0.1, 0.4, 0.7, 0.95}) {
    const double d = t * layer, eps = 1e-6 * layer;
    double d1 = 0.0, d2 = 0.0;
    const double b = optimize::barrierPotential(d, layer, &d1, &d2);
    double p1 = 0.0, m1 = 0.0;
    const double bp = optimize::barrierPotential(d + eps, layer, &p1);
    const double bm = optimize::barrierPotential(d - eps, layer, &m1);
    EXPECT_GT(b, 0.0);
    EXPECT_LT(d1, 0.0);  // repels: decreasing in d
    EXPECT_GT(d2, 0.0);  // convex
    EXPECT_NEAR(d1, (bp - bm) / (2 * eps), 1e-6 * std::abs(d1)) << "d = " << d;
    EXPECT_NEAR(d2, (p1 - m1) / (2 * eps), 1e-6 * std::abs(d2)) << "d = " << d;
  }
  // Zero beyond the layer, C¹ at its edge, infinite on and inside the obstacle.
  double d1 = 1.0;
  EXPECT_EQ(optimize::barrierPotential(layer, layer, &d1), 0.0);
  EXPECT_EQ(d1, 0.0);
  EXPECT_LT(std::abs(optimize::barrierPotential(0.999 * layer, layer)), 1e-8);
  EXPECT_TRUE(std::isinf(optimize::barrierPotential(0.0, layer)));
  EXPECT_TRUE(std::isinf(optimize::barrierPotential(-0.1, layer)));
}

// The assembled barrier gradient and Hessian (on the free unknowns of a shell's pattern) against
// central differences of the energy and of the gradient, with a tilted plane and a sphere both
// within the layer of many vertices.
TEST(Obstacles, AssembledGradientAndHessianMatchFiniteDifferences) {
  const testing::Plate plate(modeling::MeshFamily::Patch48, 4, Discretization::Hinge, 1e3);
  const int vertexCount = plate.mesh.vertexCount();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  Positions x = plate.rest.positions;
  for (int v = 0; v < vertexCount; ++v)
    for (int c = 0; c < 3; ++c) x(v, c) += jitter(random);
  const double layer = 0.3;
  std::vector<Obstacle> obstacles = {optimize::parseObstacle("--obstacle", "plane:0.2,0.1,1,-0.25"),
                                     optimize::parseObstacle("--obstacle", "sphere:0.2,0,0.6,0.5")};
  Eigen::VectorXd stiffness(vertexCount);
  for (int v = 0; v < vertexCount; ++v) stiffness[v] = 1.0 + 0.1 * v;
  const ObstacleBarrier barrier(obstacles, layer, stiffness);
  ASSERT_GT(barrier.smallestDistance(x), 0.0);
  ASSERT_LT(barrier.smallestDistance(x), 0.5 * layer);

  const std::vector<bool> free(3 * vertexCount, true);
  const optimize::HessianAssembly assembly(plate.terms(), free, vertexCount,
                                           curvature::Derivatives::All);
  optimize::HessianEvaluation e;
  e.gradient = Eigen::VectorXd::Zero(assembly.size());
  e.values.assign(assembly.rowIndex().size(), 0.0);
  barrier.add(assembly, x, e, false);
  EXPECT_NEAR(e.energy, barrier.energy(x), 1e-14 * std::abs(e.energy));
  ASSERT_GT(e.energy, 0.0);

  testing::DerivativeTolerance tolerance;
  tolerance.step = 1e-6;
  const int active = testing::expectAssembledDerivativesMatch(assembly, e, x, barrier, tolerance);
  EXPECT_GT(active, 10);
}

TEST(Obstacles, ContactTimesAreExact) {
  const Obstacle floor = optimize::parseObstacle("--obstacle", "plane:0,0,2,-1");  // z = −½
  EXPECT_DOUBLE_EQ(floor.signedDistance(Eigen::Vector3d(3, 1, 1)), 1.5);
  EXPECT_DOUBLE_EQ(floor.contactTime(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, -3)), 0.5);
  EXPECT_TRUE(std::isinf(floor.contactTime(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1))));
  const Obstacle ball = optimize::parseObstacle("--obstacle", "sphere:0,0,0,1");
  EXPECT_DOUBLE_EQ(ball.contactTime(Eigen::Vector3d(0, 0, 3), Eigen::Vector3d(0, 0, -4)), 0.5);
  // A long step that would jump over the sphere: the first contact, at x = −1.
  EXPECT_NEAR(ball.contactTime(Eigen::Vector3d(-3, 0, 0), Eigen::Vector3d(6, 0, 0)), 1.0 / 3.0,
              1e-15);
  // A line that misses it.
  EXPECT_TRUE(std::isinf(ball.contactTime(Eigen::Vector3d(-3, 0, 1.5), Eigen::Vector3d(6, 0, 0))));
  // The step bound keeps 10 % of the way to the first contact.
  const ObstacleBarrier barrier({floor, ball}, 0.1, Eigen::VectorXd::Ones(2));
  Positions x(2, 3), dx(2, 3);
  x << 0, 0, 3, -3, 0, 0;
  dx << 0, 0, -4, 6, 0, 0;
  EXPECT_NEAR(barrier.stepBound(x, dx), 0.9 / 3.0, 1e-15);
  EXPECT_EQ(barrier.stepBound(x, 0.01 * dx), 1.0);
  // Per vertex: the first reaches the sphere at ½ (0.45 with the margin), the second at ⅓.
  const Eigen::VectorXd each = barrier.vertexStepBounds(x, dx);
  EXPECT_NEAR(each[0], 0.9 / 2.0, 1e-15);
  EXPECT_NEAR(each[1], 0.9 / 3.0, 1e-15);
  x.row(0) << 5, 5, 5;  // moving away from both: unbounded, capped at 1
  EXPECT_EQ(barrier.vertexStepBounds(x, dx)[0], 1.0);
}

// The adaptive stiffness (obstacles.h) on single vertices above the floor z = 0, layer d̂ = 0.1,
// with a sphere of radius 1 at x = 10 too, rule stiffness κ̄ = 1, masses 2: an approaching vertex
// outside the layer gets the κ whose barrier holds its normal kinetic energy at d̂/2, however far
// it is; a receding one keeps κ̄; one pressed deeper than d̂/10 grows min(2, d̂/(10 d))-fold per
// call, whatever its approach to the far sphere; none falls inside the layer.
TEST(Obstacles, AdaptiveStiffnessAbsorbsTheApproachAndGrowsWhenPressedDeep) {
  const double layer = 0.1;
  ObstacleBarrier barrier({optimize::parseObstacle("--obstacle", "plane:0,0,1,0"),
                           optimize::parseObstacle("--obstacle", "sphere:10,0,0,1")},
                          layer, Eigen::VectorXd::Ones(5));
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(5, 2.0);
  Positions x(5, 3), v = Positions::Zero(5, 3);
  x << 0, 0, 0.15,  // outside the layer, falling at 3
      1, 0, 0.15,   // outside, rising
      2, 0, 0.5,    // falling at 3, 5 d̂ above the floor
      3, 0, 0.005,  // inside, d = d̂/20: doubled; moving towards the sphere, 6 away
      4, 0, 0.008;  // inside, d = d̂/12.5: 1.25-fold
  v(0, 2) = -3.0;
  v(1, 2) = 3.0;
  v(2, 2) = -3.0;
  v(3, 0) = 3.0;
  barrier.adapt(x, v, mass);
  const double absorbing = barrier.stiffness(0);
  // The barrier at d̂/2 holds ½ m w² = 9.
  EXPECT_NEAR(absorbing * optimize::barrierPotential(0.5 * layer, layer), 9.0, 1e-12);
  EXPECT_EQ(barrier.stiffness(1), 1.0);
  EXPECT_EQ(barrier.stiffness(2), absorbing);
  EXPECT_DOUBLE_EQ(barrier.stiffness(3), 2.0);
  EXPECT_DOUBLE_EQ(barrier.stiffness(4), 1.25);
  // Inside the layer κ never falls; outside it returns to κ̄ once the vertex stops approaching.
  x(0, 2) = 0.03;
  v(0, 2) = 0.0;
  barrier.adapt(x, v, mass);
  EXPECT_EQ(barrier.stiffness(0), absorbing);
  x(0, 2) = 0.2;
  barrier.adapt(x, v, mass);
  EXPECT_EQ(barrier.stiffness(0), 1.0);
  EXPECT_DOUBLE_EQ(barrier.stiffness(3), 8.0);  // doubled at each of the three calls
  barrier.resetStiffness();
  EXPECT_EQ(barrier.stiffness(3), 1.0);
}

// A budget bounds what the raises inside the layer add: two vertices pressed to d̂/20 (κ 1 → 2
// each without a budget) share a budget of 1.5 b(d̂/20) in vertex order — the first doubled, the
// second raised by half — and adapt returns the energy added; outside the layer it does not count.
TEST(Obstacles, AdaptiveStiffnessInsideTheLayerSpendsAtMostTheBudget) {
  const double layer = 0.1;
  ObstacleBarrier barrier({optimize::parseObstacle("--obstacle", "plane:0,0,1,0")}, layer,
                          Eigen::VectorXd::Ones(3));
  Positions x(3, 3), v = Positions::Zero(3, 3);
  x << 0, 0, 0.005, 1, 0, 0.005, 2, 0, 0.5;
  v(2, 2) = -3.0;  // outside, approaching: raised freely (its barrier is 0)
  const double unit = optimize::barrierPotential(0.005, layer);
  const double before = barrier.energy(x);
  const double added = barrier.adapt(x, v, Eigen::VectorXd::Constant(3, 2.0), 1.5 * unit);
  EXPECT_DOUBLE_EQ(barrier.stiffness(0), 2.0);
  EXPECT_DOUBLE_EQ(barrier.stiffness(1), 1.5);
  EXPECT_GT(barrier.stiffness(2), 1.0);
  EXPECT_NEAR(added, 1.5 * unit, 1e-15);
  EXPECT_NEAR(barrier.energy(x) - before, added, 1e-15);
  EXPECT_EQ(barrier.adapt(x, v, Eigen::VectorXd::Constant(3, 2.0), 0.0), 0.0);
  EXPECT_DOUBLE_EQ(barrier.stiffness(0), 2.0);  // no budget: no raise
}

// Raising κ_v inside the layer adds B(x; κ_new) − B(x; κ_old) to the motion (the barrier, pressed,
// gives it back on rebound). A patch48 sheet (n = 12, hinge) dropped undamped 0.05 onto a sphere
// (the drape scene): before the budget the raises added 11 % of the peak kinetic energy in 0.3 s,
// the total (contact at the current κ) rising by as much, and more at smaller steps (the growth is
// per step). Now, undamped, the raises stay within half the energy tolerance of the peak kinetic
// energy (their budget: that plus the work done against damping).
TEST(Obstacles, StiffeningInsideTheLayerStaysWithinTheEnergyBudget) {
  const testing::Plate plate(
      modeling::MeshFamily::Patch48, 12, Discretization::Hinge, 1e3,
      [](optimize::ProblemOptions& p, const modeling::Stencils&) {
        p.load.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
        p.obstacles = {optimize::parseObstacle("obstacle", "sphere:0,0,-0.35,0.3")};
      });
  optimize::DynamicsOptions o;
  optimize::TimeStepper stepper(plate.problem, o);
  stepper.start(plate.rest.positions, Positions::Zero(plate.mesh.vertexCount(), 3),
                Eigen::VectorXd());
  double highest = stepper.energies().total();
  for (int k = 0; k < 60; ++k) {
    const auto outcome = stepper.step(0.005);
    ASSERT_TRUE(outcome.converged) << "step " << k << ": " << outcome.failure;
    ASSERT_GT(stepper.barrier().smallestDistance(stepper.positions()), 0.0) << "step " << k;
    highest = std::max(highest, stepper.energies().total());
  }
  const optimize::EnergyBalance& b = stepper.balance();
  std::printf("sheet on a sphere: stiffening %.3e, total rose %.3e, peak kinetic %.3e\n",
              b.stiffening, highest - b.initial, b.peakKinetic);
  EXPECT_GT(b.stiffening, 0.0);  // the raises happen, within the budget
  EXPECT_LE(b.stiffening, 0.5 * o.energyTolerance * b.peakKinetic * (1.0 + 1e-12));
  EXPECT_LT(highest - b.initial, o.energyTolerance * b.peakKinetic);
}

TEST(Obstacles, MalformedSpecsAreRefused) {
  for (const char* spec : {"plane:0,0,1", "plane:0,0,0,1", "sphere:0,0,0,-1", "sphere:0,0,0,0",
                           "cube:0,0,0,1", "plane:0,0,1,nan", "plane:0,0,1,1,", "plane"})
    EXPECT_THROW(optimize::parseObstacle("--obstacle", spec), InputError) << spec;
}

// A flat sheet (hinge + StVK, nothing pinned) falls 0.1 onto the plane z = −0.1 under gravity,
// with backward Euler and mass damping: no vertex is ever inside (checked after every step),
// it comes to rest (kinetic energy below 1e-12 of its peak), lying within the layer d̂ of the
// plane.
TEST(Obstacles, SheetDroppedOnAPlaneComesToRestOnIt) {
  const testing::Plate plate(
      modeling::MeshFamily::Patch48, 6, Discretization::Hinge, 1e3,
      [](optimize::ProblemOptions& p, const modeling::Stencils&) {
        p.load.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
        p.obstacles = {optimize::parseObstacle("obstacle", "plane:0,0,1,-0.1")};
      });
  optimize::DynamicsOptions o;
  o.integrator = optimize::Integrator::BackwardEuler;
  o.rayleighMass = 10.0;
  optimize::TimeStepper stepper(plate.problem, o);
  stepper.start(plate.rest.positions, Positions::Zero(plate.mesh.vertexCount(), 3),
                Eigen::VectorXd());
  const double layer = stepper.barrier().layer();
  double peak = 0.0, kinetic = 0.0, closest = 1.0;
  int iterations = 0;
  const int steps = 400;
  for (int k = 0; k < steps; ++k) {
    const auto outcome = stepper.step(0.005);
    ASSERT_TRUE(outcome.converged) << "step " << k << ": " << outcome.failure;
    iterations += outcome.newtonIterations;
    const double d = stepper.barrier().smallestDistance(stepper.positions());
    ASSERT_GT(d, 0.0) << "step " << k;
    closest = std::min(closest, d);
    kinetic = stepper.energies().kinetic;
    peak = std::max(peak, kinetic);
  }
  const double highest = stepper.positions().col(2).maxCoeff() + 0.1;
  const double lowest = stepper.positions().col(2).minCoeff() + 0.1;
  std::printf(
      "dropped sheet: closest %.3e, at rest %.3e .. %.3e above the plane (layer %.3e), kinetic "
      "%.2e of the peak, %.2f Newton iterations per step\n",
      closest, lowest, highest, layer, kinetic / peak, double(iterations) / steps);
  EXPECT_LT(kinetic, 1e-12 * peak);
  EXPECT_GT(lowest, 0.0);
  EXPECT_LT(highest, layer);
  // κ_v ∝ m_v: every vertex rests at the same height, b'(d) κ_v = m_v |g|.
  EXPECT_LT(highest - lowest, 1e-6 * layer);
}

// minimize --gravity --obstacle: a clamped plate sagging under a load that would take its centre
// to −0.06 rests on a sphere whose top is at −0.03 — no vertex inside, the centre within the layer.
TEST(Obstacles, StaticMinimizerUnderGravityStaysOutsideASphere) {
  // Two rings held at rest, gravity g on the lumped masses; then a sphere, then a plane the start
  // is inside of.
  const auto plate = [](const char* obstacle) {
    return std::make_unique<testing::Plate>(
        modeling::MeshFamily::Patch48, 8, Discretization::Cotan, 0.0,
        [obstacle](optimize::ProblemOptions& p, const modeling::Stencils&) {
          p.fixedRings = 2;
          p.load.gravity = Eigen::Vector3d(0.0, 0.0, -300.0);
          if (obstacle) p.obstacles = {optimize::parseObstacle("obstacle", obstacle)};
        });
  };
  const optimize::MinimizeOptions o;
  const auto free = plate(nullptr);
  const optimize::MinimizeResult sagging = optimize::minimize(free->problem, o);
  ASSERT_TRUE(sagging.report.converged) << sagging.report.termination;
  const double freeSag = -sagging.positions.col(2).minCoeff();
  ASSERT_GT(freeSag, 0.05);

  const auto onSphere = plate("sphere:0,0,-0.53,0.5");
  const optimize::ObstacleBarrier& sphere = onSphere->problem.obstacles;
  const optimize::MinimizeResult held = optimize::minimize(onSphere->problem, o);
  ASSERT_TRUE(held.report.converged) << held.report.termination;
  int vertex = -1;
  const double closest = sphere.smallestDistance(held.positions, &vertex);
  std::printf("plate on a sphere: free sag %.4f, held sag %.4f, closest %.3e (layer %.3e)\n",
              freeSag, -held.positions.col(2).minCoeff(), closest, sphere.layer());
  EXPECT_GT(closest, 0.0);
  EXPECT_LT(closest, sphere.layer());  // in contact
  EXPECT_LT(-held.positions.col(2).minCoeff(), 0.03);
  // The Ceres and linearized solves refuse obstacles (and the load), and a start inside one is
  // refused.
  optimize::MinimizeOptions ceres;
  ceres.solver = optimize::Solver::Ceres;
  EXPECT_THROW(optimize::minimize(onSphere->problem, ceres), InputError);
  EXPECT_THROW(optimize::minimize(free->problem, ceres), InputError);
  EXPECT_THROW(optimize::minimize(plate("plane:0,0,1,0.01")->problem, o), InputError);
}

}  // namespace
}  // namespace flexure
