// flexure._flexure.info, vertex_rings, boundary_loops: what flexure info reports of a mesh, and
// the boundary rings that pins and clamps hold.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "modeling/boundary_rings.h"
#include "modeling/mesh_check.h"
#include "modeling/mesh_info.h"
#include "modeling/stencils.h"
#include "python/bindings/bindings.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

py::dict histogram(const std::map<int, int>& valences) {
  py::dict d;
  for (const auto& [valence, count] : valences) d[py::int_(valence)] = count;
  return d;
}

// flexure info --json's report of (V, F): counts and, for a valid mesh, topology and sizes.
py::dict infoOf(const PositionsRef& V, const TrianglesRef& F) {
  modeling::Mesh mesh;
  mesh.positions = V;
  mesh.triangles = F;
  const modeling::MeshCheck check = modeling::checkMesh(mesh, 10);
  py::dict d;
  d["vertices"] = mesh.vertexCount();
  d["faces"] = mesh.faceCount();
  if (check.valid()) {
    const modeling::MeshInfo info = modeling::describeMesh(mesh);
    d["edges"] = info.edges;
    d["components"] = info.components;
    d["euler_characteristic"] = info.eulerCharacteristic;
    d["boundary_loops"] = info.boundaryLoopLengths;
    py::dict valences;
    valences["interior"] = histogram(info.interiorValences);
    valences["boundary"] = histogram(info.boundaryValences);
    d["valence_histogram"] = valences;
    py::dict edge;
    edge["min"] = info.minEdgeLength;
    edge["mean"] = info.meanEdgeLength;
    edge["max"] = info.maxEdgeLength;
    d["edge_length"] = edge;
    d["area"] = info.area;
    py::dict box;
    box["min"] = std::vector<double>{info.boxMin.x(), info.boxMin.y(), info.boxMin.z()};
    box["max"] = std::vector<double>{info.boxMax.x(), info.boxMax.y(), info.boxMax.z()};
    d["bounding_box"] = box;
  }
  py::list problems;
  py::dict counts;
  for (const auto& p : check.problems) {
    py::dict problem;
    problem["kind"] = std::string(modeling::meshProblemName(p.kind));
    problem["element"] = p.element;
    problem["reason"] = p.reason;
    problems.append(problem);
  }
  for (size_t k = 0; k < check.problemCounts.size(); ++k)
    if (check.problemCounts[k] > 0)
      counts[py::str(
          std::string(modeling::meshProblemName(static_cast<modeling::MeshProblemKind>(k))))] =
          check.problemCounts[k];
  py::dict validation;
  validation["valid"] = check.valid();
  validation["problem_counts"] = counts;
  validation["problems"] = problems;
  d["validation"] = validation;
  return d;
}

Eigen::VectorXi vertexRingsOf(const PositionsRef& V, const TrianglesRef& F) {
  const modeling::Mesh mesh = checkedMesh(V, F, "V, F");
  return modeling::vertexRings(modeling::compileStencils(mesh));
}

std::vector<std::vector<int>> boundaryLoopsOf(const PositionsRef& V, const TrianglesRef& F) {
  const modeling::Mesh mesh = checkedMesh(V, F, "V, F");
  return modeling::boundaryLoops(modeling::compileStencils(mesh));
}

}  // namespace

void bindMeshes(py::module_& m) {
  m.def("info", &infoOf);
  m.def("vertex_rings", &vertexRingsOf);
  m.def("boundary_loops", &boundaryLoopsOf);
}

}  // namespace flexure::python
