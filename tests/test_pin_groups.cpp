// Pin groups (DynamicsOptions::pinGroups): each group of pinned vertices follows its own rigid
// motion, the pinned vertices in no group keep pinMotion (here: stay), and bad groups are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "modeling/errors.h"
#include "optimize/dynamics/time_stepping.h"
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

}  // namespace
}  // namespace flexure
