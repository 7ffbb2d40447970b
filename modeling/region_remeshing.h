// Local isotropic remeshing of a fairing region: the faces that can change shape (those with a
// vertex in the region) remeshed by CGAL's Polygon_mesh_processing::isotropic_remeshing (Botsch &
// Kobbelt 2004: split edges longer than 4/3 ℓ, collapse those shorter than 4/5 ℓ, flip towards
// valence 6, tangential relaxation, projection back onto the input faces), their border held:
// the border edges are neither split nor collapsed and their vertices do not move, so every face
// and vertex outside keeps its position bit for bit. Slivers in the region (blade.off's trailing
// edge: 0.47°–1.22°) stall the geometric fairing energy. The target length is one for the whole
// region: slivers that discretize a feature narrower than it (blade.off's trailing edge, 0.04
// across, in edges 1.87 long) are cut across, not resolved (docs/commands/fair.md measures it).
#pragma once

#include <optional>
#include <vector>

#include "modeling/mesh.h"

namespace flexure::modeling {

struct RemeshOptions {
  // ℓ, the target edge length; empty: the mean edge length of the remeshed faces in the input.
  std::optional<double> targetEdgeLength;
  // Rounds of split / collapse / flip / relax. 3, as CGAL's isotropic_remeshing_example.cpp:
  // CGAL's default of 1 relaxes the vertices of the splits and collapses once only. (On the test's
  // sliver grid 1 to 10 rounds all end between 28.8° and 33.3°.)
  int iterations = 3;

  // InputError naming the field (RemeshOptions.targetEdgeLength) for ℓ not finite and > 0 or
  // iterations outside [1, 100].
  void validate() const;
};

struct RemeshedRegion {
  Mesh mesh;  // the input's vertices that remain, in input order, then the new ones
  // Per output vertex: its input index, or −1 for a vertex the remeshing added.
  std::vector<int> inputVertex;
  // Per output vertex: a vertex of the remeshed faces off their border (what moves in a fair;
  // it holds the input's region vertices that remain, and the new ones).
  std::vector<bool> region;
  std::vector<bool> remeshedFace;  // per output face
  double targetEdgeLength = 0.0;
  int iterations = 0;
  int facesBefore = 0, facesAfter = 0;  // the remeshed faces in the input and in the output
  // Distances (in the mesh's length unit) from the input's remeshed faces to the output's, the
  // reverse, and their maximum (the symmetric Hausdorff distance). Each is the largest distance
  // of a set of sample points: on every face the 15 points of barycentric coordinates (i, j, k)/4,
  // i + j + k = 4 (vertices and edge points included), so each is a lower bound of the exact
  // one-sided Hausdorff distance, within the samples' spacing (a quarter edge) times the faces'
  // curvature; 0 to round-off when the region is flat.
  double hausdorffInputToRemeshed = 0.0, hausdorffRemeshedToInput = 0.0, hausdorffDistance = 0.0;
  // The smallest angle of the remeshed faces, in the input and in the output.
  double minAngleDegreesBefore = 0.0, minAngleDegreesAfter = 0.0;
};

// `region` has one entry per vertex of `mesh` (a manifold triangle mesh) and selects at least one
// vertex. InputError for a wrong size or an empty region (naming "region"), for options that fail
// validate(), and for a mesh CGAL rejects (naming the face). The border edges are held as they
// are whatever their length: a border edge longer than 4/3 ℓ stays, with the faces along it.
RemeshedRegion remeshRegion(const Mesh& mesh, const std::vector<bool>& region,
                            const RemeshOptions& options);

}  // namespace flexure::modeling
