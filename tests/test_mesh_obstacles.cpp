// Mesh obstacles (optimize/assembly/mesh_obstacles.h, through self_contact.h's barrier): a sheet
// dropped on a static box of 12 triangles comes to rest on it, no frame crossing it; a small
// sphere mesh driven into a pinned sheet pushes it without crossing; the tip of a coarse
// projectile aimed between the shell's vertices is stopped by the face it meets (an obstacle
// vertex against a shell face); and bad starts and motions are refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/self_intersections.h"
#include "optimize/assembly/mesh_obstacles.h"
#include "optimize/dynamics/time_stepping.h"
#include "support/plate.h"

namespace flexure {
namespace {

using curvature::Discretization;
using modeling::Mesh;
using modeling::Positions;
using optimize::MeshObstacle;
using optimize::PinMotion;
using optimize::TimeStepper;

// The box [lo, hi] as 12 outward triangles.
Mesh boxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Mesh box;
  box.positions.resize(8, 3);
  for (int v = 0; v < 8; ++v)
    box.positions.row(v) << (v & 1 ? hi : lo).x(), (v & 2 ? hi : lo).y(), (v & 4 ? hi : lo).z();
  box.triangles.resize(12, 3);
  box.triangles << 0, 2, 1, 1, 2, 3,  // z = lo
      4, 5, 6, 5, 7, 6,               // z = hi
      0, 1, 4, 1, 5, 4,               // y = lo
      2, 6, 3, 3, 6, 7,               // y = hi
      0, 4, 2, 2, 4, 6,               // x = lo
      1, 3, 5, 3, 7, 5;               // x = hi
  return box;
}

// A tetrahedron with its tip at `tip`, its base a triangle of circumradius r at height r above.
Mesh projectile(const Eigen::Vector3d& tip, double r) {
  Mesh tet;
  tet.positions.resize(4, 3);
  tet.positions.row(0) = tip.transpose();
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0 * 3.14159265358979 * k / 3.0;
    tet.positions.row(k + 1) =
        (tip + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), r)).transpose();
  }
  tet.triangles.resize(4, 3);
  tet.triangles << 0, 2, 1, 0, 3, 2, 0, 1, 3, 1, 2, 3;
  return tet;
}

// The patch48 sheet [-½, ½]² at z = 0 with n cells a side.
Mesh sheet(int n) {
  return testing::generatedPlate(modeling::MeshFamily::Patch48, n);
}

std::vector<bool> boundaryOf(const Mesh& mesh) {
  std::vector<bool> pinned;
  for (int v = 0; v < mesh.vertexCount(); ++v)
    pinned.push_back(mesh.positions.row(v).head<2>().cwiseAbs().maxCoeff() > 0.49);
  return pinned;
}

// Whether the shell at x crosses obstacle k where it is at time t (exact).
bool crosses(const Mesh& shell, const Positions& x, const MeshObstacle& obstacle, double t) {
  return !modeling::intersectingFacePairs(Mesh{x, shell.triangles},
                                          Mesh{obstacle.positionsAt(t), obstacle.mesh.triangles})
              .empty();
}

optimize::ProblemOptions sheetOptions(double young) {
  optimize::ProblemOptions o = testing::plateProblem(Discretization::Hinge, young);
  o.selfContact = false;  // the obstacles alone
  return o;
}

TEST(MeshObstacles, SheetDroppedOnAStaticBoxComesToRestOnIt) {
  const Mesh shell = sheet(6);
  Positions start = shell.positions;
  start.col(2).array() += 0.1;
  optimize::ProblemOptions o = sheetOptions(1e3);
  o.load.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  o.meshObstacles = {{boxMesh({-0.7, -0.7, -0.3}, {0.7, 0.7, 0.0}), PinMotion(), "box"}};
  ASSERT_EQ(o.meshObstacles[0].mesh.faceCount(), 12);
  const optimize::Problem problem = optimize::buildProblem(shell, o);
  optimize::DynamicsOptions d;
  d.integrator = optimize::Integrator::BackwardEuler;
  d.rayleighMass = 10.0;
  TimeStepper stepper(problem, d);
  stepper.start(start, Positions::Zero(shell.vertexCount(), 3), Eigen::VectorXd());
  EXPECT_TRUE(stepper.balanceChecked());  // a static obstacle does no work
  double peak = 0.0;
  for (int frame = 1; frame <= 40; ++frame) {
    const TimeStepper::Advance advance = stepper.advance(0.02, 0.02 / 64);
    ASSERT_TRUE(advance.completed) << "frame " << frame << ": " << advance.failure.failure;
    peak = std::max(peak, stepper.energies().kinetic);
    ASSERT_FALSE(crosses(shell, stepper.positions(), o.meshObstacles[0], stepper.time()))
        << "frame " << frame;
  }
  const double layer = stepper.selfContact().layer();
  const double lowest = stepper.positions().col(2).minCoeff();
  const double highest = stepper.positions().col(2).maxCoeff();
  std::printf("sheet on a box: heights [%.3e, %.3e] (offset %.3e), kinetic %.2e of the peak\n",
              lowest, highest, layer, stepper.energies().kinetic / peak);
  EXPECT_LT(stepper.energies().kinetic, 1e-3 * peak);  // at rest
  EXPECT_GT(lowest, 0.05 * layer);                     // on the box's top, not through it
  EXPECT_LT(highest, layer);
}

TEST(MeshObstacles, MovingSphereMeshPushesAPinnedSheetWithoutCrossing) {
  const Mesh shell = sheet(8);
  optimize::ProblemOptions o = sheetOptions(1e2);
  o.fixedVertex = boundaryOf(shell);
  Mesh ball = modeling::sphereMesh(8, false);  // diameter 1
  ball.positions = (0.12 * ball.positions).rowwise() + Eigen::RowVector3d(0.03, 0.02, 0.2);
  o.meshObstacles = {{ball, PinMotion::translation({0.0, 0.0, -1.0}), "ball"}};
  const optimize::Problem problem = optimize::buildProblem(shell, o);
  optimize::DynamicsOptions d;
  d.rayleighMass = 5.0;
  TimeStepper stepper(problem, d);
  stepper.start(shell.positions, Positions::Zero(shell.vertexCount(), 3), Eigen::VectorXd());
  EXPECT_FALSE(stepper.balanceChecked());  // the moving obstacle does work: driven
  for (int frame = 1; frame <= 12; ++frame) {
    const TimeStepper::Advance advance = stepper.advance(0.02, 0.02 / 256);
    ASSERT_TRUE(advance.completed) << "frame " << frame << ": " << advance.failure.failure;
    ASSERT_FALSE(crosses(shell, stepper.positions(), o.meshObstacles[0], stepper.time()))
        << "frame " << frame;
  }
  const double lowest = stepper.positions().col(2).minCoeff();
  const double ballBottom = o.meshObstacles[0].positionsAt(stepper.time()).col(2).minCoeff();
  std::printf("pushed sheet: lowest vertex %.3f, the ball's bottom %.3f, %d pairs at most\n",
              lowest, ballBottom, stepper.contactStatistics().peakPairs);
  EXPECT_LT(ballBottom, -0.09);  // the ball (radius 0.06) went 0.1 below the sheet's plane …
  EXPECT_LT(lowest, -0.09);      // … and the sheet went with it
  EXPECT_GT(stepper.contactStatistics().peakPairs, 0);
  EXPECT_EQ(stepper.balanceVerdict(), optimize::BalanceVerdict::Driven);
}

// The tip of a tetrahedron smaller than the sheet's faces, aimed at a face's centroid: no shell
// vertex or edge is near it, only the face (the pair obstacle vertex–shell face) can stop it.
TEST(MeshObstacles, AProjectileTipBetweenShellVerticesIsStoppedByTheFace) {
  const Mesh shell = sheet(4);
  int target = 0;
  double nearest = std::numeric_limits<double>::infinity();
  Eigen::Vector3d centroid;
  for (int f = 0; f < shell.faceCount(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += shell.positions.row(shell.triangles(f, k)).transpose() / 3.0;
    if (c.head<2>().norm() < nearest) nearest = c.head<2>().norm(), target = f, centroid = c;
  }
  optimize::ProblemOptions o = sheetOptions(1e2);
  o.fixedVertex = boundaryOf(shell);
  o.contactOffset = 0.01;
  const double tipHeight = 0.05;
  o.meshObstacles = {{projectile(centroid + Eigen::Vector3d(0, 0, tipHeight), 0.02),
                      PinMotion::translation({0.0, 0.0, -1.0}), "projectile"}};
  const optimize::Problem problem = optimize::buildProblem(shell, o);
  optimize::DynamicsOptions d;
  d.rayleighMass = 5.0;
  TimeStepper stepper(problem, d);
  stepper.start(shell.positions, Positions::Zero(shell.vertexCount(), 3), Eigen::VectorXd());
  const auto faceHeightBelowTip = [&](const Eigen::Vector3d& tip) {  // the face's plane at the tip
    const Positions& x = stepper.positions();
    const Eigen::Vector3d a = x.row(shell.triangles(target, 0)).transpose();
    const Eigen::Vector3d n = (x.row(shell.triangles(target, 1)).transpose() - a)
                                  .cross(x.row(shell.triangles(target, 2)).transpose() - a);
    return a.z() - (n.x() * (tip.x() - a.x()) + n.y() * (tip.y() - a.y())) / n.z();
  };
  for (int frame = 1; frame <= 10; ++frame) {
    const TimeStepper::Advance advance = stepper.advance(0.01, 0.01 / 256);
    ASSERT_TRUE(advance.completed) << "frame " << frame << ": " << advance.failure.failure;
    ASSERT_FALSE(crosses(shell, stepper.positions(), o.meshObstacles[0], stepper.time()))
        << "frame " << frame;
    const Eigen::Vector3d tip = o.meshObstacles[0].positionsAt(stepper.time()).row(0).transpose();
    ASSERT_GT(tip.z(), faceHeightBelowTip(tip)) << "frame " << frame << ": the tip passed";
  }
  const Eigen::Vector3d tip = o.meshObstacles[0].positionsAt(stepper.time()).row(0).transpose();
  std::printf("projectile: tip at z = %.3f (0.05 below the sheet's plane), face below at %.3f\n",
              tip.z(), faceHeightBelowTip(tip));
  EXPECT_LT(tip.z(), -0.04);  // it went on 0.1 down, carrying the face with it
  EXPECT_LT(stepper.positions().col(2).minCoeff(), tip.z());
}

TEST(MeshObstacles, BadObstaclesAreRefused) {
  const Mesh shell = sheet(4);
  optimize::ProblemOptions o = sheetOptions(1e2);
  o.meshObstacles = {{Mesh{Positions(0, 3), modeling::Triangles(0, 3)}, PinMotion(), "empty"}};
  try {
    optimize::buildProblem(shell, o);
    ADD_FAILURE() << "an empty obstacle was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ProblemOptions.meshObstacles[0] (empty)"),
              std::string::npos)
        << e.what();
  }
  // A box through the sheet's middle at the start: refused, naming it and a pair of faces.
  o.meshObstacles = {{boxMesh({-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1}), PinMotion(), "box"}};
  const optimize::Problem through = optimize::buildProblem(shell, o);
  TimeStepper stepper(through, optimize::DynamicsOptions());
  try {
    stepper.start(shell.positions, Positions::Zero(shell.vertexCount(), 3), Eigen::VectorXd());
    ADD_FAILURE() << "an obstacle through the shell was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("box intersects the shell"), std::string::npos)
        << e.what();
  }
}

// A box driven down onto the pinned boundary: the pins cannot give way, so the obstacle's motion
// over a step reaches them at every step length, and the advance fails naming the time and a pair.
TEST(MeshObstacles, AnObstacleDrivenIntoPinnedVerticesFails) {
  const Mesh shell = sheet(4);
  optimize::ProblemOptions o = sheetOptions(1e2);
  o.fixedVertex = boundaryOf(shell);
  o.meshObstacles = {{boxMesh({0.4, -0.1, 0.05}, {0.6, 0.1, 0.2}),
                      PinMotion::translation({0.0, 0.0, -1.0}), "box"}};
  const optimize::Problem problem = optimize::buildProblem(shell, o);
  TimeStepper stepper(problem, optimize::DynamicsOptions());
  stepper.start(shell.positions, Positions::Zero(shell.vertexCount(), 3), Eigen::VectorXd());
  const TimeStepper::Advance advance = stepper.advance(0.1, 0.1 / 64);
  ASSERT_FALSE(advance.completed);
  const std::string& failure = advance.failure.failure;
  std::printf("driven into the pins: at t = %.4f: %s\n", advance.failedTime, failure.c_str());
  EXPECT_NE(failure.find("over the step from t = "), std::string::npos) << failure;
  EXPECT_NE(failure.find("of box"), std::string::npos) << failure;
  EXPECT_GT(advance.failedTime, 0.03);  // the box starts 0.05 above the sheet
  EXPECT_LT(advance.failedTime, 0.06);
}

}  // namespace
}  // namespace flexure
