// Exact intersection checks (modeling/self_intersections.h): a flat sheet and a folded strip have
// none; a folded strip with a vertex of its upper layer pushed through the lower one has them, each
// involving a face of that vertex; faces touching at a shared position (adjacent faces, a cut's
// lips, coincident copies) are left out; a shell against an obstacle mesh.
#include <gtest/gtest.h>

#include <cmath>

#include "modeling/generators.h"
#include "modeling/self_intersections.h"

namespace flexure {
namespace {

using modeling::Mesh;

Mesh flatSheet(int n) {
  modeling::GeneratorOptions options;
  options.n = n;
  return modeling::generateMesh(options);
}

// The unit square's 4-8 mesh (10 × 10 cells) folded into a U along x: the lower layer for
// s = x + ½ ≤ 0.4, a bend through s = 0.5 up to s = 0.6, and the upper layer 0.4 above the lower
// one for s ≥ 0.6, running back over it.
Mesh foldedStrip() {
  Mesh mesh = flatSheet(10);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const double s = mesh.positions(v, 0) + 0.5;
    double x = s, z = 0.0;
    if (s > 0.4 && s < 0.6) {
      const double angle = M_PI * (s - 0.4) / 0.2;
      x = 0.4 + 0.2 * std::sin(angle), z = 0.2 * (1 - std::cos(angle));
    } else if (s >= 0.6) {
      x = 0.4 - (s - 0.6), z = 0.4;
    }
    mesh.positions(v, 0) = x, mesh.positions(v, 2) = z;
  }
  return mesh;
}

int vertexNear(const Mesh& mesh, double x, double y, double z) {
  for (int v = 0; v < mesh.vertexCount(); ++v)
    if ((mesh.positions.row(v) - Eigen::RowVector3d(x, y, z)).norm() < 1e-9) return v;
  return -1;
}

bool faceHasVertex(const Mesh& mesh, int f, int v) {
  return (mesh.triangles.row(f).array() == v).any();
}

TEST(SelfIntersections, FlatSheetAndFoldedStripHaveNone) {
  EXPECT_TRUE(modeling::intersectingFacePairs(flatSheet(8)).empty());
  EXPECT_TRUE(modeling::intersectingFacePairs(foldedStrip()).empty());
}

TEST(SelfIntersections, AVertexPushedThroughTheLowerLayerIsFound) {
  Mesh mesh = foldedStrip();
  const int pushed = vertexNear(mesh, 0.2, 0.0, 0.4);  // s = 0.8, on the upper layer
  ASSERT_GE(pushed, 0);
  mesh.positions(pushed, 2) = -0.2;
  const std::vector<std::array<int, 2>> pairs = modeling::intersectingFacePairs(mesh);
  ASSERT_FALSE(pairs.empty());
  for (const auto& [f, g] : pairs) {
    EXPECT_LT(f, g);
    EXPECT_TRUE(faceHasVertex(mesh, f, pushed) != faceHasVertex(mesh, g, pushed))
        << "faces " << f << ", " << g;
  }
}

TEST(SelfIntersections, FacesSharingAPositionAreLeftOut) {
  // Two coincident copies of a triangle with distinct vertex indices.
  Mesh copies;
  copies.positions.resize(6, 3);
  copies.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  copies.triangles.resize(2, 3);
  copies.triangles << 0, 1, 2, 3, 4, 5;
  EXPECT_TRUE(modeling::intersectingFacePairs(copies).empty());
  // A cut's lips: a triangle and one turned about their common (duplicated) vertex into it.
  Mesh lips = copies;
  lips.positions.row(4) << 0.5, 0.5, -0.5;
  lips.positions.row(5) << 0.5, 0.5, 0.5;
  EXPECT_TRUE(modeling::intersectingFacePairs(lips).empty());
  // Without the shared position the same crossing is found.
  lips.positions.row(3) << 0.4, 0.4, 0.0;
  lips.positions.row(4) << 0.3, 0.3, -0.5;
  lips.positions.row(5) << 0.3, 0.3, 0.5;
  EXPECT_EQ(modeling::intersectingFacePairs(lips), (std::vector<std::array<int, 2>>{{0, 1}}));
}

TEST(SelfIntersections, ShellAgainstAnObstacleMesh) {
  const Mesh sheet = flatSheet(4);  // z = 0 over [−½, ½]²
  Mesh spike;
  spike.positions.resize(3, 3);
  spike.positions << 0.1, 0.1, -0.5, 0.2, 0.1, 0.5, 0.1, 0.2, 0.5;
  spike.triangles.resize(1, 3);
  spike.triangles << 0, 1, 2;
  const std::vector<std::array<int, 2>> pairs = modeling::intersectingFacePairs(sheet, spike);
  ASSERT_FALSE(pairs.empty());
  for (const auto& [f, g] : pairs) {
    EXPECT_EQ(g, 0);
    EXPECT_LT(f, sheet.faceCount());
  }
  // Raised above the sheet: none; resting on it with a vertex: touching counts.
  spike.positions.col(2).array() += 0.6;
  EXPECT_TRUE(modeling::intersectingFacePairs(sheet, spike).empty());
  spike.positions(0, 2) = 0.0;
  EXPECT_FALSE(modeling::intersectingFacePairs(sheet, spike).empty());
}

}  // namespace
}  // namespace flexure
