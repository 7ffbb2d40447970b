// The region forms a user types without coordinates (modeling/fairing_region.h): around:VERTEX,R
// (geodesic distance by fast marching, checked against the Euclidean distance on flat meshes)
// and rings:VERTEX,K (against rings grown by hand), and their refusals.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "modeling/errors.h"
#include "modeling/fairing_region.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/stencils.h"
#include "modeling/vertex_sets.h"
#include "support/input_error.h"

namespace flexure {
namespace {

using modeling::Mesh;
using ::testing::HasSubstr;
using ::testing::StartsWith;

using testing::inputErrorOf;

Mesh flatMesh(modeling::MeshFamily family, int n) {
  modeling::GeneratorOptions generator;
  generator.family = family;
  generator.n = n;
  generator.seed = 7;
  return modeling::generateMesh(generator);
}

// The vertex nearest the point p.
int nearestVertex(const Mesh& mesh, const Eigen::Vector3d& p) {
  Eigen::Index best = 0;
  (mesh.positions.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

// On a flat mesh the geodesic distance is the Euclidean one. Fast marching meets it to round-off
// on the regular patch48 and to within 2 % (measured 1.7 %) beyond the first ring on an irregular
// Delaunay mesh, never below it; Dijkstra along edges alone would be up to 15 % long.
TEST(FairingRegionForms, GeodesicDistanceOnAFlatMeshIsEuclidean) {
  for (const modeling::MeshFamily family :
       {modeling::MeshFamily::Patch48, modeling::MeshFamily::Delaunay}) {
    const Mesh plate = flatMesh(family, 32);
    const modeling::Stencils s = modeling::compileStencils(plate);
    const int source = nearestVertex(plate, Eigen::Vector3d(0.1, -0.05, 0.0));
    const double h = modeling::meanEdgeLength(plate, s);
    const std::vector<double> d = modeling::geodesicDistances(plate, s, source, 10.0);
    double worst = 0.0;
    int measured = 0;
    for (int v = 0; v < plate.vertexCount(); ++v) {
      const double exact = (plate.positions.row(v) - plate.positions.row(source)).norm();
      EXPECT_GE(d[v], exact * (1.0 - 1e-12)) << "vertex " << v;
      if (exact < 2.0 * h) continue;
      worst = std::max(worst, d[v] / exact - 1.0);
      ++measured;
    }
    EXPECT_GT(measured, 500);
    EXPECT_LT(worst, family == modeling::MeshFamily::Patch48 ? 1e-12 : 0.02)
        << "family " << static_cast<int>(family);
    // The reach cuts the march off: vertices beyond it are +∞.
    const std::vector<double> near = modeling::geodesicDistances(plate, s, source, 3.0 * h);
    for (int v = 0; v < plate.vertexCount(); ++v) {
      if (std::isfinite(near[v])) {
        EXPECT_LE(near[v], 3.0 * h);
        EXPECT_DOUBLE_EQ(near[v], d[v]);
      } else {
        EXPECT_GT(d[v], 3.0 * h);
      }
    }
  }
}

TEST(FairingRegionForms, AroundSelectsTheGeodesicDisk) {
  const Mesh plate = flatMesh(modeling::MeshFamily::Delaunay, 32);
  const modeling::Stencils s = modeling::compileStencils(plate);
  const int source = nearestVertex(plate, Eigen::Vector3d::Zero());
  const double h = modeling::meanEdgeLength(plate, s);
  const std::vector<bool> region =
      modeling::parseRegion("around:" + std::to_string(source) + ",5", plate, s);
  // Every vertex within 0.99 · 5 ℓ̄ of the source (Euclidean) is in, none beyond 5 ℓ̄.
  int inside = 0;
  for (int v = 0; v < plate.vertexCount(); ++v) {
    const double r = (plate.positions.row(v) - plate.positions.row(source)).norm() / h;
    if (r <= 0.99 * 5.0) {
      EXPECT_TRUE(region[v]) << "vertex " << v << " at " << r;
    }
    if (r > 5.0) {
      EXPECT_FALSE(region[v]) << "vertex " << v << " at " << r;
    }
    inside += region[v];
  }
  // About π 5² ℓ̄² of area, with a vertex per ≈ (√3/4 · 2) ℓ̄² of an equilateral-ish mesh.
  EXPECT_GT(inside, 60);
  EXPECT_LT(inside, 120);
  modeling::requireFairableRegion(s, region, "around");
}

TEST(FairingRegionForms, RingsSelectTheVertexAndItsRings) {
  const Mesh plate = flatMesh(modeling::MeshFamily::Delaunay, 16);
  const modeling::Stencils s = modeling::compileStencils(plate);
  const int source = nearestVertex(plate, Eigen::Vector3d::Zero());
  // Rings grown by hand from the one-ring lists.
  std::set<int> grown = {source};
  for (int k = 0; k <= 3; ++k) {
    const std::vector<bool> region = modeling::parseRegion(
        "rings:" + std::to_string(source) + "," + std::to_string(k), plate, s);
    std::set<int> got;
    for (int v = 0; v < plate.vertexCount(); ++v)
      if (region[v]) got.insert(v);
    EXPECT_EQ(got, grown) << "K = " << k;
    if (k == 1) {
      EXPECT_EQ(got.size(), static_cast<std::size_t>(1 + s.valence(source)));
    }
    std::set<int> next = grown;
    for (const int v : grown)
      for (int r = s.oneRingOffsets[v]; r < s.oneRingOffsets[v + 1]; ++r)
        next.insert(s.oneRingVertices[r]);
    grown = next;
  }
}

TEST(FairingRegionForms, MalformedFormsAreRefusedNamingTheSpecAndTheProblem) {
  const Mesh plate = flatMesh(modeling::MeshFamily::Patch48, 8);  // 81 vertices
  const modeling::Stencils s = modeling::compileStencils(plate);
  const auto refusal = [&](const std::string& spec) {
    return inputErrorOf([&] { modeling::parseRegion(spec, plate, s); });
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"around:81,2", "vertex 81 is out of range: the mesh has 81 vertices (0 .. 80)"},
      {"around:-1,2", "vertex -1 is out of range"},
      {"around:40,0", "R = 0 must be a finite number > 0"},
      {"around:40,-1", "R = -1 must be a finite number > 0"},
      {"around:40,inf", "R = inf must be a finite number > 0"},
      {"around:40,two", "R 'two' is not a number"},
      {"around:40,2x", "R '2x' is not a number"},
      {"around:40", "expected around:VERTEX,R"},
      {"around:", "expected around:VERTEX,R"},
      {"around:40,2,", "expected around:VERTEX,R"},
      {"around:40,2,3", "expected around:VERTEX,R"},
      {"around:4.5,2", "'4.5' is not a vertex index"},
      {"rings:40,-1", "K = -1 must be >= 0"},
      {"rings:40,1.5", "K '1.5' is not a whole number"},
      {"rings:99,1", "vertex 99 is out of range"},
      {"rings:40", "expected rings:VERTEX,K"},
      {"rings:40,1 ", "K '1 ' is not a whole number"},
      {"ring:40,1", "expected vertices:FILE, sphere:x,y,z,r, around:VERTEX,R, rings:VERTEX,K"},
  };
  for (const auto& [spec, problem] : cases) {
    const std::string message = refusal(spec);
    EXPECT_THAT(message, StartsWith("region " + spec + ":")) << spec;
    EXPECT_THAT(message, HasSubstr(problem)) << spec;
  }
}

}  // namespace
}  // namespace flexure
