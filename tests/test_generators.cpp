#include "modeling/generators.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "modeling/errors.h"
#include "modeling/mesh_check.h"

namespace flexure::modeling {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Edge = std::pair<int, int>;

// Undirected edges of the triangle list, each once.
std::set<Edge> edgesOf(const Mesh& mesh) {
  std::set<Edge> edges;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(f, k);
      const int b = mesh.triangles(f, (k + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  return edges;
}

std::vector<int> valences(const Mesh& mesh) {
  std::vector<int> valence(mesh.vertexCount(), 0);
  for (const auto& [a, b] : edgesOf(mesh)) {
    ++valence[a];
    ++valence[b];
  }
  return valence;
}

Eigen::Vector2d xy(const Mesh& mesh, int v) {
  return {mesh.positions(v, 0), mesh.positions(v, 1)};
}

// Twice the signed area of face f in the xy-plane (positive when counter-clockwise).
double doubleSignedArea(const Mesh& mesh, int f) {
  const Eigen::Vector2d a = xy(mesh, mesh.triangles(f, 0));
  const Eigen::Vector2d u = xy(mesh, mesh.triangles(f, 1)) - a;
  const Eigen::Vector2d w = xy(mesh, mesh.triangles(f, 2)) - a;
  return u.x() * w.y() - u.y() * w.x();
}

// The smallest interior angle of all faces, in degrees.
double minAngleDegrees(const Mesh& mesh) {
  double smallest = 180.0;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = xy(mesh, mesh.triangles(f, k));
      const Eigen::Vector2d u = xy(mesh, mesh.triangles(f, (k + 1) % 3)) - a;
      const Eigen::Vector2d w = xy(mesh, mesh.triangles(f, (k + 2) % 3)) - a;
      const double angle = std::atan2(u.x() * w.y() - u.y() * w.x(), u.dot(w));
      smallest = std::min(smallest, angle * 180.0 / kPi);
    }
  }
  return smallest;
}

double meanEdgeLength(const Mesh& mesh) {
  const std::set<Edge> edges = edgesOf(mesh);
  double total = 0.0;
  for (const auto& [a, b] : edges) total += (xy(mesh, a) - xy(mesh, b)).norm();
  return total / static_cast<double>(edges.size());
}

// Vertex-face pairs with the vertex strictly inside the face's circumcircle: the in-circle
// determinant, relative to the size of its terms, exceeds rounding.
int circumcircleViolations(const Mesh& mesh) {
  int violations = 0;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector2d a = xy(mesh, mesh.triangles(f, 0));
    const Eigen::Vector2d b = xy(mesh, mesh.triangles(f, 1));
    const Eigen::Vector2d c = xy(mesh, mesh.triangles(f, 2));
    for (int v = 0; v < mesh.vertexCount(); ++v) {
      if (v == mesh.triangles(f, 0) || v == mesh.triangles(f, 1) || v == mesh.triangles(f, 2)) {
        continue;
      }
      const Eigen::Vector2d p = xy(mesh, v);
      const Eigen::Vector2d pa = a - p, pb = b - p, pc = c - p;
      const double det = pa.squaredNorm() * (pb.x() * pc.y() - pb.y() * pc.x()) -
                         pb.squaredNorm() * (pa.x() * pc.y() - pa.y() * pc.x()) +
                         pc.squaredNorm() * (pa.x() * pb.y() - pa.y() * pb.x());
      const double scale = (pa.squaredNorm() + pb.squaredNorm() + pc.squaredNorm()) *
                           (pa.norm() * pb.norm() + pb.norm() * pc.norm() + pa.norm() * pc.norm());
      if (det > 1e-12 * scale) ++violations;
    }
  }
  return violations;
}

bool onBoundary(const Mesh& mesh, int v) {
  return std::abs(mesh.positions(v, 0)) == 0.5 || std::abs(mesh.positions(v, 1)) == 0.5;
}

// What every generated mesh must satisfy: a consistently oriented, edge-manifold triangulation
// of the square (Euler characteristic 1, area 1), counter-clockwise, flat, every vertex used.
void expectValidSquareMesh(const Mesh& mesh) {
  ASSERT_GT(mesh.faceCount(), 0);
  ASSERT_GE(mesh.triangles.minCoeff(), 0);
  ASSERT_LT(mesh.triangles.maxCoeff(), mesh.vertexCount());

  const std::set<Edge> edges = edgesOf(mesh);
  EXPECT_EQ(mesh.vertexCount() - static_cast<int>(edges.size()) + mesh.faceCount(), 1);

  double area = 0.0;
  int clockwise = 0;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const double a2 = doubleSignedArea(mesh, f);
    if (!(a2 > 0.0)) ++clockwise;
    area += 0.5 * a2;
  }
  EXPECT_EQ(clockwise, 0) << "faces not counter-clockwise";
  EXPECT_NEAR(area, 1.0, 1e-12);

  // Each directed edge once; each undirected edge in one (boundary) or two faces, and exactly
  // the boundary edges lie on the sides of the square.
  std::map<Edge, int> directed;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed[{mesh.triangles(f, k), mesh.triangles(f, (k + 1) % 3)}];
  }
  double boundaryLength = 0.0;
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "directed edge " << edge.first << "->" << edge.second;
    if (directed.count({edge.second, edge.first}) == 0) {
      boundaryLength += (xy(mesh, edge.first) - xy(mesh, edge.second)).norm();
      EXPECT_TRUE(onBoundary(mesh, edge.first) && onBoundary(mesh, edge.second));
    }
  }
  EXPECT_NEAR(boundaryLength, 4.0, 1e-12);

  std::vector<bool> used(mesh.vertexCount(), false);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) used[mesh.triangles(f, k)] = true;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unreferenced vertices";
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    EXPECT_LE(std::abs(mesh.positions(v, 0)), 0.5);
    EXPECT_LE(std::abs(mesh.positions(v, 1)), 0.5);
    EXPECT_EQ(mesh.positions(v, 2), 0.0);
  }
}

// The InputError message thrown by generateMesh(options); fails the test when none is thrown.
std::string inputErrorOf(const GeneratorOptions& options) {
  try {
    generateMesh(options);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError for " << meshFamilyName(options.family) << " n = " << options.n;
  return "";
}

GeneratorOptions optionsFor(MeshFamily family, int n, std::optional<double> aspect = {}) {
  GeneratorOptions options;
  options.family = family;
  options.n = n;
  options.aspect = aspect;
  return options;
}

TEST(GeneratorsFamily, NamesRoundTrip) {
  for (MeshFamily family :
       {MeshFamily::Patch48, MeshFamily::Stripe, MeshFamily::Criss, MeshFamily::Delaunay}) {
    EXPECT_EQ(parseMeshFamily(meshFamilyName(family)), family);
  }
  EXPECT_EQ(meshFamilyName(MeshFamily::Patch48), "patch48");
  EXPECT_EQ(meshFamilyName(MeshFamily::Delaunay), "delaunay");
}

TEST(GeneratorsFamily, UnknownNameListsTheFamilies) {
  try {
    parseMeshFamily("patch84");
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'patch84'"), std::string::npos) << message;
    for (const char* name : {"patch48", "stripe", "criss", "delaunay"}) {
      EXPECT_NE(message.find(name), std::string::npos) << message;
    }
  }
}

TEST(GeneratorsPatch48, CountsAndPositions) {
  for (int n : {1, 2, 5, 8}) {
    const Mesh mesh = generateMesh(optionsFor(MeshFamily::Patch48, n));
    ASSERT_EQ(mesh.vertexCount(), (n + 1) * (n + 1));
    ASSERT_EQ(mesh.faceCount(), 2 * n * n);
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const int v = j * (n + 1) + i;
        EXPECT_DOUBLE_EQ(mesh.positions(v, 0), -0.5 + static_cast<double>(i) / n);
        EXPECT_DOUBLE_EQ(mesh.positions(v, 1), -0.5 + static_cast<double>(j) / n);
      }
    }
    expectValidSquareMesh(mesh);
  }
}

TEST(GeneratorsPatch48, InteriorValencesAreFourAndEight) {
  const int n = 8;
  const Mesh mesh = generateMesh(optionsFor(MeshFamily::Patch48, n));
  const std::vector<int> valence = valences(mesh);
  int eights = 0;
  int fours = 0;
  for (int j = 1; j < n; ++j) {
    for (int i = 1; i < n; ++i) {
      const int v = j * (n + 1) + i;
      EXPECT_EQ(valence[v], (i + j) % 2 == 0 ? 8 : 4) << "vertex (" << i << ", " << j << ")";
      eights += valence[v] == 8;
      fours += valence[v] == 4;
    }
  }
  EXPECT_EQ(eights, 25);  // of the 7 × 7 interior vertices, those with i + j even
  EXPECT_EQ(fours, 24);
}

TEST(GeneratorsPatch48, BoundaryValences) {
  // A boundary vertex with i + j even touches the diagonals of its cells: corners 3, sides 5;
  // with i + j odd: corners 2, sides 3.
  for (int n : {5, 8}) {
    const Mesh mesh = generateMesh(optionsFor(MeshFamily::Patch48, n));
    const std::vector<int> valence = valences(mesh);
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const bool sideX = i == 0 || i == n;
        const bool sideY = j == 0 || j == n;
        if (!sideX && !sideY) continue;
        const bool even = (i + j) % 2 == 0;
        const int expected = sideX && sideY ? (even ? 3 : 2) : (even ? 5 : 3);
        EXPECT_EQ(valence[j * (n + 1) + i], expected)
            << "n = " << n << ", vertex (" << i << ", " << j << ")";
      }
    }
  }
}

TEST(GeneratorsPatch48, FacesComeRowByRowWithAlternatingDiagonals) {
  const int n = 4;
  const Mesh mesh = generateMesh(optionsFor(MeshFamily::Patch48, n));
  // Cell (0, 0): lower-left → upper-right diagonal; cell (1, 0): lower-right → upper-left.
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 6));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 6, 5));
  EXPECT_EQ(mesh.triangles.row(2), Eigen::RowVector3i(1, 2, 6));
  EXPECT_EQ(mesh.triangles.row(3), Eigen::RowVector3i(2, 7, 6));
  // The first face of row j = 1 is cell (0, 1), odd.
  EXPECT_EQ(mesh.triangles.row(2 * n), Eigen::RowVector3i(5, 6, 10));
}

TEST(GeneratorsPatch48, AspectMakesRectangularCells) {
  const Mesh mesh = generateMesh(optionsFor(MeshFamily::Patch48, 4, 0.5));
  EXPECT_EQ(mesh.vertexCount(), 5 * 9);
  EXPECT_EQ(mesh.faceCount(), 2 * 4 * 8);
  EXPECT_DOUBLE_EQ(mesh.positions(5, 1) - mesh.positions(0, 1), 0.125);
  expectValidSquareMesh(mesh);
}

TEST(GeneratorsStripe, CountsCellSizeAndValences) {
  const int n = 8;
  const Mesh mesh = generateMesh(optionsFor(MeshFamily::Stripe, n));
  const int rows = n / 2;
  ASSERT_EQ(mesh.vertexCount(), (n + 1) * (rows + 1));
  ASSERT_EQ(mesh.faceCount(), 2 * n * rows);
  // Cells of width 1/n and height 2/n.
  EXPECT_DOUBLE_EQ(mesh.positions(1, 0) - mesh.positions(0, 0), 1.0 / n);
  EXPECT_DOUBLE_EQ(mesh.positions(n + 1, 1) - mesh.positions(0, 1), 2.0 / n);
  EXPECT_DOUBLE_EQ(mesh.positions(mesh.vertexCount() - 1, 0), 0.5);
  EXPECT_DOUBLE_EQ(mesh.positions(mesh.vertexCount() - 1, 1), 0.5);
  const std::vector<int> valence = valences(mesh);
  for (int j = 1; j < rows; ++j) {
    for (int i = 1; i < n; ++i) {
      EXPECT_EQ(valence[j * (n + 1) + i], (i + j) % 2 == 0 ? 8 : 4);
    }
  }
  expectValidSquareMesh(mesh);
}

TEST(GeneratorsStripe, ExplicitAspect) {
  const Mesh mesh = generateMesh(optionsFor(MeshFamily::Stripe, 6, 3.0));
  EXPECT_EQ(mesh.vertexCount(), 7 * 3);
  expectValidSquareMesh(mesh);
}

TEST(GeneratorsCriss, SameDiagonalEverywhere) {
  const int n = 6;
  const Mesh mesh = generateMesh(optionsFor(MeshFamily::Criss, n));
  ASSERT_EQ(mesh.vertexCount(), (n + 1) * (n + 1));
  ASSERT_EQ(mesh.faceCount(), 2 * n * n);
  const std::vector<int> valence = valences(mesh);
  for (int j = 1; j < n; ++j) {
    for (int i = 1; i < n; ++i) EXPECT_EQ(valence[j * (n + 1) + i], 6);
  }
  // Every diagonal runs lower-left → upper-right: it joins (i, j) and (i + 1, j + 1).
  const std::set<Edge> edges = edgesOf(mesh);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int lowerLeft = j * (n + 1) + i;
      EXPECT_EQ(edges.count({lowerLeft, lowerLeft + n + 2}), 1u);
      EXPECT_EQ(edges.count({lowerLeft + 1, lowerLeft + n + 1}), 0u);
    }
  }
  expectValidSquareMesh(mesh);
}

TEST(GeneratorsCriss, WithAspect) {
  // aspect 3: cells 1/6 wide and 1/2 high; aspect 0.5: 1/4 wide, 1/8 high.
  const Mesh tall = generateMesh(optionsFor(MeshFamily::Criss, 6, 3.0));
  EXPECT_EQ(tall.vertexCount(), 7 * 3);
  EXPECT_EQ(tall.faceCount(), 2 * 6 * 2);
  EXPECT_DOUBLE_EQ(tall.positions(7, 1) - tall.positions(0, 1), 0.5);
  expectValidSquareMesh(tall);
  const Mesh flat = generateMesh(optionsFor(MeshFamily::Criss, 4, 0.5));
  EXPECT_EQ(flat.vertexCount(), 5 * 9);
  EXPECT_DOUBLE_EQ(flat.positions(5, 1) - flat.positions(0, 1), 0.125);
  expectValidSquareMesh(flat);
}

TEST(GeneratorsOptions, BadOptionsThrowHelpfulMessages) {
  EXPECT_EQ(inputErrorOf(optionsFor(MeshFamily::Criss, 8, 3.0)),
            "criss: GeneratorOptions.aspect 3 does not tile the square with n = 8 cells (8/3 is "
            "not a whole number)");
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Patch48, 8, 16.0)).find("8/16 is not a whole"),
            std::string::npos);
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Patch48, 0)).find("n must be at least 1, got 0"),
            std::string::npos);
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Delaunay, -3)).find("got -3"), std::string::npos);
  const std::string odd = inputErrorOf(optionsFor(MeshFamily::Stripe, 7));
  EXPECT_NE(odd.find("stripe: n = 7"), std::string::npos) << odd;
  EXPECT_NE(odd.find("even"), std::string::npos) << odd;
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Criss, 4, -1.0)).find("positive"),
            std::string::npos);
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Criss, 4, std::nan(""))).find("positive"),
            std::string::npos);
  const std::string delaunay = inputErrorOf(optionsFor(MeshFamily::Delaunay, 4, 1.0));
  EXPECT_NE(delaunay.find("delaunay: GeneratorOptions.aspect"), std::string::npos) << delaunay;
  EXPECT_THROW(refinementSequence(optionsFor(MeshFamily::Patch48, 4), 0), InputError);
}

TEST(GeneratorsOptions, ValidateRefusesWhatGenerateRefusesAndNothingElse) {
  for (const MeshFamily family :
       {MeshFamily::Patch48, MeshFamily::Stripe, MeshFamily::Criss, MeshFamily::Delaunay}) {
    EXPECT_NO_THROW(optionsFor(family, 8).validate()) << meshFamilyName(family);
    EXPECT_THROW(optionsFor(family, 0).validate(), InputError) << meshFamilyName(family);
  }
  EXPECT_THROW(optionsFor(MeshFamily::Stripe, 7).validate(), InputError);
  EXPECT_THROW(optionsFor(MeshFamily::Criss, 8, 3.0).validate(), InputError);
  EXPECT_THROW(optionsFor(MeshFamily::Criss, 4, -1.0).validate(), InputError);
  EXPECT_THROW(optionsFor(MeshFamily::Delaunay, 4, 1.0).validate(), InputError);
  EXPECT_NO_THROW(optionsFor(MeshFamily::Criss, 8, 4.0).validate());
}

TEST(GeneratorsRefinement, SequenceDoublesN) {
  const std::vector<Mesh> meshes = refinementSequence(optionsFor(MeshFamily::Patch48, 2), 3);
  ASSERT_EQ(meshes.size(), 3u);
  for (int level = 0; level < 3; ++level) {
    const int n = 2 << level;
    EXPECT_EQ(meshes[level].vertexCount(), (n + 1) * (n + 1));
    EXPECT_EQ(meshes[level].faceCount(), 2 * n * n);
  }
  const std::vector<Mesh> criss = refinementSequence(optionsFor(MeshFamily::Criss, 3, 3.0), 2);
  EXPECT_EQ(criss[0].vertexCount(), 4 * 2);
  EXPECT_EQ(criss[1].vertexCount(), 7 * 3);

  GeneratorOptions delaunay = optionsFor(MeshFamily::Delaunay, 4);
  delaunay.seed = 7;
  const std::vector<Mesh> irregular = refinementSequence(delaunay, 2);
  const Mesh direct = delaunayMesh(8, 7);
  EXPECT_EQ(irregular[1].positions, direct.positions);
  EXPECT_EQ(irregular[1].triangles, direct.triangles);
}

TEST(GeneratorsAllFamilies, ValidForSeveralSizes) {
  for (int n : {2, 4, 6, 16}) {
    for (MeshFamily family :
         {MeshFamily::Patch48, MeshFamily::Stripe, MeshFamily::Criss, MeshFamily::Delaunay}) {
      SCOPED_TRACE(std::string(meshFamilyName(family)) + " n = " + std::to_string(n));
      expectValidSquareMesh(generateMesh(optionsFor(family, n)));
    }
  }
}

TEST(DelaunayMesh, BoundaryVerticesExactlyOnTheSides) {
  for (int n : {1, 3, 8, 32}) {
    const Mesh mesh = delaunayMesh(n, 1);
    std::vector<double> bottom, right, top, left;
    for (int v = 0; v < mesh.vertexCount(); ++v) {
      const double x = mesh.positions(v, 0);
      const double y = mesh.positions(v, 1);
      if (y == -0.5) bottom.push_back(x);
      if (x == 0.5) right.push_back(y);
      if (y == 0.5) top.push_back(x);
      if (x == -0.5) left.push_back(y);
      if (!onBoundary(mesh, v)) {
        // Interior points keep away from the sides.
        EXPECT_GT(0.5 - std::max(std::abs(x), std::abs(y)), 0.5 / n);
      }
    }
    int boundaryCount = 0;
    for (int v = 0; v < mesh.vertexCount(); ++v) boundaryCount += onBoundary(mesh, v);
    EXPECT_EQ(boundaryCount, 4 * n);
    for (std::vector<double>* side : {&bottom, &right, &top, &left}) {
      ASSERT_EQ(side->size(), static_cast<std::size_t>(n + 1));  // corners on two sides
      std::sort(side->begin(), side->end());
      for (int k = 0; k <= n; ++k) {
        EXPECT_NEAR((*side)[k], -0.5 + static_cast<double>(k) / n, 1e-15);
      }
    }
    expectValidSquareMesh(mesh);
  }
}

TEST(DelaunayMesh, EdgeLengthAndAngles) {
  for (int n : {8, 32, 128}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const Mesh mesh = delaunayMesh(n, seed);
      const double mean = meanEdgeLength(mesh) * n;
      EXPECT_GE(mean, 0.8) << "n = " << n << " seed = " << seed;
      EXPECT_LE(mean, 1.2) << "n = " << n << " seed = " << seed;
      EXPECT_GT(minAngleDegrees(mesh), 20.0) << "n = " << n << " seed = " << seed;
    }
  }
}

TEST(DelaunayMesh, DeterministicForASeed) {
  const Mesh first = delaunayMesh(16, 42);
  const Mesh second = delaunayMesh(16, 42);
  ASSERT_EQ(first.vertexCount(), second.vertexCount());
  EXPECT_EQ(first.positions, second.positions);  // bit for bit
  EXPECT_EQ(first.triangles, second.triangles);
  GeneratorOptions options = optionsFor(MeshFamily::Delaunay, 16);
  options.seed = 42;
  EXPECT_EQ(generateMesh(options).positions, first.positions);
}

TEST(DelaunayMesh, SeedsGiveDifferentMeshes) {
  const Mesh a = delaunayMesh(16, 1);
  const Mesh b = delaunayMesh(16, 2);
  const bool samePositions = a.vertexCount() == b.vertexCount() && a.positions == b.positions;
  EXPECT_FALSE(samePositions);
}

TEST(DelaunayMesh, EmptyCircumcircles) {
  EXPECT_EQ(circumcircleViolations(delaunayMesh(6, 5)), 0);
  EXPECT_EQ(circumcircleViolations(delaunayMesh(3, 9)), 0);

  // The check itself sees a bad diagonal: the long edge of a thin rhombus.
  Mesh rhombus;
  rhombus.positions.resize(4, 3);
  rhombus.positions << -1, 0, 0, 1, 0, 0, 0, 0.1, 0, 0, -0.1, 0;
  rhombus.triangles.resize(2, 3);
  rhombus.triangles << 0, 1, 2, 1, 0, 3;
  EXPECT_EQ(circumcircleViolations(rhombus), 2);
}

}  // namespace
}  // namespace flexure::modeling

// ---- shells: cylinder, sphere, hemisphere --------------------------------------------------

namespace flexure::modeling {
namespace {

Eigen::Vector3d vertexOf(const Mesh& mesh, int f, int k) {
  return mesh.positions.row(mesh.triangles(f, k)).transpose();
}

double surfaceArea(const Mesh& mesh) {
  double area = 0.0;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = vertexOf(mesh, f, 0);
    area += 0.5 * (vertexOf(mesh, f, 1) - a).cross(vertexOf(mesh, f, 2) - a).norm();
  }
  return area;
}

// The enclosed volume by the divergence theorem, Σ_T x0 · (x1 × x2) / 6 (closed meshes).
double enclosedVolume(const Mesh& mesh) {
  double volume = 0.0;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    volume += vertexOf(mesh, f, 0).dot(vertexOf(mesh, f, 1).cross(vertexOf(mesh, f, 2))) / 6.0;
  }
  return volume;
}

// Connected loops of boundary edges (edges with one face).
int boundaryLoops(const Mesh& mesh) {
  std::map<Edge, int> uses;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(f, k);
      const int b = mesh.triangles(f, (k + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::vector<int> parent(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) parent[v] = v;
  const auto root = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::set<int> onBoundary;
  for (const auto& [edge, count] : uses) {
    if (count != 1) continue;
    parent[root(edge.first)] = root(edge.second);
    onBoundary.insert(edge.first);
    onBoundary.insert(edge.second);
  }
  std::set<int> loops;
  for (int v : onBoundary) loops.insert(root(v));
  return static_cast<int>(loops.size());
}

double minAngleDegrees3d(const Mesh& mesh) {
  double smallest = 180.0;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = vertexOf(mesh, f, k);
      const Eigen::Vector3d u = vertexOf(mesh, f, (k + 1) % 3) - a;
      const Eigen::Vector3d w = vertexOf(mesh, f, (k + 2) % 3) - a;
      smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / kPi);
    }
  }
  return smallest;
}

// Every face normal points away from `axis` through the origin (zero axis: from the origin).
void expectOutward(const Mesh& mesh, const Eigen::Vector3d& axis) {
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = vertexOf(mesh, f, 0);
    const Eigen::Vector3d normal = (vertexOf(mesh, f, 1) - a).cross(vertexOf(mesh, f, 2) - a);
    Eigen::Vector3d centre = (a + vertexOf(mesh, f, 1) + vertexOf(mesh, f, 2)) / 3.0;
    centre -= axis * axis.dot(centre);
    ASSERT_GT(normal.dot(centre), 0.0) << "face " << f;
  }
}

Mesh shell(MeshFamily family, int n, std::optional<double> aspect = std::nullopt) {
  GeneratorOptions options;
  options.family = family;
  options.n = n;
  options.aspect = aspect;
  return generateMesh(options);
}

int eulerCharacteristic(const Mesh& mesh) {
  return mesh.vertexCount() - static_cast<int>(edgesOf(mesh).size()) + mesh.faceCount();
}

TEST(GeneratorsShells, NamesRoundTrip) {
  for (MeshFamily family : {MeshFamily::Cylinder, MeshFamily::Sphere, MeshFamily::Hemisphere}) {
    EXPECT_EQ(parseMeshFamily(meshFamilyName(family)), family);
  }
}

TEST(GeneratorsShells, SphereIsClosedOutwardAndConvergesToTheBall) {
  double previousError = 0.0;
  for (int n : {4, 8, 16, 32, 64}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const Mesh mesh = shell(MeshFamily::Sphere, n);
    EXPECT_TRUE(checkMesh(mesh).valid());
    EXPECT_EQ(boundaryLoops(mesh), 0);
    EXPECT_EQ(eulerCharacteristic(mesh), 2);
    expectOutward(mesh, Eigen::Vector3d::Zero());
    for (int v = 0; v < mesh.vertexCount(); ++v) {
      EXPECT_NEAR(mesh.positions.row(v).norm(), 0.5, 1e-15);
    }
    // Inscribed: area and volume below π r²·4 = π and 4π r³/3 = π/6, by O(1/n²).
    const double areaError = 1.0 - surfaceArea(mesh) / kPi;
    const double volumeError = 1.0 - enclosedVolume(mesh) / (kPi / 6.0);
    EXPECT_GT(areaError, 0.0);
    EXPECT_GT(volumeError, 0.0);
    EXPECT_LT(areaError * n * n, 10.5);
    EXPECT_LT(volumeError * n * n, 19.5);
    if (n >= 16) {
      EXPECT_NEAR(areaError / previousError, 0.25, 0.05);
    }
    previousError = areaError;
    if (n >= 8) {
      EXPECT_GT(minAngleDegrees3d(mesh), 30.0);
    }
  }
}

TEST(GeneratorsShells, HemisphereHasOneBoundaryLoopOnTheEquator) {
  for (int n : {4, 8, 16, 32, 64}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const Mesh mesh = shell(MeshFamily::Hemisphere, n);
    EXPECT_TRUE(checkMesh(mesh).valid());
    EXPECT_EQ(boundaryLoops(mesh), 1);
    EXPECT_EQ(eulerCharacteristic(mesh), 1);
    expectOutward(mesh, Eigen::Vector3d::Zero());
    EXPECT_GE(mesh.positions.col(2).minCoeff(), 0.0);
    int onEquator = 0;
    for (int v = 0; v < mesh.vertexCount(); ++v) onEquator += mesh.positions(v, 2) == 0.0 ? 1 : 0;
    EXPECT_EQ(onEquator, n);
    const double areaError = 1.0 - surfaceArea(mesh) / (kPi / 2.0);
    EXPECT_GT(areaError, 0.0);
    EXPECT_LT(areaError * n * n, 10.5);
    if (n >= 8) {
      EXPECT_GT(minAngleDegrees3d(mesh), 30.0);
    }
  }
}

TEST(GeneratorsShells, CylinderIsAnOpenTubeWithTwoBoundaryLoops) {
  for (int n : {3, 8, 16, 64}) {
    for (double length : {1.0, 3.0}) {
      SCOPED_TRACE("n = " + std::to_string(n) + " length " + std::to_string(length));
      const Mesh mesh = shell(MeshFamily::Cylinder, n, length);
      EXPECT_TRUE(checkMesh(mesh).valid());
      EXPECT_EQ(boundaryLoops(mesh), 2);
      EXPECT_EQ(eulerCharacteristic(mesh), 0);
      expectOutward(mesh, Eigen::Vector3d::UnitZ());
      EXPECT_DOUBLE_EQ(mesh.positions.col(2).maxCoeff(), 0.5 * length);
      EXPECT_DOUBLE_EQ(mesh.positions.col(2).minCoeff(), -0.5 * length);
      // Every triangle has a ring edge, the chord c = 2r sin(π/n), and its apex on the next ring
      // half a step round: at height Δz above the chord and r (1 − cos(π/n)) out from it.
      const double r = 0.5;
      const double rings = std::round(length / (std::sqrt(3.0) / 2.0 * kPi / n));
      const double dz = length / std::max(rings, 1.0);
      const double chord = 2.0 * r * std::sin(kPi / n);
      const double apexHeight = std::hypot(dz, r * (1.0 - std::cos(kPi / n)));
      EXPECT_EQ(mesh.faceCount(), 2 * n * static_cast<int>(std::max(rings, 1.0)));
      const double exact = mesh.faceCount() * 0.5 * chord * apexHeight;
      EXPECT_NEAR(surfaceArea(mesh), exact, 1e-12 * exact);
      // ... which tends to the tube's 2π r L = π L.
      if (n == 64) {
        EXPECT_NEAR(surfaceArea(mesh) / (kPi * length), 1.0, 2e-3);
      }
      if (n >= 8) {
        EXPECT_GT(minAngleDegrees3d(mesh), 50.0);
      }
    }
  }
}

TEST(GeneratorsShells, PlateProblemsRefuseShells) {
  EXPECT_EQ(parsePlateFamily("delaunay"), MeshFamily::Delaunay);
  try {
    parsePlateFamily("sphere");
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("'sphere' is a shell"), std::string::npos);
  }
  EXPECT_THROW(parsePlateFamily("cylinder"), InputError);
  EXPECT_THROW(parsePlateFamily("nonsense"), InputError);
}

TEST(GeneratorsShells, BadShellOptionsThrowHelpfulMessages) {
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Sphere, 6)).find("multiple of 4"),
            std::string::npos);
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Hemisphere, 4, 1.0)).find("does not apply"),
            std::string::npos);
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Cylinder, 2)).find("at least 3"),
            std::string::npos);
  EXPECT_NE(inputErrorOf(optionsFor(MeshFamily::Cylinder, 8, -1.0)).find("positive"),
            std::string::npos);
}

}  // namespace
}  // namespace flexure::modeling
