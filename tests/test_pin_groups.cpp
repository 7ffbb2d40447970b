// Pin groups (DynamicsOptions::pinGroups): each group of pinned vertices follows its own rigid
// motion, the pinned vertices in no group keep pinMotion (here: stay), a group is let go at its
// release time, and bad groups are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "modeling/errors.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracturing.h"
#include "support/damped_free_body.h"
#include "support/plate.h"

namespace flexure {
namespace {

using optimize::DynamicsOptions;
using optimize::PinGroup;
using optimize::PinMotion;
using optimize::TimeStepper;

// The rest vertices with x̄ ≤ −0.45 (`left`) or x̄ ≥ 0.45.
std::vector<bool> endOf(const modeling::Mesh& mesh, bool left) {
  std::vector<bool> end(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v)
    end[v] = left ? mesh.positions(v, 0) <= -0.45 : mesh.positions(v, 0) >= 0.45;
  return end;
}

struct TwoEnds : testing::Plate {
  TwoEnds()
      : testing::Plate(modeling::MeshFamily::Delaunay, 8, curvature::Discretization::Hinge, 1e3,
                       [](optimize::ProblemOptions& o, const modeling::Stencils& s) {
                         o.fixedVertex.assign(s.vertexCount(), false);
                         const modeling::Mesh m =
                             testing::generatedPlate(modeling::MeshFamily::Delaunay, 8);
                         const std::vector<bool> left = endOf(m, true), right = endOf(m, false);
                         for (int v = 0; v < s.vertexCount(); ++v)
                           o.fixedVertex[v] = left[v] || right[v];
                       }) {}
};

// Two groups, one still and one translating: the moving one is at x̄ + u t with velocity u after
// every step, the still one where it started, and the free vertices between them moved.
TEST(PinGroups, EachGroupFollowsItsOwnMotion) {
  const TwoEnds plate;
  const int vertexCount = plate.mesh.vertexCount();
  const std::vector<bool> left = endOf(plate.mesh, true), right = endOf(plate.mesh, false);
  ASSERT_GT(std::count(right.begin(), right.end(), true), 2);
  DynamicsOptions o;
  PinGroup pulled;
  pulled.vertices = right;
  pulled.motion.kind = PinMotion::Kind::Translate;
  pulled.motion.velocity = Eigen::Vector3d(0.2, 0.0, 0.05);
  o.pinGroups = {pulled};
  EXPECT_TRUE(o.pinsMove());
  TimeStepper stepper(plate.problem, o);
  stepper.start(plate.mesh.positions, modeling::Positions::Zero(vertexCount, 3), Eigen::VectorXd());
  const double h = 0.01;
  double worstMoving = 0.0, worstVelocity = 0.0, worstStill = 0.0;
  for (int k = 1; k <= 20; ++k) {
    ASSERT_TRUE(stepper.step(h).converged) << "step " << k;
    for (int v = 0; v < vertexCount; ++v) {
      const Eigen::Vector3d rest = plate.mesh.positions.row(v).transpose();
      const Eigen::Vector3d x = stepper.positions().row(v).transpose();
      if (right[v]) {
        worstMoving = std::max(worstMoving, (x - (rest + k * h * pulled.motion.velocity)).norm());
        worstVelocity =
            std::max(worstVelocity,
                     (stepper.velocities().row(v).transpose() - pulled.motion.velocity).norm());
      }
      if (left[v]) worstStill = std::max(worstStill, (x - rest).norm());
    }
  }
  EXPECT_LT(worstMoving, 1e-14);
  EXPECT_LT(worstVelocity, 1e-14);
  EXPECT_EQ(worstStill, 0.0);
  double freeMotion = 0.0;
  for (int v = 0; v < vertexCount; ++v)
    if (!left[v] && !right[v])
      freeMotion = std::max(freeMotion, stepper.positions()(v, 0) - plate.mesh.positions(v, 0));
  EXPECT_GT(freeMotion, 1e-3);
}

TEST(PinGroups, GroupsOfTheWrongSizeOrOverlappingAreRefused) {
  const TwoEnds plate;
  const int vertexCount = plate.mesh.vertexCount();
  DynamicsOptions wrongSize;
  wrongSize.pinGroups = {PinGroup{std::vector<bool>(vertexCount - 1), PinMotion{}}};
  EXPECT_THROW(TimeStepper(plate.problem, wrongSize), InputError);
  DynamicsOptions overlapping;
  const PinGroup right{endOf(plate.mesh, false), PinMotion{}};
  overlapping.pinGroups = {right, right};
  try {
    TimeStepper stepper(plate.problem, overlapping);
    ADD_FAILURE() << "overlapping groups accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("DynamicsOptions.pinGroups"), std::string::npos);
  }
  DynamicsOptions still;
  still.pinGroups = {right};
  EXPECT_FALSE(still.pinsMove());
}

// The left end held still until T = 10 h, the right end pulled at u until T' = 15 h (h = 1/64, so
// that the steps reach both exactly;
// FracturingDynamics without fracture, which owns the stepper a release replaces): the left end
// stays exactly where it was until T and moves after it; the right end follows x̄ + u t until T'
// and leaves the line after it, having gone on with the velocity u it had; with every pin let go
// the balance is checked again, from the pins' work W booked at the release. The stretched plate
// let go rings: after it, steps of h/4 keep the drift at 0.76 % (3.2 % with steps of h; with
// steps of h/4 and the released vertices keeping the pins' accelerations instead of the forces',
// 9.6 %).
TEST(PinGroups, AGroupIsLetGoAtItsReleaseTime) {
  TwoEnds plate;
  const int vertexCount = plate.mesh.vertexCount();
  const std::vector<bool> left = endOf(plate.mesh, true), right = endOf(plate.mesh, false);
  DynamicsOptions o;
  PinGroup held{left, PinMotion{}}, pulled{right, PinMotion{}};
  const double h = 1.0 / 64;
  held.releaseTime = 10 * h;
  pulled.motion.kind = PinMotion::Kind::Translate;
  pulled.motion.velocity = Eigen::Vector3d(0.2, 0.0, 0.05);
  pulled.releaseTime = 15 * h;
  o.pinGroups = {held, pulled};
  const modeling::Positions rest = plate.mesh.positions;
  optimize::FracturingDynamics dynamics(plate.mesh, std::move(plate.problem),
                                        optimize::ProblemOptions(), o, std::nullopt);
  dynamics.start(rest, modeling::Positions::Zero(vertexCount, 3));
  EXPECT_EQ(dynamics.nextRelease(), 10 * h);
  double leftBefore = 0.0, leftAfter = 0.0, rightBefore = 0.0, rightAfter = 0.0;
  for (int k = 1; k <= 25; ++k) {
    const int parts = k > 15 ? 4 : 1;
    for (int part = 0; part < parts; ++part)
      ASSERT_TRUE(dynamics.stepper().advance(h / parts, h / 64).completed) << "step " << k;
    const double t = dynamics.stepper().time();
    const optimize::TimeStepper::State before = dynamics.stepper().state();
    const bool released = dynamics.releasePins(t);
    EXPECT_EQ(released, k == 10 || k == 15) << "step " << k;
    if (released) {  // the same state goes on: positions and velocities carried
      EXPECT_TRUE(dynamics.stepper().positions() == before.x);
      EXPECT_TRUE(dynamics.stepper().velocities() == before.v);
    }
    for (int v = 0; v < vertexCount; ++v) {
      const Eigen::Vector3d x = dynamics.stepper().positions().row(v).transpose();
      const Eigen::Vector3d x0 = rest.row(v).transpose();
      if (left[v])
        (k <= 10 ? leftBefore : leftAfter) =
            std::max(k <= 10 ? leftBefore : leftAfter, (x - x0).norm());
      if (right[v])
        (k <= 15 ? rightBefore : rightAfter) = std::max(
            k <= 15 ? rightBefore : rightAfter, (x - (x0 + t * pulled.motion.velocity)).norm());
    }
  }
  EXPECT_EQ(leftBefore, 0.0);
  EXPECT_GT(leftAfter, 1e-4);
  EXPECT_LT(rightBefore, 1e-14);
  EXPECT_GT(rightAfter, 1e-4);
  EXPECT_TRUE(std::isinf(dynamics.nextRelease()));
  EXPECT_TRUE(dynamics.stepper().balanceChecked());
  EXPECT_GT(dynamics.stepper().balance().pinWork, 0.0);  // pulling stretched the plate
  EXPECT_LT(dynamics.stepper().balance().relativeDrift(), 0.01);
}

// Both ends let go at T = 10 h (h = 1/64; the left end still, the right one pulled) with Rayleigh
// damping C = α M + β K̄, under gravity g: from T on the plate is a free body, whose momentum
// follows support/damped_free_body.h's law within its bound. It holds only when Newmark's a_n at T
// is the equation of motion's after the release, damping included
// (TimeStepper::continueAfterRelease): measured before that, the released vertices' a_n from the
// forces alone (no −α v_R, no −β (K̄ v)_R) and the others' without the coupling −β K̄_FR v_R, the
// momentum left the closed form by 1.8e-4, 0.040 and 0.041 (125, 2.7e4 and 1.3e6 × the bound) for
// (α, β) = (2, 0), (2, 0.01), (0, 0.01); now by 1.5e-5, 1.5e-5 (0.95 × the bound: the trapezoidal
// rule's own error, e^{−αh} × its bound after one step) and 1.6e-11.
TEST(PinGroups, APlateLetGoWithDampingFallsAsADampedFreeBody) {
  const double h = 1.0 / 64, release = 10 * h;
  const Eigen::Vector3d g(0.0, 0.0, -1.0);
  for (const auto& [alpha, beta] : {std::pair{2.0, 0.0}, {2.0, 0.01}, {0.0, 0.01}}) {
    TwoEnds plate;
    plate.problem.gravity = g;
    const int vertexCount = plate.mesh.vertexCount();
    DynamicsOptions o;
    o.rayleighMass = alpha;
    o.rayleighStiffness = beta;
    PinGroup held{endOf(plate.mesh, true), PinMotion{}}, pulled{endOf(plate.mesh, false), {}};
    held.releaseTime = pulled.releaseTime = release;
    pulled.motion.kind = PinMotion::Kind::Translate;
    pulled.motion.velocity = Eigen::Vector3d(0.2, 0.0, 0.05);
    o.pinGroups = {held, pulled};
    const modeling::Positions rest = plate.mesh.positions;
    optimize::FracturingDynamics dynamics(plate.mesh, std::move(plate.problem),
                                          optimize::ProblemOptions(), o, std::nullopt);
    dynamics.start(rest, modeling::Positions::Zero(vertexCount, 3));
    const auto momentum = [&] {
      const TimeStepper& s = dynamics.stepper();
      return Eigen::Vector3d(s.velocities().transpose() * s.masses());
    };
    for (int k = 1; k <= 10; ++k) ASSERT_TRUE(dynamics.stepper().advance(h, h / 64).completed);
    ASSERT_TRUE(dynamics.releasePins(release));
    const double mass = dynamics.stepper().masses().sum();
    const Eigen::Vector3d p0 = momentum();
    const double diagonal = (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm();
    const testing::DampedFreeBody body(p0, mass, g, alpha, h, o, diagonal);
    double worst = 0.0, largest = 0.0;  // the largest error over its bound, and alone
    for (int k = 1; k <= 20; ++k) {
      ASSERT_TRUE(dynamics.stepper().advance(h, h / 64).completed) << "step " << k;
      const double s = dynamics.stepper().time() - release;
      const double error = (momentum() - body.momentum(s)).norm();
      largest = std::max(largest, error);
      worst = std::max(worst, error / body.tolerance(s, k));
    }
    std::printf(
        "alpha %g beta %g: |p(T)| %.4g, M %.4g; momentum error <= %.3g (%.3g x tolerance)\n", alpha,
        beta, p0.norm(), mass, largest, worst);
    EXPECT_LE(worst, 1.0) << "alpha " << alpha << " beta " << beta;
    EXPECT_GT(p0.norm(), 1e-3 * mass);  // the pulled end carried momentum into the release
  }
}

TEST(PinGroups, ReleaseTimesThatAreNotPositiveAreRefused) {
  const TwoEnds plate;
  for (const double bad : {0.0, -1.0, -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
    DynamicsOptions o;
    PinGroup right{endOf(plate.mesh, false), PinMotion{}};
    right.releaseTime = bad;
    o.pinGroups = {right};
    try {
      TimeStepper stepper(plate.problem, o);
      ADD_FAILURE() << "release time " << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("PinGroup.releaseTime"), std::string::npos) << e.what();
    }
  }
  DynamicsOptions never;  // the default, +∞: held for the whole run
  never.pinGroups = {PinGroup{endOf(plate.mesh, false), PinMotion{}}};
  EXPECT_NO_THROW(TimeStepper(plate.problem, never));
}

}  // namespace
}  // namespace flexure
