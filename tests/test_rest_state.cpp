#include "modeling/rest_state.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mixed_area.h"
#include "modeling/polynomial_surface.h"
#include "modeling/vertex_quantities.h"
#include "support/small_meshes.h"

namespace flexure::modeling {
namespace {

using flexure::testing::tetrahedron;

Mesh triangle(Eigen::Vector3d a, Eigen::Vector3d b, Eigen::Vector3d c) {
  Mesh m;
  m.positions.resize(3, 3);
  m.positions << a.transpose(), b.transpose(), c.transpose();
  m.triangles.resize(1, 3);
  m.triangles << 0, 1, 2;
  return m;
}

RestState restOf(const Mesh& m) {
  return precomputeRestState(compileStencils(m), m.positions);
}

TEST(RestState, RightTriangleByHand) {
  const RestState r = restOf(triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_DOUBLE_EQ(r.faceAreas[0], 0.5);
  EXPECT_TRUE(r.faceNormals.row(0).isApprox(Eigen::RowVector3d(0, 0, 1)));
  EXPECT_DOUBLE_EQ(r.faceEdgeLengths(0, 0), std::sqrt(2.0));  // opposite vertex 0
  EXPECT_DOUBLE_EQ(r.faceEdgeLengths(0, 1), 1.0);
  EXPECT_DOUBLE_EQ(r.faceEdgeLengths(0, 2), 1.0);
  // Outward edge normals: the hypotenuse's points to (1, 1)/√2, the legs' to −y and −x.
  const double h = std::sqrt(0.5);
  EXPECT_TRUE((r.faceEdgeNormals.block<1, 3>(0, 0)).isApprox(Eigen::RowVector3d(h, h, 0)));
  EXPECT_TRUE((r.faceEdgeNormals.block<1, 3>(0, 3)).isApprox(Eigen::RowVector3d(-1, 0, 0)));
  EXPECT_TRUE((r.faceEdgeNormals.block<1, 3>(0, 6)).isApprox(Eigen::RowVector3d(0, -1, 0)));
  // cot 90° = 0 at the right angle, cot 45° = 1 at the others.
  EXPECT_TRUE(r.faceCotangents.row(0).isApprox(Eigen::RowVector3d(0, 1, 1)) ||
              (r.faceCotangents.row(0) - Eigen::RowVector3d(0, 1, 1)).norm() < 1e-15);
  // Voronoi regions: the right-angle corner takes 1/4, the others 1/8 each.
  EXPECT_DOUBLE_EQ(r.vertexVoronoiAreas[0], 0.25);
  EXPECT_DOUBLE_EQ(r.vertexVoronoiAreas[1], 0.125);
  EXPECT_DOUBLE_EQ(r.vertexVoronoiAreas[2], 0.125);
  EXPECT_TRUE(r.vertexBarycentricAreas.isApprox(Eigen::Vector3d::Constant(0.5 / 3)));
}

TEST(RestState, ObtuseTriangleUsesMixedAreas) {
  const RestState r = restOf(triangle({0, 0, 0}, {4, 0, 0}, {2, 0.5, 0}));  // obtuse at vertex 2
  EXPECT_DOUBLE_EQ(r.faceAreas[0], 1.0);
  EXPECT_DOUBLE_EQ(r.vertexVoronoiAreas[2], 0.5);
  EXPECT_DOUBLE_EQ(r.vertexVoronoiAreas[0], 0.25);
  EXPECT_DOUBLE_EQ(r.vertexVoronoiAreas[1], 0.25);
}

TEST(RestState, EdgeNormalsAreUnitInPlaneAndOutward) {
  Mesh mesh = generateMesh({MeshFamily::Delaunay, 6, 5, {}});
  applyHeightField(PolynomialSurface::quadratic(0.7, -0.4, 0.3), mesh.positions);
  const RestState r = restOf(mesh);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d n = r.faceNormals.row(f);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d nh = r.faceEdgeNormals.block<1, 3>(f, 3 * i).transpose();
      const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, (i + 1) % 3));
      const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, (i + 2) % 3));
      const Eigen::Vector3d opposite = mesh.positions.row(mesh.triangles(f, i));
      EXPECT_NEAR(nh.norm(), 1.0, 1e-12);
      EXPECT_NEAR(nh.dot(n), 0.0, 1e-12);
      EXPECT_NEAR(nh.dot(b - a), 0.0, 1e-12);
      EXPECT_LT(nh.dot(opposite - a), 0.0);
    }
  }
}

TEST(RestState, AreasPartitionTheSurface) {
  for (MeshFamily family : {MeshFamily::Patch48, MeshFamily::Stripe, MeshFamily::Delaunay}) {
    Mesh mesh = generateMesh({family, 8, 2, {}});
    applyHeightField(PolynomialSurface::quadratic(1, 0.5, -1), mesh.positions);
    const RestState r = restOf(mesh);
    const double total = r.faceAreas.sum();
    EXPECT_GT(total, 1.0);  // the graph of a non-planar function over the unit square
    EXPECT_NEAR(r.vertexVoronoiAreas.sum(), total, 1e-12 * total);
    EXPECT_NEAR(r.vertexBarycentricAreas.sum(), total, 1e-12 * total);
  }
  const RestState closed = restOf(tetrahedron());
  EXPECT_NEAR(closed.vertexVoronoiAreas.sum(), closed.faceAreas.sum(), 1e-14);
}

TEST(RestState, InvariantUnderRigidMotionAndScalesWithSize) {
  Mesh mesh = generateMesh({MeshFamily::Delaunay, 5, 9, {}});
  applyHeightField(PolynomialSurface::quadratic(0.3, 0.2, 0.9), mesh.positions);
  const RestState r = restOf(mesh);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  Positions moved =
      (mesh.positions * rotation.transpose()).rowwise() + Eigen::RowVector3d(3, -1, 2);
  const RestState m = precomputeRestState(compileStencils(mesh), moved);
  EXPECT_TRUE(m.faceAreas.isApprox(r.faceAreas, 1e-12));
  EXPECT_TRUE(m.edgeLengths.isApprox(r.edgeLengths, 1e-12));
  EXPECT_TRUE(m.vertexVoronoiAreas.isApprox(r.vertexVoronoiAreas, 1e-12));
  EXPECT_TRUE((m.faceNormals * rotation).isApprox(r.faceNormals, 1e-12));

  const RestState s = precomputeRestState(compileStencils(mesh), 2.5 * mesh.positions);
  EXPECT_TRUE(s.faceAreas.isApprox(6.25 * r.faceAreas, 1e-12));
  EXPECT_TRUE(s.faceEdgeLengths.isApprox(2.5 * r.faceEdgeLengths, 1e-12));
  EXPECT_TRUE(s.vertexVoronoiAreas.isApprox(6.25 * r.vertexVoronoiAreas, 1e-12));
}

TEST(RestState, ZeroAreaRestFaceIsReportedById) {
  const Mesh mesh = triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  Positions flat = mesh.positions;
  flat.row(2) << 2, 0, 0;
  try {
    precomputeRestState(compileStencils(mesh), flat);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("rest face 0 (vertices 0, 1, 2) has zero area"));
  }
}

// The mixed Voronoi share by hand: the right isosceles triangle is not obtuse, so each corner
// takes its Voronoi region; the three shares sum to the area. An obtuse one gives A/2 and A/4.
TEST(MixedArea, SharesByHandAndSumToTheArea) {
  // (0,0), (1,0), (0,1): cot 0 at the right angle, cot 1 at the two 45° corners.
  const double cot[3] = {0.0, 1.0, 1.0}, squared[3] = {2.0, 1.0, 1.0};
  EXPECT_DOUBLE_EQ(mixedVoronoiShare(1.0, cot, squared, 0), (1.0 * 1.0 + 1.0 * 1.0) / 8.0);
  EXPECT_DOUBLE_EQ(mixedVoronoiShare(1.0, cot, squared, 1), (1.0 * 1.0 + 2.0 * 0.0) / 8.0);
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) sum += mixedVoronoiShare(1.0, cot, squared, i);
  EXPECT_DOUBLE_EQ(sum, 0.5);
  // (0, 0), (2, 0), (−0.2, 0.5): 2A = 1, obtuse at corner 0 (its cotangent is −0.4).
  const Eigen::Vector2d x[3] = {{0.0, 0.0}, {2.0, 0.0}, {-0.2, 0.5}};
  double cotangents[3], lengths[3];
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d a = x[(i + 1) % 3] - x[i], b = x[(i + 2) % 3] - x[i];
    cotangents[i] = a.dot(b) / 1.0;  // cot = a·b / |a × b|, |a × b| = 2A = 1
    lengths[i] = (x[(i + 2) % 3] - x[(i + 1) % 3]).squaredNorm();
  }
  ASSERT_LT(cotangents[0], 0.0);
  EXPECT_DOUBLE_EQ(mixedVoronoiShare(1.0, cotangents, lengths, 0), 0.25);   // A/2
  EXPECT_DOUBLE_EQ(mixedVoronoiShare(1.0, cotangents, lengths, 1), 0.125);  // A/4
  EXPECT_DOUBLE_EQ(mixedVoronoiShare(1.0, cotangents, lengths, 2), 0.125);
}

TEST(VertexQuantities, NormalsOfAFlatPatchAndOfATetrahedron) {
  const Mesh flat = flexure::testing::twoTriangleSquare();
  const Eigen::MatrixX3d up = vertexNormals(flat.positions, flat.triangles);
  for (int v = 0; v < 4; ++v) EXPECT_TRUE(up.row(v).isApprox(Eigen::RowVector3d(0, 0, 1)));
  // The tetrahedron's corner at the origin: three unit right triangles, normals −x, −y, −z.
  const Mesh t = tetrahedron();
  const Eigen::MatrixX3d n = vertexNormals(t.positions, t.triangles);
  EXPECT_TRUE(n.row(0).isApprox(-Eigen::RowVector3d(1, 1, 1).normalized()));
  for (int v = 0; v < 4; ++v) EXPECT_NEAR(n.row(v).norm(), 1.0, 1e-15);
}

TEST(VertexQuantities, LumpedMassesSumToDensityTimesArea) {
  const Mesh m = generateMesh({MeshFamily::Delaunay, 6, 3, {}});
  const RestState r = restOf(m);
  for (MassLumping lumping : {MassLumping::Barycentric, MassLumping::Voronoi})
    EXPECT_NEAR(lumpedVertexMasses(r, lumping, 2.5).sum(), 2.5 * r.faceAreas.sum(), 1e-13);
}

}  // namespace
}  // namespace flexure::modeling
