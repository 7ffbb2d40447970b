// Local isotropic remeshing of a fairing region (modeling/region_remeshing.h): the slivers of the
// region go, everything outside the remeshed faces keeps its position bit for bit, the mesh stays
// valid, and the sampled Hausdorff distance to the input is 0 on a flat region and small but
// positive on a curved one.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <vector>

#include "modeling/fairing_region.h"
#include "modeling/generators.h"
#include "modeling/mesh_check.h"
#include "modeling/region_remeshing.h"
#include "modeling/stencils.h"
#include "support/input_error.h"

namespace flexure {
namespace {

using modeling::Mesh;
using ::testing::HasSubstr;
using testing::inputErrorOf;

constexpr int kGrid = 12;  // cells per side of the sliver grid

// A flat unit-spaced kGrid × kGrid grid in z = 0, each cell split along its diagonal, with the
// vertices of column 5 in rows 3 to kGrid − 3 moved to x = 5.98: the cells between columns 5 and
// 6 there are 0.02 wide, their triangles have angles down to 0.58°.
Mesh sliverGrid() {
  Mesh mesh;
  const int n = kGrid + 1;
  mesh.positions.resize(n * n, 3);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const bool moved = i == 5 && j >= 3 && j <= kGrid - 3;
      mesh.positions.row(j * n + i) << (moved ? 5.98 : i), j, 0.0;
    }
  }
  mesh.triangles.resize(2 * kGrid * kGrid, 3);
  int f = 0;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      mesh.triangles.row(f++) << a, b, c;
      mesh.triangles.row(f++) << a, c, d;
    }
  }
  return mesh;
}

// The faces with a vertex in `region`.
std::vector<bool> regionFaces(const Mesh& mesh, const std::vector<bool>& region) {
  std::vector<bool> faces(mesh.faceCount(), false);
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) faces[f] = faces[f] || region[mesh.triangles(f, k)];
  return faces;
}

// Everything outside the remeshed faces survives unchanged: every input vertex on a face that was
// not remeshed is in the output at the same position bit for bit, and the faces that were not
// remeshed are the input's, vertex for vertex.
void expectOutsideUnchanged(const Mesh& input, const std::vector<bool>& region,
                            const modeling::RemeshedRegion& r) {
  const std::vector<bool> inputRemeshed = regionFaces(input, region);
  std::vector<int> outputOf(input.vertexCount(), -1);
  for (int v = 0; v < r.mesh.vertexCount(); ++v)
    if (r.inputVertex[v] >= 0) outputOf[r.inputVertex[v]] = v;
  std::multiset<std::array<int, 3>> kept, expected;
  for (int f = 0; f < input.faceCount(); ++f) {
    if (inputRemeshed[f]) continue;
    std::array<int, 3> face{};
    for (int k = 0; k < 3; ++k) {
      const int v = input.triangles(f, k);
      ASSERT_GE(outputOf[v], 0) << "input vertex " << v << " of held face " << f << " removed";
      EXPECT_FALSE(r.region[outputOf[v]]) << "held vertex " << v << " in the new region";
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(r.mesh.positions(outputOf[v], c), input.positions(v, c)) << "vertex " << v;
      face[k] = v;
    }
    expected.insert(face);
  }
  for (int f = 0; f < r.mesh.faceCount(); ++f) {
    if (r.remeshedFace[f]) continue;
    std::array<int, 3> face{};
    for (int k = 0; k < 3; ++k) face[k] = r.inputVertex[r.mesh.triangles(f, k)];
    kept.insert(face);
  }
  EXPECT_EQ(kept, expected);
}

TEST(RegionRemeshing, SliversOfAFlatRegionGoAndTheRestStays) {
  const Mesh grid = sliverGrid();
  const modeling::Stencils stencils = modeling::compileStencils(grid);
  const std::vector<bool> region = modeling::interiorRegion(stencils);
  const modeling::RemeshedRegion r = modeling::remeshRegion(grid, region, {});
  EXPECT_LT(r.minAngleDegreesBefore, 0.6);
  // Measured 31.5° (CGAL 5.5); the bound leaves room for other versions.
  EXPECT_GT(r.minAngleDegreesAfter, 20.0);
  EXPECT_EQ(r.iterations, 3);
  const std::vector<bool> faces = regionFaces(grid, region);
  EXPECT_EQ(r.facesBefore, static_cast<int>(std::count(faces.begin(), faces.end(), true)));
  EXPECT_GT(r.facesAfter, 0);
  EXPECT_TRUE(modeling::checkMesh(r.mesh).valid());
  expectOutsideUnchanged(grid, region, r);
  // Flat: every point of either surface lies on the other (z = 0 throughout, the border the same).
  EXPECT_LT(r.hausdorffDistance, 1e-12);
  EXPECT_EQ(r.hausdorffDistance, std::max(r.hausdorffInputToRemeshed, r.hausdorffRemeshedToInput));
  for (int v = 0; v < r.mesh.vertexCount(); ++v) EXPECT_EQ(r.mesh.positions(v, 2), 0.0);
  // The new region is fairable: at least two rings from the boundary, as the input's.
  EXPECT_NO_THROW(modeling::requireFairableRegion(modeling::compileStencils(r.mesh), r.region,
                                                  "remeshed grid"));
}

// The target length defaults to the mean edge length of the remeshed faces: on the grid, between
// the unit cell side and its diagonal; given, it is used.
TEST(RegionRemeshing, TargetEdgeLengthIsTheRegionsMeanUnlessGiven) {
  const Mesh grid = sliverGrid();
  const std::vector<bool> region = modeling::interiorRegion(modeling::compileStencils(grid));
  const modeling::RemeshedRegion byDefault = modeling::remeshRegion(grid, region, {});
  EXPECT_GT(byDefault.targetEdgeLength, 0.9);
  EXPECT_LT(byDefault.targetEdgeLength, 1.42);
  modeling::RemeshOptions finer;
  finer.targetEdgeLength = 0.5;
  const modeling::RemeshedRegion fine = modeling::remeshRegion(grid, region, finer);
  EXPECT_EQ(fine.targetEdgeLength, 0.5);
  EXPECT_GT(fine.facesAfter, 2 * byDefault.facesAfter);
  expectOutsideUnchanged(grid, region, fine);
}

// A curved region (a hemisphere's interior): the remeshed surface is projected onto the input's
// facets, so its vertices lie on them, but its faces cut chords across their creases: the distance
// is positive and a small fraction of the target length (measured 0.0103 = 0.072 ℓ, ℓ = 0.144 on
// the unit hemisphere of 24 edges around; CGAL 5.5).
TEST(RegionRemeshing, CurvedRegionMovesLittle) {
  modeling::GeneratorOptions generator;
  generator.family = modeling::MeshFamily::Hemisphere;
  generator.n = 24;
  const Mesh dome = modeling::generateMesh(generator);
  const std::vector<bool> region = modeling::interiorRegion(modeling::compileStencils(dome));
  const modeling::RemeshedRegion r = modeling::remeshRegion(dome, region, {});
  EXPECT_TRUE(modeling::checkMesh(r.mesh).valid());
  expectOutsideUnchanged(dome, region, r);
  EXPECT_GT(r.hausdorffDistance, 1e-6 * r.targetEdgeLength);
  EXPECT_LT(r.hausdorffDistance, 0.1 * r.targetEdgeLength);
}

TEST(RegionRemeshing, BadOptionsAndRegionsAreRefusedNamingThem) {
  const Mesh grid = sliverGrid();
  const std::vector<bool> region = modeling::interiorRegion(modeling::compileStencils(grid));
  modeling::RemeshOptions o;
  o.targetEdgeLength = -1.0;
  EXPECT_THAT(inputErrorOf([&] { modeling::remeshRegion(grid, region, o); }),
              HasSubstr("RemeshOptions.targetEdgeLength -1"));
  o.targetEdgeLength = 1e-4;  // some 1e9 faces on the grid's region: refused before any work
  EXPECT_THAT(inputErrorOf([&] { modeling::remeshRegion(grid, region, o); }),
              HasSubstr("faces, over the 2e+06 a remeshing may make"));
  o.targetEdgeLength.reset();
  o.iterations = 0;
  EXPECT_THAT(inputErrorOf([&] { modeling::remeshRegion(grid, region, o); }),
              HasSubstr("RemeshOptions.iterations 0"));
  EXPECT_THAT(inputErrorOf([&] {
                modeling::remeshRegion(grid, std::vector<bool>(grid.vertexCount(), false), {});
              }),
              HasSubstr("no vertex"));
  EXPECT_THAT(inputErrorOf([&] { modeling::remeshRegion(grid, {true}, {}); }),
              HasSubstr("1 entries"));
}

}  // namespace
}  // namespace flexure
