// The OpenMesh half-edge structure behind modeling/'s connectivity queries. Internal to
// modeling/: nothing downstream includes this header (the architecture keeps OpenMesh types here).
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "modeling/mesh.h"

namespace flexure::modeling {

// (Not "HalfedgeTraits": OpenMesh defines that name as a macro.)
struct DoublePrecisionTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using HalfedgeMesh = OpenMesh::TriMesh_ArrayKernelT<DoublePrecisionTraits>;

// Vertex v and face f of `mesh` become OpenMesh handles v and f. `mesh` must pass checkMesh()
// (OpenMesh cannot represent what it rejects); an internal failure throws std::logic_error.
HalfedgeMesh buildHalfedgeMesh(const Mesh& mesh);

}  // namespace flexure::modeling
