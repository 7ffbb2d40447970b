// The vibration modes of a viewer page (reports/viewer_modes.h): the nodal lines of known plate
// modes where theory puts them, every nodal point on a mesh edge whose ends change sign (or at a
// vertex where the normal displacement vanishes), and a modes folder read back into the page.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/vertex_quantities.h"
#include "optimize/modes/vibration_modes.h"
#include "render/viewer_page.h"
#include "reports/viewer_modes.h"

namespace flexure {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Square {
  modeling::Mesh mesh;
  modeling::Stencils stencils;
  modeling::RestState rest;
  explicit Square(int n) {
    modeling::GeneratorOptions g;
    g.family = modeling::MeshFamily::Patch48;
    g.n = n;
    mesh = modeling::generateMesh(g);  // [−½, ½]², z = 0
    stencils = modeling::compileStencils(mesh);
    rest = modeling::precomputeRestState(stencils, mesh.positions);
  }
  // The simply supported square's mode (a, b): z = sin aπx sin bπy on [0, 1]².
  modeling::Positions mode(int a, int b) const {
    modeling::Positions shape = modeling::Positions::Zero(mesh.vertexCount(), 3);
    for (int v = 0; v < mesh.vertexCount(); ++v) {
      const double x = mesh.positions(v, 0) + 0.5, y = mesh.positions(v, 1) + 0.5;
      shape(v, 2) = std::sin(a * kPi * x) * std::sin(b * kPi * y);
    }
    return shape;
  }
  Eigen::Vector3d at(const render::ViewerLinePoint& p) const {
    return ((1.0 - p.t) * mesh.positions.row(p.a) + p.t * mesh.positions.row(p.b)).transpose();
  }
};

// The (1,2) mode sin πx sin 2πy has the straight nodal line y = ½ across the square, (2,1) the
// line x = ½, and (1,1) none inside (its zero set is the held boundary). An odd n puts no grid
// line on the nodal line: every point is interpolated inside an edge.
TEST(ViewerModes, NodalLinesOfKnownPlateModesLieWhereTheoryPutsThem) {
  const int n = 15;
  const Square square(n);
  EXPECT_TRUE(square.mode(1, 1).allFinite());
  EXPECT_EQ(reports::viewerMode(square.stencils, square.rest, square.mode(1, 1), "(1,1)")
                .nodalLines.size(),
            0u);
  for (const auto& [a, b, across] :
       {std::tuple{1, 2, 1}, std::tuple{2, 1, 0}}) {  // across: the coordinate that is 0 on it
    const render::ViewerMode mode =
        reports::viewerMode(square.stencils, square.rest, square.mode(a, b), "mode");
    ASSERT_GE(mode.nodalLines.size(), static_cast<size_t>(n));
    double length = 0.0, farthest = 0.0;
    for (const auto& [p, q] : mode.nodalLines) {
      const Eigen::Vector3d x = square.at(p), y = square.at(q);
      length += (y - x).norm();
      for (const Eigen::Vector3d& point : {x, y})
        if (point.cwiseAbs().maxCoeff() < 0.5 - 2.0 / n)  // inside: off the held boundary
          farthest = std::max(farthest, std::abs(point(across)));
    }
    // The whole line across the unit square, a little longer where it zigzags across the
    // diagonals (patch48 n = 15: 1.000 and 1.027).
    EXPECT_GE(length, 0.99) << "mode (" << a << "," << b << ")";
    EXPECT_LE(length, 1.05) << "mode (" << a << "," << b << ")";
    EXPECT_LE(farthest, 0.1 / n) << "mode (" << a << "," << b << ")";
  }
}

// Every point of a nodal line lies on an edge of the mesh whose ends have opposite normal
// displacements (t inside (0, 1), where the linear interpolant vanishes), or at a vertex with
// none; on a generic mode, the diagonal (1,2) + (2,1) on a Delaunay plate.
TEST(ViewerModes, NodalPointsLieOnEdgesWithASignChange) {
  modeling::GeneratorOptions g;
  g.family = modeling::MeshFamily::Delaunay;
  g.n = 12;
  const modeling::Mesh mesh = modeling::generateMesh(g);
  const modeling::Stencils stencils = modeling::compileStencils(mesh);
  const modeling::RestState rest = modeling::precomputeRestState(stencils, mesh.positions);
  modeling::Positions shape = modeling::Positions::Zero(mesh.vertexCount(), 3);
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const double x = mesh.positions(v, 0) + 0.5, y = mesh.positions(v, 1) + 0.5;
    shape(v, 2) = std::sin(kPi * x) * std::sin(kPi * y) * (std::cos(kPi * x) + std::cos(kPi * y));
  }
  const Eigen::MatrixX3d normals = modeling::vertexNormals(mesh.positions, stencils.faces);
  const Eigen::VectorXd s = (shape.array() * normals.array()).rowwise().sum();
  const double floor = optimize::kNodalFloor * s.cwiseAbs().maxCoeff();
  std::set<std::pair<int, int>> edges;
  for (int f = 0; f < stencils.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) {
      const int a = stencils.faces(f, i), b = stencils.faces(f, (i + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  const render::ViewerMode mode = reports::viewerMode(stencils, rest, shape, "diagonal");
  ASSERT_GT(mode.nodalLines.size(), 10u);
  for (const auto& [p, q] : mode.nodalLines)
    for (const render::ViewerLinePoint& point : {p, q}) {
      if (point.a == point.b) {
        EXPECT_LE(std::abs(s[point.a]), floor) << "vertex " << point.a;
        continue;
      }
      EXPECT_TRUE(edges.count({std::min(point.a, point.b), std::max(point.a, point.b)}))
          << point.a << "-" << point.b << " is no edge";
      EXPECT_LT(s[point.a] * s[point.b], 0.0) << point.a << "-" << point.b;
      EXPECT_GT(point.t, 0.0);
      EXPECT_LT(point.t, 1.0);
      // The linear interpolant of s vanishes there.
      EXPECT_NEAR((1.0 - point.t) * s[point.a] + point.t * s[point.b], 0.0,
                  1e-12 * s.cwiseAbs().maxCoeff());
    }
}

// A folder as `flexure modes` writes it (modes.json, rest.obj, the shapes): its modes, φ the shape
// minus the rest; without the rest mesh, an InputError naming the file.
TEST(ViewerModes, ReadsAModesFolder) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(FLEXURE_TEST_TMP) / "viewer_modes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Square square(8);
  modeling::Mesh shaped = square.mesh;
  shaped.positions += 0.1 * square.mode(2, 1);
  modeling::writeMesh((dir / "mode-midedge-1.obj").string(), shaped);
  std::ofstream(dir / "modes.json")
      << R"({"rest": "rest.obj", "energies": [{"energy": "midedge", "modes": [)"
      << R"({"kind": "rigid", "lambda": 0}, {"kind": "flexible", "index": 1, "lambda": 49.35,)"
      << R"( "omega": 12.5, "multiplicity": 2, "shape": "mode-midedge-1.obj"}]}]})";
  EXPECT_TRUE(reports::isModesFolder(dir.string()));
  try {
    reports::readModesFolder(dir.string(), render::ViewerStyle::Reflection);
    ADD_FAILURE() << "no rest mesh, but read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "rest.obj").string()), std::string::npos)
        << e.what();
  }
  modeling::writeMesh((dir / "rest.obj").string(), square.mesh);
  try {
    reports::readModesFolder(dir.string(), render::ViewerStyle::Field);
    ADD_FAILURE() << "a modes folder read for a field";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.string() + ": a modes folder is drawn in the"),
              std::string::npos)
        << e.what();
  }
  const std::vector<render::ViewerMesh> meshes =
      reports::readModesFolder(dir.string(), render::ViewerStyle::Shaded);
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].name, "midedge");
  ASSERT_EQ(meshes[0].modes.size(), 1u);
  EXPECT_EQ(meshes[0].modes[0].label, "mode 1: λ = 49.35, ω = 12.5 (×2)");
  EXPECT_LE((meshes[0].modes[0].shape - 0.1 * square.mode(2, 1)).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_GE(meshes[0].modes[0].nodalLines.size(), 8u);
}

// A cut's face change: valid from a later frame whose vertices the faces name; refused (naming
// the field) at frame 0, out of order, or naming a vertex the frame does not have.
TEST(ViewerPage, FaceChangesAreCheckedAgainstTheirFrames) {
  const Square square(4);
  render::ViewerPageSpec page;
  render::ViewerMesh m;
  m.triangles = square.mesh.triangles;
  m.frames = {square.mesh.positions, square.mesh.positions};
  modeling::Positions grown(square.mesh.vertexCount() + 1, 3);
  grown << square.mesh.positions, square.mesh.positions.row(0);
  m.frames.push_back(grown);
  modeling::Triangles cut = square.mesh.triangles;
  cut(0, 0) = square.mesh.vertexCount();  // the appended vertex
  m.faceChanges.push_back({2, cut});
  page.meshes = {m};
  EXPECT_NO_THROW(page.validate());
  EXPECT_EQ(page.meshes[0].trianglesAt(1)(0, 0), square.mesh.triangles(0, 0));
  EXPECT_EQ(page.meshes[0].trianglesAt(2)(0, 0), square.mesh.vertexCount());
  const auto refused = [&](render::ViewerMesh bad, const std::string& field) {
    page.meshes = {bad};
    try {
      page.validate();
      ADD_FAILURE() << "accepted; expected a refusal naming " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  render::ViewerMesh atZero = m;
  atZero.faceChanges[0].frame = 0;
  refused(atZero, "meshes[0].faceChanges");
  render::ViewerMesh early = m;
  early.faceChanges[0].frame = 1;  // frame 1 has no vertex #V
  refused(early, "meshes[0].triangles");
  render::ViewerMesh grownWithoutCut = m;
  grownWithoutCut.faceChanges.clear();
  refused(grownWithoutCut, "meshes[0].frames");
  render::ViewerMesh cracks = m;
  cracks.frameCracks = {{}, {}};
  refused(cracks, "meshes[0].frameCracks");
}

}  // namespace
}  // namespace flexure
