// Fairing regions of real meshes: the vertices that move, the rings around them that hold
// positions and normals, and the patch (region + held rings) a fairing solve works on.
//
// With R the region, ring k around R is the neighbours of ring k − 1 not in R or an earlier ring
// (ring 0 = R). Holding rings 1 and 2 fixes the positions and the normals along the region's
// border ("clamped", as two boundary rings do for a plate). Every element of any of the five
// energies that reads a region vertex reads only vertices within two rings of R, and its
// neighbouring faces are in the patch, so the patch's energy differs from the whole mesh's by a
// constant: fairing the patch is fairing the mesh.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/stencils.h"

namespace flexure::modeling {

inline constexpr int kHeldRings = 2;
// The rings of unchanged mesh beyond the held ones that a picture of a fairing shows around it
// (flexure fair's figure, flexure view's framing of a fairing report).
inline constexpr int kContextRings = 8;

// The region a text names on `mesh`:
//   "vertices:FILE"     the indices in FILE (as readVertexSet reads them);
//   "sphere:x,y,z,r"    the vertices inside the ball (r > 0);
//   "around:VERTEX,R"   the vertices within geodesic distance R ℓ̄ of VERTEX (geodesicDistances
//                       below), ℓ̄ the mesh's mean edge length, R > 0 in multiples of it;
//   "rings:VERTEX,K"    VERTEX and its K rings (ring k = the neighbours of ring k − 1; K ≥ 0);
//   "all-interior"      every vertex at least kHeldRings rings from the boundary.
// ("holes" changes the mesh and is fillHoles' business.) Throws InputError starting "region SPEC: "
// and saying what is wrong, for a malformed text, a vertex out of range, R ≤ 0 or K < 0.
std::vector<bool> parseRegion(const std::string& spec, const Mesh& mesh, const Stencils& stencils);

// #V: the geodesic distance of every vertex from `source` along the surface, up to
// `maxDistance` (+∞ beyond it and where the source does not reach), by fast marching on the
// triangles (Kimmel & Sethian 1998, with the exact planar update of Novotni & Klein 2002): a
// vertex's distance is accepted in increasing order, Dijkstra-like; a face (a, b, c) with a and b
// accepted unfolds into the plane, the source is placed at s with |s − a| = d_a, |s − b| = d_b on
// the far side of ab from c, and d_c = |c − s| when the segment s c crosses ab (the straight
// path enters the face through that edge), else min(d_a + |ac|, d_b + |bc|) (along the edges).
// Its error is of first order in the edge length on a curved mesh; on a flat mesh it is the
// Euclidean distance to round-off on the regular patch48 and to within 2 % on an irregular
// Delaunay mesh (tested), where Dijkstra along edges alone is up to 2/√3 − 1 ≈ 15 % long on a
// regular triangulation.
std::vector<double> geodesicDistances(const Mesh& mesh, const Stencils& stencils, int source,
                                      double maxDistance);

// The mean length of the mesh's edges, ℓ̄ (the unit of "around:VERTEX,R").
double meanEdgeLength(const Mesh& mesh, const Stencils& stencils);

// Every vertex at least `heldRings` rings from the boundary. InputError for a mesh without a
// boundary (its "interior" would be everything).
std::vector<bool> interiorRegion(const Stencils& stencils, int heldRings = kHeldRings);

// Throws InputError, starting with `regionName` (e.g. "lion.off: region sphere:0,0,0,1") and
// naming a vertex, for a region that cannot be faired: it is
// empty; it comes closer than `heldRings` rings to the mesh boundary (no room for the held
// rings); or it covers a whole connected component (nothing holds it in place).
void requireFairableRegion(const Stencils& stencils, const std::vector<bool>& region,
                           std::string_view regionName, int heldRings = kHeldRings);

// The faces whose three vertices all have keep[v], with their vertices renumbered in increasing
// input order (face order kept).
struct Submesh {
  Mesh mesh;
  std::vector<int> inputVertex;  // submesh vertex → input vertex
};
Submesh extractSubmesh(const Mesh& mesh, const std::vector<bool>& keep);

// The patch a fairing solves on: the faces within `heldRings` rings of the region, and which of
// its vertices move (the region's).
struct FairingPatch : Submesh {
  std::vector<bool> moves;  // per patch vertex
};
// `region` must pass requireFairableRegion.
FairingPatch extractFairingPatch(const Mesh& mesh, const Stencils& stencils,
                                 const std::vector<bool>& region, int heldRings = kHeldRings);

// The input positions with the patch's vertices set to `patchPositions`.
Positions scatterPatchPositions(const Positions& input, const Submesh& patch,
                                const Positions& patchPositions);

// The region's outline: the boundary of the region's faces (those with a vertex in the region,
// i.e. every face that can change shape) — the edges with a region face on one side and a face
// that is not (or none) on the other, as vertex pairs. It runs along the first held ring, which
// stays in place, so it is the same line on the input and on every fair of it.
std::vector<std::pair<int, int>> regionOutlineEdges(const Stencils& stencils,
                                                    const std::vector<bool>& region);

// The area-weighted mean unit normal of the faces with a vertex in `region` (a flag per vertex of
// `mesh`): the direction a picture of the region looks along; +z when the normals cancel.
Eigen::Vector3d regionNormal(const Mesh& mesh, const std::vector<bool>& region);

}  // namespace flexure::modeling
