#include "modeling/stencils.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "modeling/generators.h"
#include "support/small_meshes.h"

namespace flexure::modeling {
namespace {

using flexure::testing::gridMesh;
using flexure::testing::tetrahedron;
using flexure::testing::twoTriangleSquare;

// The directed edges a → b that the faces traverse, with their face.
std::set<std::tuple<int, int, int>> directedEdges(const Stencils& s) {
  std::set<std::tuple<int, int, int>> out;
  for (int f = 0; f < s.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) out.insert({s.faces(f, i), s.faces(f, (i + 1) % 3), f});
  return out;
}

bool hasCounterClockwiseFace(const Stencils& s, int a, int b, int c) {
  for (int f = 0; f < s.faceCount(); ++f)
    for (int r = 0; r < 3; ++r)
      if (s.faces(f, r) == a && s.faces(f, (r + 1) % 3) == b && s.faces(f, (r + 2) % 3) == c)
        return true;
  return false;
}

TEST(Stencils, TwoTriangleSquareByHand) {
  const Stencils s = compileStencils(twoTriangleSquare());
  // Edges in lexicographic order.
  IndexPairs edges(5, 2);
  edges << 0, 1, 0, 2, 0, 3, 1, 2, 2, 3;
  EXPECT_EQ(s.edges, edges);
  // The only hinge is the diagonal (0, 2): f = (0, 2, 3) holds 0 → 2, g = (2, 0, 1).
  ASSERT_EQ(s.hingeCount(), 1);
  EXPECT_EQ(s.hinges.row(0), Eigen::RowVector4i(0, 2, 3, 1));
  EXPECT_EQ(s.hingeEdges[0], 1);
  EXPECT_EQ(s.edgeFaces.row(1), Eigen::RowVector2i(1, 0));
  // Face 0 = (0, 1, 2): edge 0 is (1, 2) boundary, edge 1 is (2, 0) = the diagonal, flap 3.
  EXPECT_EQ(s.faceFlaps.row(0), Eigen::RowVector3i(-1, 3, -1));
  EXPECT_EQ(s.faceEdges.row(0), Eigen::RowVector3i(3, 1, 0));
  EXPECT_EQ(s.faceEdgeSigns.row(0), Eigen::RowVector3i(1, -1, 1));
  // Face 1 = (0, 2, 3): 2 → 3 up, 3 → 0 down, 0 → 2 up.
  EXPECT_EQ(s.faceEdgeSigns.row(1), Eigen::RowVector3i(1, -1, 1));
  EXPECT_FALSE(s.faceIsInterior(0));
  EXPECT_TRUE(s.vertexOnBoundary.all());
  // Vertex 0: counter-clockwise from the boundary neighbour 1 to the boundary neighbour 3.
  EXPECT_EQ(s.valence(0), 3);
  EXPECT_EQ(s.oneRingVertices.segment(s.oneRingOffsets[0], 3), Eigen::Vector3i(1, 2, 3));
}

// Invariants that hold on every valid mesh.
void expectConsistent(const Mesh& mesh) {
  const Stencils s = compileStencils(mesh);
  const auto directed = directedEdges(s);
  int boundaryEdges = 0;
  for (int e = 0; e < s.edgeCount(); ++e) {
    const int a = s.edges(e, 0), b = s.edges(e, 1);
    ASSERT_LT(a, b);
    if (e > 0) {
      EXPECT_LT(std::make_pair(s.edges(e - 1, 0), s.edges(e - 1, 1)), std::make_pair(a, b));
    }
    if (s.edgeFaces(e, 0) >= 0) {
      EXPECT_TRUE(directed.count({a, b, s.edgeFaces(e, 0)}));
    }
    if (s.edgeFaces(e, 1) >= 0) {
      EXPECT_TRUE(directed.count({b, a, s.edgeFaces(e, 1)}));
    }
    ASSERT_TRUE(s.edgeFaces(e, 0) >= 0 || s.edgeFaces(e, 1) >= 0);
    boundaryEdges += (s.edgeFaces(e, 0) < 0 || s.edgeFaces(e, 1) < 0);
  }
  EXPECT_EQ(s.hingeCount(), s.edgeCount() - boundaryEdges);

  for (int f = 0; f < s.faceCount(); ++f) {
    for (int i = 0; i < 3; ++i) {
      const int a = s.faces(f, (i + 1) % 3), b = s.faces(f, (i + 2) % 3);
      const int e = s.faceEdges(f, i);
      EXPECT_EQ(s.edges(e, 0), std::min(a, b));
      EXPECT_EQ(s.edges(e, 1), std::max(a, b));
      EXPECT_EQ(s.faceEdgeSigns(f, i), a < b ? 1 : -1);
      const int flap = s.faceFlaps(f, i);
      const bool boundary = s.edgeFaces(e, 0) < 0 || s.edgeFaces(e, 1) < 0;
      EXPECT_EQ(flap < 0, boundary);
      if (flap >= 0) {
        EXPECT_TRUE(hasCounterClockwiseFace(s, b, a, flap));
      }
    }
  }
  // Across an interior edge the two faces have opposite signs σ.
  for (int h = 0; h < s.hingeCount(); ++h) {
    const int e = s.hingeEdges[h];
    const auto sign = [&](int f) {
      for (int i = 0; i < 3; ++i)
        if (s.faceEdges(f, i) == e) return s.faceEdgeSigns(f, i);
      return 0;
    };
    EXPECT_EQ(sign(s.edgeFaces(e, 0)), 1);
    EXPECT_EQ(sign(s.edgeFaces(e, 1)), -1);
    const Eigen::RowVector4i q = s.hinges.row(h);
    EXPECT_LT(q(0), q(1));
    EXPECT_TRUE(hasCounterClockwiseFace(s, q(0), q(1), q(2)));
    EXPECT_TRUE(hasCounterClockwiseFace(s, q(1), q(0), q(3)));
  }
  // One-rings: consecutive neighbours span counter-clockwise faces; valences sum to 2E.
  EXPECT_EQ(s.oneRingOffsets[s.vertexCount()], 2 * s.edgeCount());
  for (int v = 0; v < s.vertexCount(); ++v) {
    const int begin = s.oneRingOffsets[v], n = s.valence(v);
    const int pairs = s.vertexOnBoundary[v] ? n - 1 : n;
    for (int k = 0; k < pairs; ++k) {
      const int a = s.oneRingVertices[begin + k], b = s.oneRingVertices[begin + (k + 1) % n];
      EXPECT_TRUE(hasCounterClockwiseFace(s, v, a, b)) << "vertex " << v;
    }
  }
  EXPECT_EQ(s.vertexCount() - s.edgeCount() + s.faceCount(),
            boundaryEdges > 0 ? 1 : 2);  // the test meshes are disks or spheres
}

TEST(Stencils, InvariantsOnSmallMeshes) {
  expectConsistent(twoTriangleSquare());
  expectConsistent(tetrahedron());
  expectConsistent(gridMesh(3, 2));
}

TEST(Stencils, InvariantsOnGeneratedFamilies) {
  for (MeshFamily family :
       {MeshFamily::Patch48, MeshFamily::Stripe, MeshFamily::Criss, MeshFamily::Delaunay}) {
    SCOPED_TRACE(std::string(meshFamilyName(family)));
    expectConsistent(generateMesh({family, 6, 3, {}}));
  }
}

TEST(Stencils, Patch48InteriorFacesAndHinges) {
  const int n = 8;
  const Stencils s = compileStencils(generateMesh({MeshFamily::Patch48, n, 1, {}}));
  EXPECT_EQ(s.edgeCount(), 2 * n * (n + 1) + n * n);  // axis edges + one diagonal per cell
  EXPECT_EQ(s.hingeCount(), s.edgeCount() - 4 * n);
  int interiorFaces = 0;
  for (int f = 0; f < s.faceCount(); ++f) interiorFaces += s.faceIsInterior(f);
  EXPECT_EQ(interiorFaces, 2 * n * n - 4 * n);  // every boundary cell has one boundary face
}

TEST(Stencils, ComponentsOfTwoSeparateSquares) {
  // Two copies of the two-triangle square, the second's vertices numbered 4..7.
  Mesh m = flexure::testing::twoTriangleSquare();
  Mesh two;
  two.positions.resize(8, 3);
  two.positions << m.positions, m.positions.rowwise() + Eigen::RowVector3d(3, 0, 0);
  two.triangles.resize(4, 3);
  two.triangles << m.triangles, m.triangles.array() + 4;
  const std::vector<int> component = vertexComponents(compileStencils(two));
  EXPECT_THAT(component, ::testing::ElementsAre(0, 0, 0, 0, 1, 1, 1, 1));
  EXPECT_THAT(vertexComponents(compileStencils(m)), ::testing::Each(0));
}

}  // namespace
}  // namespace flexure::modeling
