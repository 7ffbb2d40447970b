// Mesh checks: everything flexure requires of an input triangle mesh, reported per element.
//
// A Mesh is usable when checkMesh() finds no problem: at least one face, vertex indices in range,
// finite coordinates,
// no face repeating a vertex, no zero-area face, no unreferenced vertex, no duplicate face, no edge
// shared by more than two faces, consistent orientation (each interior edge traversed once in
// each direction) and no vertex whose faces form more than one fan.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

enum class MeshProblemKind {
  Empty,
  VertexIndexOutOfRange,
  NonFiniteCoordinate,
  RepeatedVertexInFace,
  ZeroAreaFace,
  UnreferencedVertex,
  DuplicateFace,
  NonManifoldEdge,
  InconsistentOrientation,
  NonManifoldVertex,
  AreaOverflow,  // finite coordinates whose face area or edge lengths overflow double precision
};

struct MeshProblem {
  MeshProblemKind kind;
  std::string element;  // "face 12 (vertices 3, 4, 9)", "edge (4, 9)", "vertex 7", ...
  std::string reason;   // what is wrong with it, in words
};

struct MeshCheck {
  std::vector<MeshProblem> problems;  // at most `maxPerKind` of each kind
  std::vector<int> problemCounts;     // per MeshProblemKind, all occurrences
  bool valid() const { return problems.empty(); }
  int totalProblems() const;
};

// Short machine-readable name of a problem kind ("non_manifold_edge", ...).
std::string_view meshProblemName(MeshProblemKind kind);

// Finds every problem of `mesh`; keeps the first `maxPerKind` of each kind for the report.
MeshCheck checkMesh(const Mesh& mesh, int maxPerKind = 5);

// Throws InputError "SOURCE: ELEMENT: REASON" (with a count of further problems) unless valid.
void requireValidMesh(const Mesh& mesh, std::string_view source);

}  // namespace flexure::modeling
