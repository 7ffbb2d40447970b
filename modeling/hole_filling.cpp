#include "modeling/hole_filling.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <string>

#include "modeling/cgal_surface_mesh.h"
#include "modeling/errors.h"
#include "modeling/mesh_check.h"

namespace flexure::modeling {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Halfedge = CgalSurfaceMesh::Halfedge_index;
using Face = CgalSurfaceMesh::Face_index;
using Vertex = CgalSurfaceMesh::Vertex_index;

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d point(const CgalSurfaceMesh& sm, Vertex v) {
  const auto& p = sm.point(v);
  return {p.x(), p.y(), p.z()};
}

// (x1 − x0) × (x2 − x0) of a triangle: its normal times twice its area.
Eigen::Vector3d areaNormal(const CgalSurfaceMesh& sm, Face f) {
  Eigen::Vector3d x[3];
  int i = 0;
  for (const Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) x[i++] = point(sm, v);
  return (x[1] - x[0]).cross(x[2] - x[0]);
}

double longestSquaredEdge(const CgalSurfaceMesh& sm, Face f) {
  double longest = 0.0;
  for (const Halfedge h : CGAL::halfedges_around_face(sm.halfedge(f), sm))
    longest = std::max(longest, (point(sm, sm.target(h)) - point(sm, sm.source(h))).squaredNorm());
  return longest;
}

// Why the fill made of `faces` is not clean (hole_filling.h), or "" when it is. `inputVertices`:
// vertices below it are the input's and are named by their index.
std::string uncleanFill(const CgalSurfaceMesh& sm, const std::vector<Face>& faces,
                        int inputVertices) {
  const auto name = [&](Vertex v) {
    return static_cast<int>(v) < inputVertices ? std::to_string(static_cast<int>(v))
                                               : std::string("new");
  };
  const double foldCosine = std::cos(kCleanFillFoldDegrees * kPi / 180.0);
  for (const Face f : faces) {
    const Eigen::Vector3d n = areaNormal(sm, f);
    if (!(n.norm() > kCleanFillFlatness * longestSquaredEdge(sm, f))) {
      std::ostringstream s;
      s << "CGAL's fill has a face of zero area (vertices";
      const char* separator = " ";
      for (const Vertex v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
        s << separator << name(v);
        separator = ", ";
      }
      s << ")";
      return s.str();
    }
    for (const Halfedge h : CGAL::halfedges_around_face(sm.halfedge(f), sm)) {
      const Face g = sm.face(sm.opposite(h));
      if (g == CgalSurfaceMesh::null_face()) continue;
      const Eigen::Vector3d m = areaNormal(sm, g);
      const double cosine = n.dot(m) / (n.norm() * m.norm());
      if (cosine < foldCosine) {
        std::ostringstream s;
        s << "CGAL's fill folds over at edge (" << name(sm.source(h)) << ", " << name(sm.target(h))
          << "): the faces on its two sides turn by " << std::fixed << std::setprecision(1)
          << std::acos(std::max(-1.0, cosine)) * 180.0 / kPi << "° (more than "
          << std::setprecision(0) << kCleanFillFoldDegrees << "°)";
        return s.str();
      }
    }
  }
  return "";
}

int smallestVertex(const CgalSurfaceMesh& sm, Halfedge loop) {
  int smallest = static_cast<int>(sm.target(loop));
  for (const Halfedge h : CGAL::halfedges_around_face(loop, sm))
    smallest = std::min(smallest, static_cast<int>(sm.target(h)));
  return smallest;
}

int loopLength(const CgalSurfaceMesh& sm, Halfedge loop) {
  int edges = 0;
  for (const Halfedge h : CGAL::halfedges_around_face(loop, sm)) {
    (void)h;
    ++edges;
  }
  return edges;
}

// Why the loop at `loop` is pinched, or "" when it is not: two of its distinct vertices lie within
// kPinchedLoopDistance of its mean edge length of each other, so the loop passes twice through
// one point (two holes touching there, or a slit over coincident vertices). CGAL fills the two
// lobes as one patch whose triangles join them across the point and fold there
// (elephant-with-holes' loop of 15 edges at vertex 1531 through the coincident 2552 and 2738: a
// fold of 126° that no fairing of its one new vertex undoes).
std::string pinchedLoop(const CgalSurfaceMesh& sm, Halfedge loop) {
  std::vector<Vertex> vertices;
  double perimeter = 0.0;
  for (const Halfedge h : CGAL::halfedges_around_face(loop, sm)) {
    vertices.push_back(sm.target(h));
    perimeter += (point(sm, sm.target(h)) - point(sm, sm.source(h))).norm();
  }
  const double tolerance = kPinchedLoopDistance * perimeter / static_cast<double>(vertices.size());
  for (std::size_t a = 0; a < vertices.size(); ++a) {
    for (std::size_t b = a + 1; b < vertices.size(); ++b) {
      if (vertices[a] != vertices[b] &&
          (point(sm, vertices[a]) - point(sm, vertices[b])).norm() <= tolerance) {
        const int first = std::min(static_cast<int>(vertices[a]), static_cast<int>(vertices[b]));
        const int second = std::max(static_cast<int>(vertices[a]), static_cast<int>(vertices[b]));
        return "the loop passes twice through one point (vertices " + std::to_string(first) +
               " and " + std::to_string(second) +
               " coincide): CGAL's fill would join its two sides across it";
      }
    }
  }
  return "";
}

// Fills the loop at `loop`: the new faces and vertices, and why the fill is not clean ("" when
// it is): uncleanFill's reason, else pinchedLoop's (a pinched loop's fill is not clean either).
struct LoopFill {
  std::vector<Face> faces;
  std::vector<Vertex> vertices;
  std::string problem;
};

LoopFill fillLoop(CgalSurfaceMesh& sm, Halfedge loop, int inputVertices) {
  LoopFill fill;
  const std::string pinched = pinchedLoop(sm, loop);
  PMP::triangulate_and_refine_hole(sm, loop, std::back_inserter(fill.faces),
                                   std::back_inserter(fill.vertices));
  fill.problem = fill.faces.empty() ? std::string("CGAL could not triangulate it")
                                    : uncleanFill(sm, fill.faces, inputVertices);
  if (fill.problem.empty()) fill.problem = pinched;
  return fill;
}

}  // namespace

FilledMesh fillHoles(const Mesh& mesh, int maxBoundaryEdges) {
  CgalSurfaceMesh sm = toCgalSurfaceMesh(mesh, "fillHoles");
  std::vector<Halfedge> loops;  // one border halfedge per boundary cycle
  PMP::extract_boundary_cycles(sm, std::back_inserter(loops));

  // First every chosen loop is filled on a copy to see which fills are clean (the loops are
  // disjoint and a fill reads only its own loop, so a fill does not depend on the others); then
  // the clean ones are filled on the mesh itself. Surface_mesh keeps element indices on copy and
  // only appends, so the loops' halfedges name the same loops in both.
  FilledMesh filled;
  std::vector<std::size_t> clean;
  {
    CgalSurfaceMesh trial = sm;
    for (std::size_t i = 0; i < loops.size(); ++i) {
      const int edges = loopLength(sm, loops[i]);
      if (maxBoundaryEdges > 0 && edges > maxBoundaryEdges) {
        ++filled.loopsLeft;
        continue;
      }
      const LoopFill fill = fillLoop(trial, loops[i], mesh.vertexCount());
      if (fill.problem.empty()) {
        clean.push_back(i);
      } else {
        filled.skipped.push_back({edges, smallestVertex(sm, loops[i]), fill.problem});
      }
    }
  }
  for (const std::size_t i : clean) {
    FilledHole hole;
    hole.boundaryEdges = loopLength(sm, loops[i]);
    hole.loopVertex = smallestVertex(sm, loops[i]);
    const LoopFill fill = fillLoop(sm, loops[i], mesh.vertexCount());
    if (!fill.problem.empty()) {
      throw NumericalError("hole filling: the loop of " + std::to_string(hole.boundaryEdges) +
                           " edges at vertex " + std::to_string(hole.loopVertex) +
                           " filled cleanly alone but not among the others: " + fill.problem);
    }
    hole.newFaces = static_cast<int>(fill.faces.size());
    hole.newVertices = static_cast<int>(fill.vertices.size());
    filled.holes.push_back(hole);
  }
  filled.mesh = fromCgalSurfaceMesh(sm);
  filled.newVertex.assign(filled.mesh.vertexCount(), false);
  for (int v = mesh.vertexCount(); v < filled.mesh.vertexCount(); ++v) filled.newVertex[v] = true;

  const MeshCheck check = checkMesh(filled.mesh, 1);
  if (!check.valid()) {
    const MeshProblem& p = check.problems.front();
    throw NumericalError("hole filling: CGAL's patches do not make a valid mesh: " + p.element +
                         ": " + p.reason);
  }
  return filled;
}

}  // namespace flexure::modeling
