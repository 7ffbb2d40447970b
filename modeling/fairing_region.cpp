#include "modeling/fairing_region.h"

#include <charconv>
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
      throw InputError("--region " + spec + ": '" + field + "' is not a number");
    numbers.push_back(value);
  }
  return numbers;
}

// #V: the connected component of every vertex (through edges).
std::vector<int> components(const Stencils& s) {
  std::vector<int> component(s.vertexCount(), -1);
  std::vector<int> stack;
  int count = 0;
  for (int seed = 0; seed < s.vertexCount(); ++seed) {
    if (component[seed] >= 0) continue;
    component[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int r = s.oneRingOffsets[v]; r < s.oneRingOffsets[v + 1]; ++r) {
        const int w = s.oneRingVertices[r];
        if (component[w] < 0) {
          component[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return component;
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
      throw InputError("--region " + spec + ": expected sphere:x,y,z,r with r > 0");
    return verticesInSphere(mesh.positions, Eigen::Vector3d(n[0], n[1], n[2]), n[3]);
  }
  if (spec == "all-interior") return interiorRegion(stencils);
  throw InputError("--region " + spec +
                   ": expected vertices:FILE, sphere:x,y,z,r, all-interior or holes[:N]");
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
  const std::vector<int> component = components(stencils);
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

}  // namespace flexure::modeling
