#include "modeling/fairing_region.h"

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>

#include "modeling/boundary_rings.h"
#include "modeling/errors.h"
#include "modeling/vertex_sets.h"

namespace flexure::modeling {
namespace {

std::vector<double> parseNumbers(const std::string& text, const std::string& spec) {
  std::vector<double> numbers;
  std::istringstream fields(text);
  std::string field;
  while (std::getline(fields, field, ',')) {
    double value = 0.0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (error != std::errc() || end != field.data() + field.size())
      throw InputError("region " + spec + ": '" + field + "' is not a number");
    numbers.push_back(value);
  }
  return numbers;
}

// The comma-separated fields of `text`, empty ones kept ("1," is {"1", ""}).
std::vector<std::string> splitFields(const std::string& text) {
  std::vector<std::string> fields(1);
  for (const char c : text) {
    if (c == ',')
      fields.emplace_back();
    else
      fields.back().push_back(c);
  }
  return fields;
}

// "around:VERTEX,R" or "rings:VERTEX,K": the vertex (an index in [0, #V)) and the second field
// parsed by `parseSecond`, which throws for a bad value. InputError quoting `spec` otherwise.
template <typename Second>
std::pair<int, Second> parseVertexAnd(
    const std::string& spec, const std::string& value, int vertexCount, const std::string& form,
    const std::function<Second(const std::string&)>& parseSecond) {
  const std::vector<std::string> fields = splitFields(value);
  if (fields.size() != 2 || fields[0].empty() || fields[1].empty())
    throw InputError("region " + spec + ": expected " + form);
  int vertex = 0;
  const std::string& v = fields[0];
  const auto [end, error] = std::from_chars(v.data(), v.data() + v.size(), vertex);
  if (error != std::errc() || end != v.data() + v.size())
    throw InputError("region " + spec + ": '" + v + "' is not a vertex index (expected " + form +
                     ")");
  if (vertex < 0 || vertex >= vertexCount) {
    throw InputError("region " + spec + ": vertex " + v + " is out of range: the mesh has " +
                     std::to_string(vertexCount) + " vertices (0 .. " +
                     std::to_string(vertexCount - 1) + ")");
  }
  return {vertex, parseSecond(fields[1])};
}

// The planar update of geodesicDistances: d_c through face (a, b, c) from d_a and d_b, or +∞ when
// the straight path from the unfolded source does not enter the face through ab.
double faceUpdate(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  double da, double db) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d e = b - a;
  const double length = e.norm();
  if (!(length > 0.0)) return kInfinity;
  const Eigen::Vector3d u = e / length;
  // The face in the plane: a = (0, 0), b = (L, 0), c = (cx, cy) with cy ≥ 0; the source
  // s = (sx, −sy) below ab, |s − a| = d_a, |s − b| = d_b.
  const double cx = (c - a).dot(u), cy = ((c - a) - cx * u).norm();
  const double sx = (da * da - db * db + length * length) / (2.0 * length);
  const double sy2 = da * da - sx * sx;
  if (!(sy2 >= 0.0) || !(cy > 0.0)) return kInfinity;  // d_a, d_b and L violate the triangle rule
  const double sy = std::sqrt(sy2);
  const double crossing = sx + sy / (sy + cy) * (cx - sx);  // where segment s c meets y = 0
  if (crossing < 0.0 || crossing > length) return kInfinity;
  return std::hypot(cx - sx, cy + sy);
}

}  // namespace

std::vector<bool> parseRegion(const std::string& spec, const Mesh& mesh, const Stencils& stencils) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon),
                    value = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (kind == "vertices" && !value.empty())
    return readVertexSet(value, mesh.vertexCount(), "region vertex list");
  if (kind == "sphere") {
    const std::vector<double> n = parseNumbers(value, spec);
    if (n.size() != 4 || !(n[3] > 0.0))
      throw InputError("region " + spec + ": expected sphere:x,y,z,r with r > 0");
    return verticesInSphere(mesh.positions, Eigen::Vector3d(n[0], n[1], n[2]), n[3]);
  }
  if (kind == "around") {
    const std::string form = "around:VERTEX,R (R > 0 mean edge lengths)";
    const auto [vertex, radius] =
        parseVertexAnd<double>(spec, value, mesh.vertexCount(), form, [&](const std::string& r) {
          double x = 0.0;
          const auto [end, error] = std::from_chars(r.data(), r.data() + r.size(), x);
          if (error != std::errc() || end != r.data() + r.size())
            throw InputError("region " + spec + ": R '" + r + "' is not a number (expected " +
                             form + ")");
          if (!(x > 0.0) || !std::isfinite(x))
            throw InputError("region " + spec + ": R = " + r + " must be a finite number > 0");
          return x;
        });
    const double reach = radius * meanEdgeLength(mesh, stencils);
    const std::vector<double> d = geodesicDistances(mesh, stencils, vertex, reach);
    std::vector<bool> region(mesh.vertexCount());
    for (int v = 0; v < mesh.vertexCount(); ++v) region[v] = d[v] <= reach;
    return region;
  }
  if (kind == "rings") {
    const std::string form = "rings:VERTEX,K (K >= 0 rings)";
    const auto [vertex, rings] =
        parseVertexAnd<int>(spec, value, mesh.vertexCount(), form, [&](const std::string& k) {
          int x = 0;
          const auto [end, error] = std::from_chars(k.data(), k.data() + k.size(), x);
          if (error != std::errc() || end != k.data() + k.size())
            throw InputError("region " + spec + ": K '" + k + "' is not a whole number (expected " +
                             form + ")");
          if (x < 0) throw InputError("region " + spec + ": K = " + k + " must be >= 0");
          return x;
        });
    std::vector<bool> seed(mesh.vertexCount(), false);
    seed[vertex] = true;
    const Eigen::VectorXi ring = ringDistances(stencils, seed, rings);
    std::vector<bool> region(mesh.vertexCount());
    for (int v = 0; v < mesh.vertexCount(); ++v) region[v] = ring[v] >= 0;
    return region;
  }
  if (spec == "all-interior") return interiorRegion(stencils);
  throw InputError("region " + spec +
                   ": expected vertices:FILE, sphere:x,y,z,r, around:VERTEX,R, rings:VERTEX,K, "
                   "all-interior or holes[:N]");
}

double meanEdgeLength(const Mesh& mesh, const Stencils& stencils) {
  double sum = 0.0;
  for (int e = 0; e < stencils.edgeCount(); ++e)
    sum += (mesh.positions.row(stencils.edges(e, 0)) - mesh.positions.row(stencils.edges(e, 1)))
               .norm();
  return stencils.edgeCount() > 0 ? sum / stencils.edgeCount() : 0.0;
}

std::vector<double> geodesicDistances(const Mesh& mesh, const Stencils& stencils, int source,
                                      double maxDistance) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const int n = mesh.vertexCount();
  // The faces around each vertex, CSR.
  std::vector<int> faceOffsets(n + 1, 0),
      vertexFaces(3 * static_cast<std::size_t>(mesh.faceCount()));
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) ++faceOffsets[mesh.triangles(f, k) + 1];
  for (int v = 0; v < n; ++v) faceOffsets[v + 1] += faceOffsets[v];
  std::vector<int> fill(faceOffsets.begin(), faceOffsets.end() - 1);
  for (int f = 0; f < mesh.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) vertexFaces[fill[mesh.triangles(f, k)]++] = f;

  const auto x = [&](int v) { return Eigen::Vector3d(mesh.positions.row(v).transpose()); };
  std::vector<double> d(n, kInfinity);
  std::vector<char> accepted(n, 0);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  const auto relax = [&](int v, double value) {
    if (value < d[v]) {
      d[v] = value;
      queue.push({value, v});
    }
  };
  relax(source, 0.0);
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (accepted[v] || dv > d[v]) continue;
    if (dv > maxDistance) break;
    accepted[v] = 1;
    for (int r = stencils.oneRingOffsets[v]; r < stencils.oneRingOffsets[v + 1]; ++r) {
      const int w = stencils.oneRingVertices[r];
      if (!accepted[w]) relax(w, dv + (x(w) - x(v)).norm());
    }
    for (int i = faceOffsets[v]; i < faceOffsets[v + 1]; ++i) {
      const auto t = mesh.triangles.row(vertexFaces[i]);
      const int k = t(0) == v ? 0 : t(1) == v ? 1 : 2;
      const int p = t((k + 1) % 3), q = t((k + 2) % 3);
      if (accepted[p] && !accepted[q]) relax(q, faceUpdate(x(v), x(p), x(q), dv, d[p]));
      if (accepted[q] && !accepted[p]) relax(p, faceUpdate(x(v), x(q), x(p), dv, d[q]));
    }
  }
  for (int v = 0; v < n; ++v)
    if (!accepted[v]) d[v] = kInfinity;
  return d;
}

std::vector<bool> interiorRegion(const Stencils& stencils, int heldRings) {
  if (!stencils.vertexOnBoundary.any()) {
    throw InputError(
        "the mesh is closed: all-interior would be every vertex and nothing would hold it; "
        "choose a region (vertices:FILE or sphere:x,y,z,r)");
  }
  const Eigen::VectorXi rings = vertexRings(stencils);
  std::vector<bool> region(stencils.vertexCount());
  for (int v = 0; v < stencils.vertexCount(); ++v)
    region[v] = rings[v] < 0 || rings[v] >= heldRings;
  return region;
}

void requireFairableRegion(const Stencils& stencils, const std::vector<bool>& region,
                           std::string_view regionName, int heldRings) {
  const std::string name(regionName);
  if (countVertices(region) == 0) throw InputError(name + ": the region selects no vertex");
  const Eigen::VectorXi fromBoundary = vertexRings(stencils);
  for (int v = 0; v < stencils.vertexCount(); ++v) {
    if (region[v] && fromBoundary[v] >= 0 && fromBoundary[v] < heldRings) {
      throw InputError(name + ": region vertex " + std::to_string(v) +
                       (fromBoundary[v] == 0 ? " is on the mesh boundary"
                                             : " is " + std::to_string(fromBoundary[v]) +
                                                   " ring from the mesh boundary") +
                       ": the " + std::to_string(heldRings) +
                       " held rings around the region need room; keep the region " +
                       std::to_string(heldRings) + " rings inside the boundary");
    }
  }
  const std::vector<int> component = vertexComponents(stencils);
  std::vector<char> held(stencils.vertexCount(), 0);  // per component: has a vertex outside R
  for (int v = 0; v < stencils.vertexCount(); ++v)
    if (!region[v]) held[component[v]] = 1;
  for (int v = 0; v < stencils.vertexCount(); ++v) {
    if (region[v] && !held[component[v]]) {
      throw InputError(name + ": the region covers the whole connected component of vertex " +
                       std::to_string(v) +
                       " (a closed surface): nothing is left to hold it in place");
    }
  }
}

Submesh extractSubmesh(const Mesh& mesh, const std::vector<bool>& keep) {
  Submesh sub;
  std::vector<int> patchVertex(mesh.vertexCount(), -1);
  std::vector<int> faces;
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.triangles.row(f);
    if (keep[t(0)] && keep[t(1)] && keep[t(2)]) {
      faces.push_back(f);
      for (int k = 0; k < 3; ++k) patchVertex[t(k)] = 0;
    }
  }
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    if (patchVertex[v] < 0) continue;
    patchVertex[v] = static_cast<int>(sub.inputVertex.size());
    sub.inputVertex.push_back(v);
  }
  sub.mesh.positions.resize(static_cast<Eigen::Index>(sub.inputVertex.size()), 3);
  for (std::size_t p = 0; p < sub.inputVertex.size(); ++p)
    sub.mesh.positions.row(static_cast<Eigen::Index>(p)) = mesh.positions.row(sub.inputVertex[p]);
  sub.mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      sub.mesh.triangles(static_cast<Eigen::Index>(i), k) =
          patchVertex[mesh.triangles(faces[i], k)];
  }
  return sub;
}

FairingPatch extractFairingPatch(const Mesh& mesh, const Stencils& stencils,
                                 const std::vector<bool>& region, int heldRings) {
  const Eigen::VectorXi rings = ringDistances(stencils, region, heldRings);
  std::vector<bool> keep(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) keep[v] = rings[v] >= 0;
  FairingPatch patch;
  static_cast<Submesh&>(patch) = extractSubmesh(mesh, keep);
  patch.moves.resize(patch.inputVertex.size());
  for (std::size_t p = 0; p < patch.inputVertex.size(); ++p)
    patch.moves[p] = region[patch.inputVertex[p]];
  return patch;
}

Positions scatterPatchPositions(const Positions& input, const Submesh& patch,
                                const Positions& patchPositions) {
  Positions out = input;
  for (std::size_t p = 0; p < patch.inputVertex.size(); ++p)
    out.row(patch.inputVertex[p]) = patchPositions.row(static_cast<Eigen::Index>(p));
  return out;
}

std::vector<std::pair<int, int>> regionOutlineEdges(const Stencils& stencils,
                                                    const std::vector<bool>& region) {
  const auto regionFace = [&](int f) {
    if (f < 0) return false;
    return region[stencils.faces(f, 0)] || region[stencils.faces(f, 1)] ||
           region[stencils.faces(f, 2)];
  };
  std::vector<std::pair<int, int>> edges;
  for (int e = 0; e < stencils.edgeCount(); ++e)
    if (regionFace(stencils.edgeFaces(e, 0)) != regionFace(stencils.edgeFaces(e, 1)))
      edges.emplace_back(stencils.edges(e, 0), stencils.edges(e, 1));
  return edges;
}

Eigen::Vector3d regionNormal(const Mesh& m, const std::vector<bool>& region) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < m.faceCount(); ++f) {
    const auto t = m.triangles.row(f);
    if (!(region[t(0)] || region[t(1)] || region[t(2)])) continue;
    const Eigen::Vector3d x0 = m.positions.row(t(0)), x1 = m.positions.row(t(1)),
                          x2 = m.positions.row(t(2));
    sum += (x1 - x0).cross(x2 - x0);
  }
  return sum.norm() > 0.0 ? Eigen::Vector3d(sum.normalized()) : Eigen::Vector3d::UnitZ();
}

}  // namespace flexure::modeling
