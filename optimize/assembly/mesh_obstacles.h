// Mesh obstacles: rigid triangle meshes, static or in a prescribed rigid motion, that the shell
// may not pass through. They join the self-contact's collision mesh (self_contact.h): every
// vertex–face and edge–edge pair between a shell primitive and an obstacle primitive repels by
// the same barrier, in both directions (an obstacle vertex against a shell face, a shell vertex
// against an obstacle face, and edge against edge), so that neither a sharp tip of the obstacle
// nor a shell vertex slips through the other's faces. The obstacles' positions are given at each
// time, never unknowns: they push the shell and are not pushed back.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/stencils.h"
#include "optimize/assembly/pin_motion.h"

namespace flexure::optimize {

struct MeshObstacle {
  modeling::Mesh mesh;  // its vertices at time 0 and its triangles
  PinMotion motion;     // each vertex x₀ at motion.position(x₀, t); None: static
  std::string label;    // how errors name it (e.g. its file); empty: "mesh obstacle K"

  // Where its vertices are at time t (#W by 3).
  modeling::Positions positionsAt(double t) const;
  // Its vertices' velocities at time t (#W by 3; zero when static).
  modeling::Positions velocitiesAt(double t) const;
  bool moves() const { return motion.kind != PinMotion::Kind::None; }
};

// How errors name obstacle `index`: its label, or "mesh obstacle K".
std::string meshObstacleName(const std::vector<MeshObstacle>& obstacles, int index);

// InputError naming ProblemOptions.meshObstacles and the obstacle for one without a vertex or a
// triangle, with a non-finite coordinate or a face index outside its vertices.
void validateMeshObstacles(const std::vector<MeshObstacle>& obstacles);

// The edges (#E by 2, i < j, sorted) of a triangle list.
modeling::IndexPairs triangleEdges(const modeling::Triangles& faces);

}  // namespace flexure::optimize
