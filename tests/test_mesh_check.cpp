#include "modeling/mesh_check.h"
#include "modeling/mesh_repair.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "modeling/errors.h"
#include "support/small_meshes.h"

namespace flexure::modeling {
namespace {

using flexure::testing::gridMesh;
using flexure::testing::tetrahedron;
using flexure::testing::twoTriangleSquare;
using ::testing::HasSubstr;

int count(const MeshCheck& check, MeshProblemKind kind) {
  return check.problemCounts[static_cast<int>(kind)];
}

// The single problem of `mesh`, which must have exactly one.
MeshProblem onlyProblem(const Mesh& mesh) {
  const MeshCheck check = checkMesh(mesh);
  EXPECT_EQ(check.totalProblems(), 1);
  return check.problems.empty() ? MeshProblem{} : check.problems.front();
}

TEST(MeshCheck, AcceptsValidMeshes) {
  EXPECT_TRUE(checkMesh(twoTriangleSquare()).valid());
  EXPECT_TRUE(checkMesh(tetrahedron()).valid());
  EXPECT_TRUE(checkMesh(gridMesh(5, 3)).valid());
  EXPECT_TRUE(checkMesh(gridMesh(3, 3, [](int i, int j) { return i == 1 && j == 1; })).valid());
  EXPECT_NO_THROW(requireValidMesh(gridMesh(4, 4), "grid.obj"));
}

TEST(MeshCheck, EmptyMesh) {
  Mesh m;
  m.positions.resize(3, 3);
  m.positions.setZero();
  const MeshProblem p = onlyProblem(m);
  EXPECT_EQ(p.kind, MeshProblemKind::Empty);
  EXPECT_THAT(p.reason, HasSubstr("no faces"));
}

TEST(MeshCheck, NonFiniteCoordinateNamesVertexAndAxis) {
  Mesh m = twoTriangleSquare();
  m.positions(2, 1) = std::numeric_limits<double>::quiet_NaN();
  m.positions(3, 2) = std::numeric_limits<double>::infinity();
  const MeshCheck check = checkMesh(m);
  ASSERT_EQ(count(check, MeshProblemKind::NonFiniteCoordinate), 2);
  EXPECT_EQ(check.problems[0].element, "vertex 2");
  EXPECT_THAT(check.problems[0].reason, HasSubstr("y is NaN"));
  EXPECT_THAT(check.problems[1].reason, HasSubstr("z is infinite"));
}

TEST(MeshCheck, IndexOutOfRangeAndRepeatedVertex) {
  Mesh m = twoTriangleSquare();
  m.triangles(1, 2) = 7;
  EXPECT_EQ(onlyProblem(m).kind, MeshProblemKind::VertexIndexOutOfRange);
  m = twoTriangleSquare();
  m.triangles(1, 2) = 0;
  const MeshProblem p = checkMesh(m).problems.front();
  EXPECT_EQ(p.kind, MeshProblemKind::RepeatedVertexInFace);
  EXPECT_EQ(p.element, "face 1 (vertices 0, 2, 0)");
}

// Coordinates near the largest double: the area overflows to inf, which is no zero area.
TEST(MeshCheck, AreaOverflowIsNotZeroArea) {
  Mesh m = twoTriangleSquare();
  m.positions *= 1e200;
  const MeshCheck check = checkMesh(m);
  ASSERT_EQ(check.problems.size(), 2u);
  EXPECT_EQ(check.problems[0].kind, MeshProblemKind::AreaOverflow);
  EXPECT_EQ(meshProblemName(check.problems[0].kind), "area_overflow");
  EXPECT_THAT(check.problems[0].reason, ::testing::StartsWith("its area or edge lengths overflow"));
  EXPECT_THAT(check.problems[0].reason, ::testing::HasSubstr("scale the mesh down"));
}

TEST(MeshCheck, ZeroAreaFace) {
  Mesh m = twoTriangleSquare();
  m.positions.row(3) << 2, 2, 0;  // on the line through vertices 0 and 2: face (0, 2, 3) collapses
  const MeshProblem p = onlyProblem(m);
  EXPECT_EQ(p.kind, MeshProblemKind::ZeroAreaFace);
  EXPECT_EQ(p.element, "face 1 (vertices 0, 2, 3)");
  // A thin but honest sliver is not degenerate: the test is relative to the face's size.
  m.positions.row(3) << 2, 2 + 1e-6, 0;
  EXPECT_TRUE(checkMesh(m).valid());
  Mesh tiny = twoTriangleSquare();
  tiny.positions *= 1e-9;
  EXPECT_TRUE(checkMesh(tiny).valid());
}

TEST(MeshCheck, UnreferencedVertex) {
  Mesh m = twoTriangleSquare();
  m.positions.conservativeResize(5, 3);
  m.positions.row(4) << 5, 5, 5;
  const MeshProblem p = onlyProblem(m);
  EXPECT_EQ(p.kind, MeshProblemKind::UnreferencedVertex);
  EXPECT_EQ(p.element, "vertex 4");
}

TEST(MeshCheck, DuplicateFaceInAnyRotationOrOrientation) {
  for (const Eigen::RowVector3i& copy :
       {Eigen::RowVector3i(2, 0, 1), Eigen::RowVector3i(0, 2, 1)}) {
    Mesh m = twoTriangleSquare();
    m.triangles.conservativeResize(3, 3);
    m.triangles.row(2) = copy;
    const MeshCheck check = checkMesh(m);
    ASSERT_EQ(count(check, MeshProblemKind::DuplicateFace), 1);
    EXPECT_EQ(check.problems.front().element, "faces 0 and 2");
    EXPECT_EQ(count(check, MeshProblemKind::InconsistentOrientation), 0);
  }
}

TEST(MeshCheck, NonManifoldEdge) {
  Mesh m = twoTriangleSquare();
  m.positions.conservativeResize(5, 3);
  m.positions.row(4) << 0.5, 0.5, 1;
  m.triangles.conservativeResize(3, 3);
  m.triangles.row(2) << 0, 4, 2;  // a fin on the diagonal (0, 2)
  const MeshCheck check = checkMesh(m);
  ASSERT_EQ(count(check, MeshProblemKind::NonManifoldEdge), 1);
  const MeshProblem& p = check.problems.front();
  EXPECT_EQ(p.element, "edge (0, 2)");
  EXPECT_THAT(p.reason, HasSubstr("shared by 3 faces (0, 1, 2)"));
}

TEST(MeshCheck, InconsistentOrientation) {
  Mesh m = twoTriangleSquare();
  m.triangles.row(1) << 0, 3, 2;  // flipped
  const MeshProblem p = onlyProblem(m);
  EXPECT_EQ(p.kind, MeshProblemKind::InconsistentOrientation);
  EXPECT_EQ(p.element, "faces 0 and 1");
  EXPECT_THAT(p.reason, HasSubstr("edge (0, 2)"));
}

TEST(MeshCheck, NonManifoldVertexBowtie) {
  // Two triangles touching only at vertex 0.
  Mesh m;
  m.positions.resize(5, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 3, 4;
  const MeshProblem p = onlyProblem(m);
  EXPECT_EQ(p.kind, MeshProblemKind::NonManifoldVertex);
  EXPECT_EQ(p.element, "vertex 0");
  EXPECT_THAT(p.reason, HasSubstr("2 separate fans"));
}

TEST(MeshCheck, NonManifoldVertexBetweenTwoGridsSharingACorner) {
  // Cells (0,0) and (1,1) of a 2×2 grid share only vertex 4: a bowtie made of fans of 2 faces.
  const Mesh m = gridMesh(2, 2, [](int i, int j) { return i != j; });
  const MeshCheck check = checkMesh(m);
  EXPECT_EQ(count(check, MeshProblemKind::NonManifoldVertex), 1);
  EXPECT_EQ(count(check, MeshProblemKind::UnreferencedVertex), 2);  // vertices 2 and 6
}

TEST(MeshCheck, CountsEveryProblemButKeepsTheFirstFew) {
  Mesh m = gridMesh(10, 10);
  m.positions.conservativeResize(m.vertexCount() + 20, 3);
  m.positions.bottomRows(20).setOnes();
  const MeshCheck check = checkMesh(m, 5);
  EXPECT_EQ(count(check, MeshProblemKind::UnreferencedVertex), 20);
  EXPECT_EQ(check.problems.size(), 5u);
}

TEST(MeshCheck, RequireValidMeshNamesSourceElementAndCount) {
  Mesh m = gridMesh(10, 10);
  m.positions.conservativeResize(m.vertexCount() + 4, 3);
  m.positions.bottomRows(4).setOnes();
  try {
    requireValidMesh(m, "plate.off");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plate.off: vertex 121: is used by no face"));
    EXPECT_THAT(e.what(), HasSubstr("and 1 more problem ("));
  }
}

}  // namespace
}  // namespace flexure::modeling

namespace flexure::modeling {
namespace {

// A square whose second triangle runs the wrong way, a vertex no face uses (4) and a triangle
// touching the square at vertex 2 only: the three problems repairMesh mends, one of each.
Mesh brokenSquare() {
  Mesh m;
  m.positions.resize(7, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 5, 5, 2, 1, 0, 2, 2, 0;
  m.triangles.resize(3, 3);
  m.triangles << 0, 1, 2, 0, 3, 2, 2, 5, 6;
  return m;
}

TEST(MeshRepair, DropsSplitsAndOrientsUntilTheCheckPasses) {
  const Mesh broken = brokenSquare();
  const MeshCheck before = checkMesh(broken);
  ASSERT_FALSE(before.valid());
  EXPECT_GT(before.problemCounts[static_cast<int>(MeshProblemKind::UnreferencedVertex)], 0);
  EXPECT_GT(before.problemCounts[static_cast<int>(MeshProblemKind::InconsistentOrientation)], 0);
  EXPECT_GT(before.problemCounts[static_cast<int>(MeshProblemKind::NonManifoldVertex)], 0);
  const RepairedMesh repaired = repairMesh(broken);
  EXPECT_EQ(repaired.report.droppedVertices, 1);
  EXPECT_EQ(repaired.report.addedVertices, 1);
  EXPECT_EQ(repaired.report.flippedFaces, 1);
  EXPECT_EQ(repaired.mesh.vertexCount(), 7);  // 7 − 1 dropped + 1 copy of vertex 2
  EXPECT_EQ(repaired.mesh.faceCount(), 3);
  EXPECT_TRUE(checkMesh(repaired.mesh).valid());
  // A valid mesh comes back as it was.
  const Mesh square = flexure::testing::twoTriangleSquare();
  const RepairedMesh same = repairMesh(square);
  EXPECT_FALSE(same.report.changed());
  EXPECT_EQ(same.mesh.positions, square.positions);
  EXPECT_EQ(same.mesh.triangles, square.triangles);
}

}  // namespace
}  // namespace flexure::modeling
