#include "modeling/mesh_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>
#include <tuple>

#include <Eigen/Geometry>

#include "modeling/errors.h"

namespace flexure::modeling {
namespace {

constexpr int kKindCount = static_cast<int>(MeshProblemKind::AreaOverflow) + 1;

// A face is degenerate when |(x1 − x0) × (x2 − x0)| ≤ kZeroArea · (longest edge)², i.e. its
// smallest height is below ~1e-12 of its longest edge: scale-free, and far below any mesh a
// bending energy can use (the energies divide by Ā_T).
constexpr double kZeroArea = 1e-12;

std::string faceElement(const Mesh& mesh, int f) {
  const auto t = mesh.triangles.row(f);
  return "face " + std::to_string(f) + " (vertices " + std::to_string(t(0)) + ", " +
         std::to_string(t(1)) + ", " + std::to_string(t(2)) + ")";
}

std::string edgeElement(int a, int b) {
  return "edge (" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

std::string listOf(const std::vector<int>& ids) {
  std::string s;
  for (size_t i = 0; i < ids.size(); ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  return s;
}

class ProblemCollector {
 public:
  explicit ProblemCollector(int maxPerKind) : maxPerKind_(maxPerKind) {
    check_.problemCounts.assign(kKindCount, 0);
  }
  void add(MeshProblemKind kind, std::string element, std::string reason) {
    int& count = check_.problemCounts[static_cast<int>(kind)];
    if (count++ < maxPerKind_)
      check_.problems.push_back({kind, std::move(element), std::move(reason)});
  }
  int count(MeshProblemKind kind) const { return check_.problemCounts[static_cast<int>(kind)]; }
  MeshCheck take() { return std::move(check_); }

 private:
  int maxPerKind_;
  MeshCheck check_;
};

// Minimal union-find over face corners (3f + i), for counting the fans around each vertex.
class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void unite(int a, int b) { parent_[find(a)] = find(b); }

 private:
  std::vector<int> parent_;
};

void checkVertices(const Mesh& mesh, ProblemCollector& out) {
  static const char* axis[] = {"x", "y", "z"};
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    for (int c = 0; c < 3; ++c) {
      const double value = mesh.positions(v, c);
      if (!std::isfinite(value)) {
        out.add(MeshProblemKind::NonFiniteCoordinate, "vertex " + std::to_string(v),
                std::string("coordinate ") + axis[c] + " is " +
                    (std::isnan(value) ? "NaN" : "infinite"));
        break;
      }
    }
  }
}

// Returns whether every face has three distinct in-range vertices (the later checks need it).
bool checkFaceIndices(const Mesh& mesh, ProblemCollector& out) {
  bool usable = true;
  const int nv = mesh.vertexCount();
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    if (t.minCoeff() < 0 || t.maxCoeff() >= nv) {
      out.add(MeshProblemKind::VertexIndexOutOfRange, faceElement(mesh, f),
              "refers to a vertex outside 0.." + std::to_string(nv - 1));
      usable = false;
    } else if (t(0) == t(1) || t(1) == t(2) || t(2) == t(0)) {
      out.add(MeshProblemKind::RepeatedVertexInFace, faceElement(mesh, f),
              "uses the same vertex twice (a degenerate triangle)");
      usable = false;
    }
  }
  return usable;
}

void checkAreas(const Mesh& mesh, ProblemCollector& out) {
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    const Eigen::Vector3d x0 = mesh.positions.row(t(0)), x1 = mesh.positions.row(t(1)),
                          x2 = mesh.positions.row(t(2));
    if (!x0.allFinite() || !x1.allFinite() || !x2.allFinite()) continue;
    const double twiceArea = (x1 - x0).cross(x2 - x0).norm();
    const double longest =
        std::max({(x1 - x0).squaredNorm(), (x2 - x1).squaredNorm(), (x0 - x2).squaredNorm()});
    if (!std::isfinite(twiceArea) || !std::isfinite(longest)) {
      std::ostringstream reason;
      reason << "its area or edge lengths overflow double precision (coordinates up to "
             << std::max(
                    {x0.cwiseAbs().maxCoeff(), x1.cwiseAbs().maxCoeff(), x2.cwiseAbs().maxCoeff()})
             << "); scale the mesh down";
      out.add(MeshProblemKind::AreaOverflow, faceElement(mesh, f), reason.str());
      continue;
    }
    if (!(twiceArea > kZeroArea * longest)) {
      std::ostringstream reason;
      reason << "has zero area (" << 0.5 * twiceArea << "; its vertices are collinear or coincide)";
      out.add(MeshProblemKind::ZeroAreaFace, faceElement(mesh, f), reason.str());
    }
  }
}

void checkReferences(const Mesh& mesh, ProblemCollector& out) {
  std::vector<char> used(mesh.vertexCount(), 0);
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) used[mesh.triangles(f, i)] = 1;
  for (int v = 0; v < mesh.vertexCount(); ++v)
    if (!used[v])
      out.add(MeshProblemKind::UnreferencedVertex, "vertex " + std::to_string(v),
              "is used by no face");
}

// Returns, per face, whether it repeats an earlier face's vertex set.
std::vector<char> checkDuplicates(const Mesh& mesh, ProblemCollector& out) {
  std::vector<std::pair<std::array<int, 3>, int>> keyed(mesh.faceCount());
  for (int f = 0; f < mesh.faceCount(); ++f) {
    std::array<int, 3> key = {mesh.triangles(f, 0), mesh.triangles(f, 1), mesh.triangles(f, 2)};
    std::sort(key.begin(), key.end());
    keyed[f] = {key, f};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<char> duplicate(mesh.faceCount(), 0);
  for (size_t k = 1; k < keyed.size(); ++k) {
    if (keyed[k].first != keyed[k - 1].first) continue;
    duplicate[keyed[k].second] = 1;
    const auto& key = keyed[k].first;
    out.add(
        MeshProblemKind::DuplicateFace,
        "faces " + std::to_string(keyed[k - 1].second) + " and " + std::to_string(keyed[k].second),
        "use the same vertices (" + listOf({key[0], key[1], key[2]}) + ")");
  }
  return duplicate;
}

struct HalfEdgeRecord {
  int lower, higher;  // the undirected edge
  bool forward;       // the face traverses it lower → higher
  int face, corner;   // edge `corner` of `face` (opposite vertex `corner`)
  bool operator<(const HalfEdgeRecord& o) const {
    return std::tie(lower, higher, face) < std::tie(o.lower, o.higher, o.face);
  }
};

// Non-manifold edges, inconsistent orientation, and non-manifold ("bowtie") vertices: the faces
// around a vertex must form one fan, joined across the vertex's manifold edges.
void checkManifold(const Mesh& mesh, const std::vector<char>& duplicate, ProblemCollector& out) {
  const int nf = mesh.faceCount();
  std::vector<HalfEdgeRecord> records;
  records.reserve(3 * nf);
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      const int a = mesh.triangles(f, (i + 1) % 3), b = mesh.triangles(f, (i + 2) % 3);
      records.push_back({std::min(a, b), std::max(a, b), a < b, f, i});
    }
  }
  std::sort(records.begin(), records.end());

  DisjointSets corners(3 * nf);
  const auto cornerOf = [&](int f, int v) {
    for (int i = 0; i < 3; ++i)
      if (mesh.triangles(f, i) == v) return 3 * f + i;
    return -1;
  };
  for (size_t begin = 0; begin < records.size();) {
    size_t end = begin + 1;
    while (end < records.size() && records[end].lower == records[begin].lower &&
           records[end].higher == records[begin].higher)
      ++end;
    const HalfEdgeRecord& r = records[begin];
    if (end - begin > 2) {
      std::vector<int> faces;
      for (size_t k = begin; k < end; ++k) faces.push_back(records[k].face);
      out.add(MeshProblemKind::NonManifoldEdge, edgeElement(r.lower, r.higher),
              "is shared by " + std::to_string(faces.size()) + " faces (" + listOf(faces) +
                  "); a manifold edge has one or two");
    } else if (end - begin == 2) {
      const HalfEdgeRecord& s = records[begin + 1];
      if (r.forward == s.forward && !duplicate[r.face] && !duplicate[s.face]) {
        out.add(MeshProblemKind::InconsistentOrientation,
                "faces " + std::to_string(r.face) + " and " + std::to_string(s.face),
                "both traverse " + edgeElement(r.lower, r.higher) +
                    " in the same direction: their orientations disagree");
      }
      for (int v : {r.lower, r.higher}) corners.unite(cornerOf(r.face, v), cornerOf(s.face, v));
    }
    begin = end;
  }

  std::vector<int> fanRoot(mesh.vertexCount(), -1), fans(mesh.vertexCount(), 0);
  for (int c = 0; c < 3 * nf; ++c) {
    const int v = mesh.triangles(c / 3, c % 3);
    const int root = corners.find(c);
    if (fanRoot[v] == -1) {
      fanRoot[v] = root;
      fans[v] = 1;
    } else if (fanRoot[v] != root) {
      // A new fan of v: merge it into the first so it is counted once. Corner sets only ever
      // hold corners of one vertex, so this cannot disturb another vertex's count.
      corners.unite(root, fanRoot[v]);
      ++fans[v];
    }
  }
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    if (fans[v] > 1) {
      out.add(MeshProblemKind::NonManifoldVertex, "vertex " + std::to_string(v),
              "its faces form " + std::to_string(fans[v]) +
                  " separate fans (a non-manifold vertex, e.g. two surfaces touching at a point)");
    }
  }
}

}  // namespace

int MeshCheck::totalProblems() const {
  return std::accumulate(problemCounts.begin(), problemCounts.end(), 0);
}

std::string_view meshProblemName(MeshProblemKind kind) {
  switch (kind) {
    case MeshProblemKind::Empty:
      return "empty";
    case MeshProblemKind::VertexIndexOutOfRange:
      return "vertex_index_out_of_range";
    case MeshProblemKind::NonFiniteCoordinate:
      return "non_finite_coordinate";
    case MeshProblemKind::RepeatedVertexInFace:
      return "repeated_vertex_in_face";
    case MeshProblemKind::ZeroAreaFace:
      return "zero_area_face";
    case MeshProblemKind::UnreferencedVertex:
      return "unreferenced_vertex";
    case MeshProblemKind::DuplicateFace:
      return "duplicate_face";
    case MeshProblemKind::NonManifoldEdge:
      return "non_manifold_edge";
    case MeshProblemKind::InconsistentOrientation:
      return "inconsistent_orientation";
    case MeshProblemKind::NonManifoldVertex:
      return "non_manifold_vertex";
    case MeshProblemKind::AreaOverflow:
      return "area_overflow";
  }
  return "unknown";
}

MeshCheck checkMesh(const Mesh& mesh, int maxPerKind) {
  ProblemCollector out(maxPerKind);
  if (mesh.faceCount() == 0) {
    out.add(MeshProblemKind::Empty, "mesh",
            "has no faces (" + std::to_string(mesh.vertexCount()) + " vertices)");
    return out.take();
  }
  checkVertices(mesh, out);
  if (!checkFaceIndices(mesh, out)) return out.take();
  checkAreas(mesh, out);
  checkReferences(mesh, out);
  const std::vector<char> duplicate = checkDuplicates(mesh, out);
  checkManifold(mesh, duplicate, out);
  return out.take();
}

void requireValidMesh(const Mesh& mesh, std::string_view source) {
  const MeshCheck check = checkMesh(mesh, 3);
  if (check.valid()) return;
  std::string message;
  for (const MeshProblem& p : check.problems) {
    if (!message.empty()) message += '\n';
    message += std::string(source) + ": " + p.element + ": " + p.reason;
  }
  const int more = check.totalProblems() - static_cast<int>(check.problems.size());
  if (more > 0) {
    message += "\n" + std::string(source) + ": ... and " + std::to_string(more) +
               (more == 1 ? " more problem" : " more problems") + " (flexure info " +
               std::string(source) + " lists them by kind)";
  }
  throw InputError(message);
}

}  // namespace flexure::modeling
