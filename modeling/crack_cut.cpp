#include "modeling/crack_cut.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include "modeling/errors.h"
#include "modeling/mesh_info.h"

namespace flexure::modeling {

namespace {

Eigen::Vector3d rowOf(const Positions& x, int v) {
  return x.row(v).transpose();
}

// A point of the crack: a vertex, or the point (1 − t) x_a + t x_b of edge (a, b).
struct CrackPoint {
  int vertex = -1;
  int a = -1;
  int b = -1;
  double t = 0.0;
  bool tip = false;  // the crack stops here inside the mesh: it must become a vertex

  bool onEdge() const { return vertex < 0; }
  bool onEdge(int p, int q) const { return onEdge() && ((a == p && b == q) || (a == q && b == p)); }
  bool sameAs(const CrackPoint& other) const {
    if (!onEdge()) return !other.onEdge() && other.vertex == vertex;
    return other.onEdge(a, b);
  }
};

// The exact crack: points P_0 … P_N and the faces F_0 … F_{N−1}, segment k in face F_k.
struct CrackPath {
  std::vector<CrackPoint> points;
  std::vector<int> faces;
};

// The faces of the rest mesh around each directed edge.
class EdgeFaces {
 public:
  explicit EdgeFaces(const Mesh& mesh) : vertexCount_(mesh.vertexCount()) {
    for (int f = 0; f < mesh.faceCount(); ++f) {
      for (int s = 0; s < 3; ++s) {
        faceOf_[key(mesh.triangles(f, s), mesh.triangles(f, (s + 1) % 3))] = f;
      }
    }
    boundaryVertex_.assign(mesh.vertexCount(), false);
    facesAround_.resize(mesh.vertexCount());
    for (int f = 0; f < mesh.faceCount(); ++f) {
      for (int s = 0; s < 3; ++s) {
        const int a = mesh.triangles(f, s);
        const int b = mesh.triangles(f, (s + 1) % 3);
        if (face(b, a) < 0) boundaryVertex_[a] = boundaryVertex_[b] = true;
        facesAround_[a].push_back(f);
      }
    }
  }
  // Whether v is on the boundary (an edge of it has a face on one side only): after a cut, the
  // crack's lips and its tip too.
  bool onBoundary(int v) const { return boundaryVertex_[v]; }
  const std::vector<int>& facesAround(int v) const { return facesAround_[v]; }
  // The face with the directed edge a → b, −1 when none.
  int face(int a, int b) const {
    const auto found = faceOf_.find(key(a, b));
    return found == faceOf_.end() ? -1 : found->second;
  }

 private:
  std::int64_t key(int a, int b) const { return static_cast<std::int64_t>(a) * vertexCount_ + b; }
  std::int64_t vertexCount_;
  std::unordered_map<std::int64_t, int> faceOf_;
  std::vector<bool> boundaryVertex_;
  std::vector<std::vector<int>> facesAround_;
};

struct Exit {
  int side = -1;  // the face's side s: corner s → corner s + 1
  double t = 0.0;
  Eigen::Vector3d point;
};

// Where the line p + σ d (σ > 0) leaves face f, not through side `entrySide`.
Exit exitOfFace(const Mesh& mesh, int f, const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                int entrySide) {
  const Eigen::Vector3d x0 = rowOf(mesh.positions, mesh.triangles(f, 0));
  const Eigen::Vector3d normal = (rowOf(mesh.positions, mesh.triangles(f, 1)) - x0)
                                     .cross(rowOf(mesh.positions, mesh.triangles(f, 2)) - x0);
  Exit best;
  double bestSigma = std::numeric_limits<double>::infinity();
  for (int s = 0; s < 3; ++s) {
    if (s == entrySide) continue;
    const Eigen::Vector3d q0 = rowOf(mesh.positions, mesh.triangles(f, s));
    const Eigen::Vector3d edge = rowOf(mesh.positions, mesh.triangles(f, (s + 1) % 3)) - q0;
    // p + σ d = q0 + t edge, solved in the face's plane: cross with the normal n.
    const double denominator = normal.dot(d.cross(edge));
    if (std::abs(denominator) < 1e-300) continue;
    const Eigen::Vector3d offset = q0 - p;
    const double sigma = normal.dot(offset.cross(edge)) / denominator;
    const double t = normal.dot(offset.cross(d)) / denominator;
    if (sigma <= 1e-12 * edge.norm() || t < -1e-9 || t > 1.0 + 1e-9) continue;
    if (sigma < bestSigma) {
      bestSigma = sigma;
      best = Exit{s, std::clamp(t, 0.0, 1.0), q0 + std::clamp(t, 0.0, 1.0) * edge};
    }
  }
  return best;
}

// d unfolded across edge a → b from its face into the face g: the same components along the edge
// and across it (into g).
Eigen::Vector3d unfold(const Mesh& mesh, const Eigen::Vector3d& d, int a, int b, int g) {
  const Eigen::Vector3d xa = rowOf(mesh.positions, a);
  const Eigen::Vector3d along = (rowOf(mesh.positions, b) - xa).normalized();
  int opposite = 0;
  for (int k = 0; k < 3; ++k) {
    if (mesh.triangles(g, k) != a && mesh.triangles(g, k) != b) opposite = mesh.triangles(g, k);
  }
  Eigen::Vector3d across = rowOf(mesh.positions, opposite) - xa;
  across -= across.dot(along) * along;
  const double acrossComponent = (d - d.dot(along) * along).norm();
  return d.dot(along) * along + acrossComponent * across.normalized();
}

// The face around vertex w (other than `from`) that the line from w along d enters: the one whose
// side opposite w it crosses; d projected into that face's plane. −1 when none.
int faceEnteredAt(const Mesh& mesh, const EdgeFaces& edgeFaces, int w, int from,
                  Eigen::Vector3d& d) {
  const Eigen::Vector3d xw = rowOf(mesh.positions, w);
  for (const int g : edgeFaces.facesAround(w)) {
    if (g == from) continue;
    int corner = 0;
    while (mesh.triangles(g, corner) != w) ++corner;
    const Eigen::Vector3d x1 = rowOf(mesh.positions, mesh.triangles(g, (corner + 1) % 3));
    const Eigen::Vector3d x2 = rowOf(mesh.positions, mesh.triangles(g, (corner + 2) % 3));
    const Eigen::Vector3d normal = (x1 - xw).cross(x2 - xw).normalized();
    const Eigen::Vector3d inPlane = (d - d.dot(normal) * normal).normalized();
    const Exit exit = exitOfFace(mesh, g, xw, inPlane, -1);
    if (exit.side == (corner + 1) % 3) {
      d = inPlane;
      return g;
    }
  }
  return -1;
}

// Marches from face `start`'s point p along d: the crossings and the faces entered after `start`.
void march(const Mesh& mesh, const EdgeFaces& edgeFaces, const std::vector<bool>& cracking,
           int start, Eigen::Vector3d p, Eigen::Vector3d d, std::vector<bool>& visited,
           std::vector<CrackPoint>& points, std::vector<int>& faces) {
  int face = start;
  int entrySide = -1;
  for (;;) {
    const Exit exit = exitOfFace(mesh, face, p, d, entrySide);
    if (exit.side < 0) {  // degenerate: stop at the nearest vertex of the face
      CrackPoint end;
      end.a = mesh.triangles(face, 0);
      end.b = mesh.triangles(face, 1);
      end.tip = true;
      points.push_back(end);
      return;
    }
    const int a = mesh.triangles(face, exit.side);
    const int b = mesh.triangles(face, (exit.side + 1) % 3);
    if (exit.t < 1e-9 || exit.t > 1.0 - 1e-9) {  // through a vertex: on into the face beyond it
      const int w = exit.t < 0.5 ? a : b;
      points.push_back(CrackPoint{w, -1, -1, 0.0, false});
      const int next = edgeFaces.onBoundary(w) ? -1 : faceEnteredAt(mesh, edgeFaces, w, face, d);
      if (next < 0 || !cracking[next] || visited[next]) return;
      faces.push_back(next);
      visited[next] = true;
      p = exit.point;
      face = next;
      entrySide = -1;
      continue;
    }
    CrackPoint crossing{-1, a, b, exit.t, false};
    const int next = edgeFaces.face(b, a);
    if (next < 0) {  // the boundary
      points.push_back(crossing);
      return;
    }
    // Not cracking, or the crack reaches a boundary vertex (an earlier crack's tip or lip, or the
    // outer boundary): it ends at the nearer end of the edge.
    const bool reachesBoundary = edgeFaces.onBoundary(exit.t < 0.5 ? a : b);
    if (!cracking[next] || visited[next] || reachesBoundary) {
      crossing.tip = true;
      points.push_back(crossing);
      return;
    }
    points.push_back(crossing);
    faces.push_back(next);
    visited[next] = true;
    d = unfold(mesh, d, a, b, next);
    p = exit.point;
    face = next;
    for (int s = 0; s < 3; ++s) {
      if (mesh.triangles(face, s) == b && mesh.triangles(face, (s + 1) % 3) == a) entrySide = s;
    }
  }
}

CrackPath exactCrack(const Mesh& mesh, const EdgeFaces& edgeFaces, const CrackSeed& seed,
                     const std::vector<bool>& cracking) {
  const Eigen::Vector3d centroid = (rowOf(mesh.positions, mesh.triangles(seed.face, 0)) +
                                    rowOf(mesh.positions, mesh.triangles(seed.face, 1)) +
                                    rowOf(mesh.positions, mesh.triangles(seed.face, 2))) /
                                   3.0;
  std::vector<CrackPoint> forward, backward;
  std::vector<int> forwardFaces, backwardFaces;
  // One record of the faces crossed for both ways: a crack that comes round a closed surface
  // stops before a face the other way crossed (each face is split once).
  std::vector<bool> visited(mesh.faceCount(), false);
  if (seed.tipVertex >= 0) {  // grown from the tip along the direction, into the face ahead
    Eigen::Vector3d d = seed.direction;
    const int first = faceEnteredAt(mesh, edgeFaces, seed.tipVertex, -1, d);
    if (first >= 0) {
      visited[first] = true;
      CrackPath path;
      path.points.push_back(CrackPoint{seed.tipVertex, -1, -1, 0.0, false});
      path.faces.push_back(first);
      march(mesh, edgeFaces, cracking, first, rowOf(mesh.positions, seed.tipVertex), d, visited,
            path.points, path.faces);
      return path;
    }
  }
  visited[seed.face] = true;
  march(mesh, edgeFaces, cracking, seed.face, centroid, seed.direction, visited, forward,
        forwardFaces);
  march(mesh, edgeFaces, cracking, seed.face, centroid, -seed.direction, visited, backward,
        backwardFaces);
  CrackPath path;
  path.points.assign(backward.rbegin(), backward.rend());
  path.points.insert(path.points.end(), forward.begin(), forward.end());
  path.faces.assign(backwardFaces.rbegin(), backwardFaces.rend());
  path.faces.push_back(seed.face);
  path.faces.insert(path.faces.end(), forwardFaces.begin(), forwardFaces.end());
  return path;
}

void snapToVertex(CrackPoint& point, int vertex) {
  point = CrackPoint{vertex, -1, -1, 0.0, false};
}

// Vertex budging: crossings within `budge` of an edge end and crack tips move to the nearer end;
// an edge point whose segment would run to an end of its own edge moves to that end; repeated
// points merge (their face is not split).
CrackPath budge(CrackPath path, double budge) {
  for (CrackPoint& point : path.points) {
    if (!point.onEdge()) continue;
    if (point.tip || point.t < budge || point.t > 1.0 - budge) {
      snapToVertex(point, point.t < 0.5 ? point.a : point.b);
    }
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k + 1 < path.points.size(); ++k) {
      CrackPoint& p = path.points[k];
      CrackPoint& q = path.points[k + 1];
      if (p.onEdge() && !q.onEdge() && (q.vertex == p.a || q.vertex == p.b)) {
        snapToVertex(p, q.vertex);
        changed = true;
      } else if (q.onEdge() && !p.onEdge() && (p.vertex == q.a || p.vertex == q.b)) {
        snapToVertex(q, p.vertex);
        changed = true;
      }
    }
  }
  CrackPath merged;
  merged.points.push_back(path.points.front());
  for (std::size_t k = 0; k < path.faces.size(); ++k) {
    if (path.points[k + 1].sameAs(merged.points.back())) continue;
    merged.faces.push_back(path.faces[k]);
    merged.points.push_back(path.points[k + 1]);
  }
  return merged;
}

double smallestAngleDegrees(const Positions& x, const std::array<int, 3>& face) {
  return modeling::smallestAngleDegrees(x, face[0], face[1], face[2]);
}

// Triangles of the convex polygon `polygon` (counter-clockwise): itself, or a quadrilateral split
// by the diagonal whose triangles have the larger smallest angle.
std::vector<std::array<int, 3>> triangulate(const std::vector<int>& polygon, const Positions& x) {
  if (polygon.size() == 3) return {{polygon[0], polygon[1], polygon[2]}};
  const std::array<int, 3> a0{polygon[0], polygon[1], polygon[2]};
  const std::array<int, 3> a1{polygon[0], polygon[2], polygon[3]};
  const std::array<int, 3> b0{polygon[1], polygon[2], polygon[3]};
  const std::array<int, 3> b1{polygon[1], polygon[3], polygon[0]};
  const double a = std::min(smallestAngleDegrees(x, a0), smallestAngleDegrees(x, a1));
  const double b = std::min(smallestAngleDegrees(x, b0), smallestAngleDegrees(x, b1));
  if (a >= b) return {a0, a1};
  return {b0, b1};
}

// The cut mesh before the sides separate: faces split along the crack.
struct SplitMesh {
  Mesh rest;
  Positions current;
  std::vector<VertexSource> sources;
  std::vector<int> faceOrigin;
  std::vector<int> crackVertices;
  double smallestNewAngle = 180.0;
  int facesSplit = 0;
  int verticesAdded = 0;
};

int addCrossingVertex(const CrackPoint& point, SplitMesh& split,
                      std::map<std::pair<int, int>, int>& vertexOfEdge) {
  if (!point.onEdge()) return point.vertex;
  const std::pair<int, int> edge{std::min(point.a, point.b), std::max(point.a, point.b)};
  const auto found = vertexOfEdge.find(edge);
  if (found != vertexOfEdge.end()) return found->second;
  const int vertex = static_cast<int>(split.sources.size());
  split.sources.push_back(VertexSource{point.a, point.b, point.t});
  vertexOfEdge[edge] = vertex;
  ++split.verticesAdded;
  return vertex;
}

SplitMesh splitAlong(const Mesh& rest, const Positions& current, const CrackPath& path) {
  SplitMesh split;
  for (int v = 0; v < rest.vertexCount(); ++v) split.sources.push_back(VertexSource{v, v, 0.0});
  std::map<std::pair<int, int>, int> vertexOfEdge;
  for (const CrackPoint& point : path.points) {
    split.crackVertices.push_back(addCrossingVertex(point, split, vertexOfEdge));
  }
  const int vertexCount = static_cast<int>(split.sources.size());
  split.rest.positions.resize(vertexCount, 3);
  split.current.resize(vertexCount, 3);
  for (int v = 0; v < vertexCount; ++v) {
    const VertexSource& s = split.sources[v];
    split.rest.positions.row(v) =
        (1.0 - s.t) * rest.positions.row(s.a) + s.t * rest.positions.row(s.b);
    split.current.row(v) = (1.0 - s.t) * current.row(s.a) + s.t * current.row(s.b);
  }

  std::vector<std::vector<std::array<int, 3>>> replacement(rest.faceCount());
  for (std::size_t k = 0; k < path.faces.size(); ++k) {
    const CrackPoint& p = path.points[k];
    const CrackPoint& q = path.points[k + 1];
    if (!p.onEdge() && !q.onEdge()) continue;  // along an edge of the face
    const int f = path.faces[k];
    std::vector<int> polygon;
    int atP = -1;
    int atQ = -1;
    for (int s = 0; s < 3; ++s) {
      const int c0 = rest.triangles(f, s);
      const int c1 = rest.triangles(f, (s + 1) % 3);
      if (!p.onEdge() && p.vertex == c0) atP = static_cast<int>(polygon.size());
      if (!q.onEdge() && q.vertex == c0) atQ = static_cast<int>(polygon.size());
      polygon.push_back(c0);
      if (p.onEdge(c0, c1)) {
        atP = static_cast<int>(polygon.size());
        polygon.push_back(split.crackVertices[k]);
      }
      if (q.onEdge(c0, c1)) {
        atQ = static_cast<int>(polygon.size());
        polygon.push_back(split.crackVertices[k + 1]);
      }
    }
    const int n = static_cast<int>(polygon.size());
    for (const auto& [from, to] : {std::pair{atP, atQ}, std::pair{atQ, atP}}) {
      std::vector<int> part;
      for (int i = from;; i = (i + 1) % n) {
        part.push_back(polygon[i]);
        if (i == to) break;
      }
      for (const auto& triangle : triangulate(part, split.rest.positions)) {
        replacement[f].push_back(triangle);
        split.smallestNewAngle =
            std::min(split.smallestNewAngle, smallestAngleDegrees(split.rest.positions, triangle));
      }
    }
    ++split.facesSplit;
  }

  std::vector<std::array<int, 3>> faces;
  for (int f = 0; f < rest.faceCount(); ++f) {
    if (replacement[f].empty()) {
      faces.push_back({rest.triangles(f, 0), rest.triangles(f, 1), rest.triangles(f, 2)});
      split.faceOrigin.push_back(f);
      continue;
    }
    for (const auto& triangle : replacement[f]) {
      faces.push_back(triangle);
      split.faceOrigin.push_back(f);
    }
  }
  split.rest.triangles.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    split.rest.triangles.row(f) << faces[f][0], faces[f][1], faces[f][2];
  }
  return split;
}

// Union–find over face corners (3 f + k).
struct CornerSets {
  std::vector<int> parent;
  explicit CornerSets(int corners) : parent(corners) { std::iota(parent.begin(), parent.end(), 0); }
  int root(int c) {
    while (parent[c] != c) c = parent[c] = parent[parent[c]];
    return c;
  }
  void join(int a, int b) { parent[root(a)] = root(b); }
};

// Duplicates the crack's vertices: the corners of a vertex joined across edges off the crack share
// one copy; each further group of corners gets a new vertex. Returns the number of copies.
int separateSides(SplitMesh& split) {
  Mesh& mesh = split.rest;
  std::map<std::pair<int, int>, int> crackEdges;
  for (std::size_t k = 0; k + 1 < split.crackVertices.size(); ++k) {
    const int a = split.crackVertices[k];
    const int b = split.crackVertices[k + 1];
    crackEdges[{std::min(a, b), std::max(a, b)}] = 1;
  }
  std::map<std::pair<int, int>, std::vector<int>> cornersOfEdge;  // undirected edge ↦ 3 f + s
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int s = 0; s < 3; ++s) {
      const int a = mesh.triangles(f, s);
      const int b = mesh.triangles(f, (s + 1) % 3);
      cornersOfEdge[{std::min(a, b), std::max(a, b)}].push_back(3 * f + s);
    }
  }
  CornerSets sets(3 * mesh.faceCount());
  for (const auto& [edge, sides] : cornersOfEdge) {
    if (sides.size() != 2 || crackEdges.count(edge) > 0) continue;
    // Side s of face f runs corner s → s + 1; across it the other face runs the other way.
    const int f = sides[0] / 3, s = sides[0] % 3;
    const int g = sides[1] / 3, r = sides[1] % 3;
    sets.join(3 * f + s, 3 * g + (r + 1) % 3);
    sets.join(3 * f + (s + 1) % 3, 3 * g + r);
  }
  std::vector<int> firstRoot(mesh.vertexCount(), -1);
  std::map<int, int> vertexOfRoot;
  const int before = mesh.vertexCount();
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      const int root = sets.root(3 * f + k);
      if (firstRoot[v] < 0) firstRoot[v] = root;
      if (root == firstRoot[v]) continue;
      auto [entry, added] = vertexOfRoot.try_emplace(root, static_cast<int>(split.sources.size()));
      if (added) split.sources.push_back(split.sources[v]);
      mesh.triangles(f, k) = entry->second;
    }
  }
  const int after = static_cast<int>(split.sources.size());
  mesh.positions.conservativeResize(after, 3);
  split.current.conservativeResize(after, 3);
  for (int v = before; v < after; ++v) {
    // A copy of vertex w < before: find it through the source it copied.
    const VertexSource& s = split.sources[v];
    mesh.positions.row(v) = (1.0 - s.t) * mesh.positions.row(s.a) + s.t * mesh.positions.row(s.b);
    split.current.row(v) = (1.0 - s.t) * split.current.row(s.a) + s.t * split.current.row(s.b);
  }
  return after - before;
}

void requireUsableSeed(const Mesh& rest, const Positions& current, const CrackSeed& seed,
                       const std::vector<bool>& cracking) {
  if (seed.face < 0 || seed.face >= rest.faceCount()) {
    throw InputError("crack cut: seed face " + std::to_string(seed.face) +
                     " is not a face (the mesh has " + std::to_string(rest.faceCount()) + ")");
  }
  if (current.rows() != rest.vertexCount() ||
      static_cast<int>(cracking.size()) != rest.faceCount()) {
    throw InputError("crack cut: the configuration or the cracking flags do not match the mesh (" +
                     std::to_string(rest.vertexCount()) + " vertices, " +
                     std::to_string(rest.faceCount()) + " faces)");
  }
  const Eigen::Vector3d x0 = rowOf(rest.positions, rest.triangles(seed.face, 0));
  const Eigen::Vector3d normal =
      (rowOf(rest.positions, rest.triangles(seed.face, 1)) - x0)
          .cross(rowOf(rest.positions, rest.triangles(seed.face, 2)) - x0)
          .normalized();
  const double length = seed.direction.norm();
  if (seed.tipVertex >= 0 && (rest.triangles.row(seed.face).array() != seed.tipVertex).all()) {
    throw InputError("crack cut: tip vertex " + std::to_string(seed.tipVertex) +
                     " is not a corner of seed face " + std::to_string(seed.face));
  }
  if (!(length > 0.0) || std::abs(normal.dot(seed.direction)) > 1e-6 * length) {
    throw InputError(
        "crack cut: the direction of the crack must be a nonzero vector in the plane "
        "of seed face " +
        std::to_string(seed.face));
  }
}

}  // namespace

CrackCut cutAlongCrack(const Mesh& rest, const Positions& current, const CrackSeed& seed,
                       const std::vector<bool>& cracking, const CrackCutOptions& options) {
  requireUsableSeed(rest, current, seed, cracking);
  const EdgeFaces edgeFaces(rest);
  CrackSeed unitSeed = seed;
  unitSeed.direction.normalize();
  const CrackPath exact = exactCrack(rest, edgeFaces, unitSeed, cracking);
  for (double budgeFraction = options.initialBudge;; budgeFraction += 0.05) {
    budgeFraction = std::min(budgeFraction, 0.5);
    const CrackPath path = budge(exact, budgeFraction);
    SplitMesh split = splitAlong(rest, current, path);
    if (split.smallestNewAngle < options.minAngleDegrees && budgeFraction < 0.5) continue;
    CrackCut cut;
    cut.budge = budgeFraction;
    cut.facesSplit = split.facesSplit;
    cut.verticesAdded = split.verticesAdded;
    cut.crackVertices = split.crackVertices;
    cut.crackRest.resize(static_cast<int>(split.crackVertices.size()), 3);
    cut.crackCurrent.resize(static_cast<int>(split.crackVertices.size()), 3);
    for (int k = 0; k < static_cast<int>(split.crackVertices.size()); ++k) {
      cut.crackRest.row(k) = split.rest.positions.row(split.crackVertices[k]);
      cut.crackCurrent.row(k) = split.current.row(split.crackVertices[k]);
    }
    cut.verticesDuplicated = separateSides(split);
    cut.rest = std::move(split.rest);
    cut.current = std::move(split.current);
    cut.sources = std::move(split.sources);
    cut.faceOrigin = std::move(split.faceOrigin);
    return cut;
  }
}

}  // namespace flexure::modeling
