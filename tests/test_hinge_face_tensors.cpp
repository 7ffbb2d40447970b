// The hinge's per-face curvature tensor (curvature/hinge_face_tensors.h): the rows c_e give the
// hinge angle of the vertex interpolant of a uniform curvature tensor K (cylinders at several
// axes, a sphere, a saddle) on the criss, Delaunay and 4-8 plates, with the hinge energy's own
// angle and sign; the hinge term reads K back on every face with three interior edges, a face with
// fewer reads the minimum-norm tensor of its edges (no larger than K), and moving the rest tensor
// by K puts every hinge of the interpolated surface at rest. The hinge term's tensors are built
// on first use, once, from a copy of the rest geometry (HingeRestTensors).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "curvature/bending_angle.h"
#include "curvature/face_frame.h"
#include "curvature/hinge_face_tensors.h"
#include "modeling/generators.h"
#include "support/energy_fixtures.h"

namespace flexure {
namespace {

using curvature::Discretization;
using modeling::MeshFamily;

constexpr MeshFamily kFamilies[] = {MeshFamily::Criss, MeshFamily::Delaunay, MeshFamily::Patch48};

std::string familyName(MeshFamily f) {
  return f == MeshFamily::Criss ? "criss" : f == MeshFamily::Delaunay ? "delaunay" : "patch48";
}

modeling::Mesh plate(MeshFamily family) {
  modeling::GeneratorOptions g;
  g.family = family;
  g.n = 8;
  return modeling::generateMesh(g);
}

// Uniform tensors K = [[a, b], [b, c]] in the plate's x, y: cylinders of curvature κ about axes
// at 0°, 30° and 75° from y, a sphere and a saddle.
std::vector<Eigen::Matrix2d> uniformCurvatures(double kappa) {
  std::vector<Eigen::Matrix2d> out;
  for (double alpha : {0.0, 0.5236, 1.309}) {
    const Eigen::Vector2d d(std::cos(alpha), std::sin(alpha));
    out.push_back(kappa * d * d.transpose());
  }
  out.push_back(kappa * Eigen::Matrix2d::Identity());
  out.push_back(kappa * Eigen::Vector2d(1.0, -1.0).asDiagonal());
  return out;
}

// The flat plate lifted onto z = ½ uᵀ K u, u = (x, y).
modeling::Positions interpolated(const modeling::Positions& rest, const Eigen::Matrix2d& k) {
  modeling::Positions x = rest;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    const Eigen::Vector2d u = rest.row(v).head<2>().transpose();
    x(v, 2) = 0.5 * u.dot(k * u);
  }
  return x;
}

// #F by 3: K in every face's rest frame (face_frame.h), (a, b, c).
Eigen::MatrixXd inFaceFrames(const modeling::Stencils& s, const modeling::RestState& rest,
                             const Eigen::Matrix2d& k) {
  Eigen::MatrixXd out(s.faceCount(), 3);
  for (int f = 0; f < s.faceCount(); ++f) {
    const auto frame = curvature::FaceFrame::of(rest.positions.row(s.faces(f, 0)).transpose(),
                                                rest.positions.row(s.faces(f, 1)).transpose(),
                                                rest.positions.row(s.faces(f, 2)).transpose());
    Eigen::Matrix2d basis;
    basis.col(0) = frame.u.head<2>();
    basis.col(1) = frame.v.head<2>();
    const Eigen::Matrix2d local = basis.transpose() * k * basis;
    out.row(f) << local(0, 0), local(0, 1), local(1, 1);
  }
  return out;
}

// The hinge's angle measure φ(θ_e) at x, per hinge, as the hinge energy reads it.
Eigen::VectorXd hingeMeasures(const modeling::Stencils& s, const modeling::Positions& x,
                              curvature::HingeAngle measure) {
  Eigen::VectorXd out(s.hingeCount());
  for (int h = 0; h < s.hingeCount(); ++h) {
    curvature::Vec3<double> p[4];
    for (int k = 0; k < 4; ++k)
      p[k] = {x(s.hinges(h, k), 0), x(s.hinges(h, k), 1), x(s.hinges(h, k), 2)};
    out[h] = curvature::hingeAngleMeasure(curvature::bendingAngle(p[0], p[1], p[2], p[3]), measure);
  }
  return out;
}

double frobenius(const Eigen::RowVectorXd& t) {
  return std::sqrt(t(0) * t(0) + 2 * t(1) * t(1) + t(2) * t(2));
}

TEST(HingeFaceTensors, RowsGiveTheHingeAnglesOfAUniformCurvature) {
  // κ = 1e-3 on the unit plate: the slopes are below 1e-3, so θ_e equals the interpolant's slope
  // jump to a relative 1e-6; the formula's own error is O(κ² h), far below the tolerance. A wrong
  // sign, or the old threshold's 2 h̄_e in place of the altitudes' mean, is off by O(κ h).
  const double kappa = 1e-3;
  for (MeshFamily family : kFamilies) {
    const modeling::Mesh mesh = plate(family);
    const modeling::Stencils s = modeling::compileStencils(mesh);
    const modeling::RestState rest = modeling::precomputeRestState(s, mesh.positions);
    const curvature::HingeFaceTensors faces(s, rest);
    for (const Eigen::Matrix2d& k : uniformCurvatures(kappa)) {
      const modeling::Positions x = interpolated(mesh.positions, k);
      const Eigen::MatrixXd local = inFaceFrames(s, rest, k);
      Eigen::MatrixXd tensors(faces.faceCount(), 3);
      for (int e = 0; e < faces.faceCount(); ++e) tensors.row(e) = local.row(faces.face(e));
      const Eigen::VectorXd predicted = faces.angles(tensors);
      for (auto measure : {curvature::HingeAngle::Theta, curvature::HingeAngle::Tan}) {
        const Eigen::VectorXd angles = hingeMeasures(s, x, measure);
        ASSERT_GT(angles.cwiseAbs().maxCoeff(), 0.05 * kappa / 8) << familyName(family);
        EXPECT_LT((angles - predicted).cwiseAbs().maxCoeff(), 1e-5 * angles.cwiseAbs().maxCoeff())
            << familyName(family) << " K = " << k(0, 0) << ", " << k(0, 1) << ", " << k(1, 1);
      }
    }
  }
}

TEST(HingeFaceTensors, TheHingeTermReadsAUniformCurvaturePerFace) {
  const double kappa = 1e-3;
  for (MeshFamily family : kFamilies) {
    testing::BendingSetup setup(plate(family), testing::bendingOptions(Discretization::Hinge));
    curvature::RestCurvatureState& state = *setup.term->restCurvatureState();
    const curvature::HingeFaceTensors faces(setup.stencils, setup.rest);
    // Interior edges per face, to tell the faces with three from the boundary's.
    std::vector<int> interior(static_cast<size_t>(setup.stencils.faceCount()), 0);
    for (int h = 0; h < setup.stencils.hingeCount(); ++h)
      for (int side = 0; side < 2; ++side)
        ++interior[static_cast<size_t>(
            setup.stencils.edgeFaces(setup.stencils.hingeEdges[h], side))];
    EXPECT_EQ(state.restCurvatures().cwiseAbs().maxCoeff(), 0.0);  // flat rest
    for (const Eigen::Matrix2d& k : uniformCurvatures(kappa)) {
      const modeling::Positions x = interpolated(setup.rest.positions, k);
      const Eigen::MatrixXd local = inFaceFrames(setup.stencils, setup.rest, k);
      const Eigen::MatrixXd read = state.elementCurvatures(x, {});
      ASSERT_EQ(read.rows(), faces.faceCount());
      int full = 0, partial = 0;
      for (Eigen::Index e = 0; e < read.rows(); ++e) {
        const int f = state.elementId(static_cast<int>(e));
        if (interior[static_cast<size_t>(f)] == 3) {
          ++full;
          EXPECT_LT(frobenius(read.row(e) - local.row(f)), 1e-5 * kappa) << familyName(family);
        } else {
          // The minimum-norm tensor: the part of K its one or two edges see, never more.
          ++partial;
          EXPECT_LE(frobenius(read.row(e)), frobenius(local.row(f)) * (1 + 1e-5));
        }
      }
      EXPECT_GT(full, 0);
      EXPECT_GT(partial, 0);
      // Rest tensors moved by K put the interpolated surface at rest: its energy drops from the
      // flat rest's to nothing (every hinge's rest angle is θ_e(K); partial faces included, since
      // each reproduces its edges' angles).
      const double flat = setup.term->energy(x, {});
      state.setRestCurvatures(read);
      EXPECT_LT(setup.term->energy(x, {}), 1e-10 * flat) << familyName(family);
      state.setRestCurvatures(Eigen::MatrixXd::Zero(read.rows(), 3));
      EXPECT_NEAR(setup.term->energy(x, {}), flat, 1e-12 * flat);
    }
  }
}

TEST(HingeFaceTensors, RestTensorsAreBuiltOnFirstUseFromACopy) {
  // A curved rest (a saddle, so that the rest angles and S̄⁰ are not zero), its stencils and rest
  // state gone before the first use: the build reads only the holder's copy.
  const Eigen::Matrix2d k = Eigen::Vector2d(0.3, -0.2).asDiagonal();
  modeling::Mesh mesh = plate(MeshFamily::Delaunay);
  mesh.positions = interpolated(mesh.positions, k);
  std::unique_ptr<curvature::HingeRestTensors> lazy;
  Eigen::VectorXd restAngles;
  Eigen::MatrixXd eagerRest, eagerRead;
  std::vector<int> eagerFaces;
  {
    const modeling::Stencils s = modeling::compileStencils(mesh);
    const modeling::RestState rest = modeling::precomputeRestState(s, mesh.positions);
    restAngles = hingeMeasures(s, mesh.positions, curvature::HingeAngle::Theta);
    const curvature::HingeFaceTensors eager(s, rest);
    eagerRest = eager.tensors(restAngles);
    eagerRead = eager.tensors(2.0 * restAngles);
    for (int e = 0; e < eager.faceCount(); ++e) eagerFaces.push_back(eager.face(e));
    lazy = std::make_unique<curvature::HingeRestTensors>(curvature::HingeRestGeometry::of(s, rest),
                                                         restAngles);
  }
  ASSERT_GT(eagerRest.cwiseAbs().maxCoeff(), 0.01);
  EXPECT_FALSE(lazy->isBuilt());
  EXPECT_EQ(lazy->restAngles(), restAngles);  // no build needed
  EXPECT_FALSE(lazy->isBuilt());
  // Two threads ask at once: one build, the same object for both.
  const curvature::HingeFaceTensors* seen[2] = {nullptr, nullptr};
  std::thread other([&] { seen[1] = &lazy->faces(); });
  seen[0] = &lazy->faces();
  other.join();
  EXPECT_TRUE(lazy->isBuilt());
  EXPECT_EQ(seen[0], seen[1]);
  // The eager build's tensors, bit for bit.
  EXPECT_EQ(lazy->restTensors(), eagerRest);
  EXPECT_EQ(lazy->faces().tensors(2.0 * restAngles), eagerRead);
  ASSERT_EQ(lazy->faces().faceCount(), static_cast<int>(eagerFaces.size()));
  for (int e = 0; e < lazy->faces().faceCount(); ++e)
    EXPECT_EQ(lazy->faces().face(e), eagerFaces[e]);
}

}  // namespace
}  // namespace flexure
