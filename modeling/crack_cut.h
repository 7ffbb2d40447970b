// Cutting a triangle mesh along a crack through faces (Gingold et al. 2004, seed 002, "Fracture";
// ARCSim's cuts through faces with vertex budging, Pfaff et al. 2014).
//
// The crack is the straightest line on the rest surface through the centroid of a seed face along a
// given direction: marched face to face both ways, the direction unfolded across each edge about
// it (the same angle to the edge on both sides), while the faces it enters are cracking. It ends on
// the boundary or, at a face that is not cracking or at an edge whose nearer end is on the
// boundary, at that nearer end (the crack tip is a vertex, so no neighbour is left with a hanging
// vertex; a crack grown later from near an earlier tip joins it there).
//
// Vertex budging: a crossing within `budge` (a fraction of the edge) of an edge end moves to that
// end, and so does one whose segment would run along its own edge. The budge starts at
// CrackCutOptions.initialBudge and grows until no face the cut makes has an angle below
// CrackCutOptions.minAngleDegrees (at ½ every crossing is a vertex: the crack runs along edges and
// makes no face).
//
// Faces the crack crosses are split into triangles along it (a quadrilateral by the diagonal with
// the larger smallest angle), a new vertex at each remaining crossing, its rest and current
// positions interpolated along the edge at the same parameter. Then the vertices on the crack are
// duplicated: around each vertex the faces joined by edges that are not on the crack keep one copy,
// so the pieces on the two sides separate; a tip vertex stays whole.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

struct CrackCutOptions {
  double minAngleDegrees = 10.0;  // no face the cut makes has a smaller angle
  double initialBudge = 0.15;     // fraction of an edge within which a crossing moves to its end
};

// The start of a crack: a face and a direction in its rest plane (the crack runs along it).
// With a tip vertex (an earlier crack's tip, a corner of the face), the crack grows from it: it
// starts there and runs along the direction (pointing away from the crack), into the face around
// the tip that this line enters and on through the cracking faces (through the seed face's
// centroid both ways when the line enters no face).
struct CrackSeed {
  int face = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  int tipVertex = -1;
};

// Vertex i of the cut mesh is (1 − t) x_a + t x_b of the old vertices (a == b, t = 0: a copy):
// how rest and current positions, velocities and any per-vertex quantity carry over.
struct VertexSource {
  int a = 0;
  int b = 0;
  double t = 0.0;
};

struct CrackCut {
  Mesh rest;                          // the cut rest mesh
  Positions current;                  // #V' by 3, the configuration on the cut mesh
  std::vector<VertexSource> sources;  // #V'
  std::vector<int> faceOrigin;        // #F': the old face each new face lies in
  // The crack's vertices in order (cut-mesh indices of one side), and its points: rest and current.
  std::vector<int> crackVertices;
  Positions crackRest;
  Positions crackCurrent;
  double budge = 0.0;  // the budge that was used
  int facesSplit = 0;
  int verticesAdded = 0;       // at crossings
  int verticesDuplicated = 0;  // to separate the sides
};

// Cuts `rest` (with the configuration `current`, #V by 3) along the crack from `seed` through the
// faces with cracking[f] (#F; the seed face is cut whatever its flag). InputError for a seed face
// out of range, a direction not in the seed face's plane or zero, or sizes that do not match.
CrackCut cutAlongCrack(const Mesh& rest, const Positions& current, const CrackSeed& seed,
                       const std::vector<bool>& cracking, const CrackCutOptions& options = {});

}  // namespace flexure::modeling
