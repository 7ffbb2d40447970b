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

#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/stencils.h"

namespace flexure::modeling {

inline constexpr int kHeldRings = 2;

// The region a `--region` text names on `mesh`: "vertices:FILE" (indices, as readVertexSet reads
// them), "sphere:x,y,z,r" (the vertices inside), or "all-interior" (every vertex at least
// kHeldRings rings from the boundary). ("holes" changes the mesh and is fillHoles' business.)
// Throws InputError for a malformed text.
std::vector<bool> parseRegion(const std::string& spec, const Mesh& mesh, const Stencils& stencils);

// Every vertex at least `heldRings` rings from the boundary. InputError for a mesh without a
// boundary (its "interior" would be everything).
std::vector<bool> interiorRegion(const Stencils& stencils, int heldRings = kHeldRings);

// Throws InputError, starting with `regionName` (e.g. "lion.off: --region sphere:0,0,0,1") and
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

}  // namespace flexure::modeling
