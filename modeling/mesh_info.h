// A description of a mesh for people: counts, topology, valences, sizes (flexure info, demo).
#pragma once

#include <Eigen/Core>
#include <map>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

struct MeshInfo {
  int vertices = 0;
  int faces = 0;
  int edges = 0;
  int components = 0;
  int eulerCharacteristic = 0;           // V − E + F: 1 for a disk, 2 for a sphere
  std::vector<int> boundaryLoopLengths;  // vertices per loop, longest first
  std::map<int, int> interiorValences;   // valence → number of interior vertices
  std::map<int, int> boundaryValences;   // valence → number of boundary vertices
  double minEdgeLength = 0.0, meanEdgeLength = 0.0, maxEdgeLength = 0.0;
  double area = 0.0;
  Eigen::Vector3d boxMin = Eigen::Vector3d::Zero(), boxMax = Eigen::Vector3d::Zero();
};

// `mesh` must pass checkMesh().
MeshInfo describeMesh(const Mesh& mesh);

// The smallest interior angle of the triangle (x_a, x_b, x_c) of `x`, in degrees: at each corner
// atan2(|u × w|, u · w) of the edges u, w leaving it (accurate for slivers, unlike acos).
double smallestAngleDegrees(const Positions& x, int a, int b, int c);

}  // namespace flexure::modeling
