#include "modeling/boundary_rings.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "modeling/generators.h"
#include "support/small_meshes.h"

namespace flexure::modeling {
namespace {

using flexure::testing::gridMesh;
using flexure::testing::tetrahedron;

// Twice the signed area enclosed by a loop of vertices in the xy-plane.
double signedArea(const Positions& x, const std::vector<int>& loop) {
  double twice = 0.0;
  for (size_t k = 0; k < loop.size(); ++k) {
    const auto a = x.row(loop[k]), b = x.row(loop[(k + 1) % loop.size()]);
    twice += a(0) * b(1) - b(0) * a(1);
  }
  return 0.5 * twice;
}

TEST(BoundaryRings, Patch48RingIsGridDistanceToTheBoundary) {
  for (const int n : {4, 8, 9}) {
    const Mesh mesh = generateMesh({MeshFamily::Patch48, n, 1, {}});
    const Eigen::VectorXi rings = vertexRings(compileStencils(mesh));
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        EXPECT_EQ(rings[j * (n + 1) + i], std::min({i, j, n - i, n - j})) << i << ", " << j;
      }
    }
    EXPECT_EQ(verticesInRings(rings, 1).size(), 4u * n);
    EXPECT_EQ(verticesInRings(rings, 2).size(), 4u * n + 4u * (n - 2));
  }
}

TEST(BoundaryRings, RingsFollowEdgesNotDistance) {
  // On a criss mesh the diagonals join (i, j) to (i+1, j+1): rings are still grid distances,
  // since a diagonal changes the distance to every side by at most one.
  const Mesh mesh = gridMesh(6, 6);
  const Eigen::VectorXi rings = vertexRings(compileStencils(mesh));
  EXPECT_EQ(rings[3 * 7 + 3], 3);
  EXPECT_EQ(rings.maxCoeff(), 3);
}

TEST(BoundaryRings, SquareHasOneCounterClockwiseLoop) {
  const int n = 6;
  const Mesh mesh = generateMesh({MeshFamily::Patch48, n, 1, {}});
  const Stencils s = compileStencils(mesh);
  const auto loops = boundaryLoops(s);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 4u * n);
  EXPECT_EQ(loops[0].front(), 0);
  EXPECT_NEAR(signedArea(mesh.positions, loops[0]), 1.0, 1e-12);
}

TEST(BoundaryRings, AnnulusHasTwoLoopsAndRingsFromBoth) {
  // A 3 × 3 grid with the centre cell removed: an outer loop of 12 and an inner loop of 4 vertices,
  // and every vertex is on one of them.
  const Mesh mesh = gridMesh(3, 3, [](int i, int j) { return i == 1 && j == 1; });
  const Stencils s = compileStencils(mesh);
  auto loops = boundaryLoops(s);
  ASSERT_EQ(loops.size(), 2u);
  std::sort(loops.begin(), loops.end(), [](auto& a, auto& b) { return a.size() > b.size(); });
  EXPECT_EQ(loops[0].size(), 12u);
  EXPECT_EQ(loops[1].size(), 4u);
  EXPECT_GT(signedArea(mesh.positions, loops[0]), 0.0);  // outer: counter-clockwise
  EXPECT_LT(signedArea(mesh.positions, loops[1]), 0.0);  // hole: clockwise
  EXPECT_EQ(vertexRings(s).maxCoeff(), 0);
}

TEST(BoundaryRings, ClosedMeshHasNoBoundaryAndNoRings) {
  const Stencils s = compileStencils(tetrahedron());
  EXPECT_TRUE(boundaryLoops(s).empty());
  EXPECT_EQ(vertexRings(s), Eigen::VectorXi::Constant(4, -1));
  EXPECT_TRUE(verticesInRings(vertexRings(s), 2).empty());
}

}  // namespace
}  // namespace flexure::modeling
