// Fixed boundaries: which vertices (and midedge unknowns) a minimization holds, and at what values.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "modeling/mesh.h"
#include "modeling/polynomial_surface.h"
#include "modeling/stencils.h"

namespace flexure::optimize {

using modeling::Positions;

// The unknowns of a vertex: z alone (height; x, y held at rest) or x, y, z.
enum class DofMode { Height, Xyz };
// "height" | "xyz"; InputError naming `field` (the option that gave it) otherwise.
DofMode parseDofMode(std::string_view name, std::string_view field);

struct BoundaryConditions {
  std::vector<bool> fixedVertex;  // #V
  Positions start;                // #V by 3: values of the fixed vertices, start of the free ones
  std::vector<bool> fixedEdge;    // #E: midedge ξ held at `xi` (clamped boundary normals)
  Eigen::VectorXd xi;             // #E: values of the held ξ, start of the free ones
};

// `bc` with its held vertices at `held`'s rows (#V by 3; the free rows stay bc's starts) and, when
// given, its held ξ at `heldXi` (#E): the same held unknowns at other values. InputError when a
// size does not match, or when bc holds ξ, no ξ are given and a held vertex moves: the held ξ
// are the clamp of bc's own held values (midedge's boundary normals) and do not follow others.
BoundaryConditions withHeldValues(BoundaryConditions bc, const Positions& held,
                                  const std::optional<Eigen::VectorXd>& heldXi);

// Which unknowns a solve moves, in HessianAssembly's numbering (coordinate c of vertex v is 3v + c,
// ξ_e is 3 #V + e): the coordinates of the vertices not held (z only in height mode), then the ξ
// not held (`heldEdge`: #E, or empty when the energy owns no edge unknowns).
std::vector<bool> freeUnknownMask(const std::vector<bool>& heldVertex,
                                  const std::vector<bool>& heldEdge, DofMode dof);

// The vertices of rings 0 .. ringCount − 1 (ring 0 = the boundary; 2 rings fix positions and
// normals: "clamped").
std::vector<bool> fixedRings(const modeling::Stencils& stencils, int ringCount);

// A set of held vertices, as the text `spec` names it: rings:K (rings 0 .. K − 1), vertices:FILE
// (a list as modeling::readVertexSet reads it) or box:X0,X1,Y0,Y1,Z0,Z1 (the `rest` vertices
// inside the box, bounds included; a box that holds none is an error). InputError for a bad text
// starts with `option` (what gave the text, e.g. the command line's option) and the text.
std::vector<bool> parseFixedSet(const std::string& option, const std::string& spec,
                                const modeling::Stencils& stencils, const Positions& rest);

// The midedge ξ (#E) held with a set of held vertices named by `spec` (parseFixedSet's text):
// rings:K with K ≥ 2 holds the boundary faces, and with them midedge's boundary normals ("clamped",
// as fixedRings(·, 2) is for a minimization and the ring clamp for vibration modes): every
// boundary edge. Empty (no ξ held) for any other set.
std::vector<bool> clampedBoundaryEdges(const std::string& spec, const modeling::Stencils& stencils);

// Positions that hold x̄, ȳ of `rest` and lift the fixed vertices onto z = p(x̄, ȳ); the free
// ones keep their rest z (the interior starts at rest).
Positions boundaryFromSurface(const Positions& rest, const std::vector<bool>& fixedVertex,
                              const modeling::PolynomialSurface& surface);

// Midedge boundary normals: clamped (boundary ξ prescribed from the boundary surface's normals)
// or free (natural, moment-free).
enum class BoundaryNormals { Clamped, Free };
// "clamped" | "free"; InputError naming ProblemOptions.boundaryNormals otherwise.
BoundaryNormals parseBoundaryNormals(std::string_view name);

// The test problems' boundary conditions: the fixed vertices lifted onto z = p(x̄, ȳ), the
// interior at rest, and (midedge, `restXi` non-empty) boundary ξ clamped to p's normals — for a
// linearized solve the linearized clamp — or free. Boundary faces must be fixed for a clamp to
// hold (two rings fix them).
BoundaryConditions surfaceBoundary(const modeling::Stencils& stencils, const Positions& rest,
                                   const Eigen::VectorXd& restXi,
                                   const std::vector<bool>& fixedVertex,
                                   const modeling::PolynomialSurface& surface,
                                   BoundaryNormals normals, bool linearized);

// C2's measure: max over the free vertices of |z − p(x, y)|, divided by max over all vertices of
// |p(x, y)| (at the rest x, y).
double reproductionError(const Positions& rest, const Positions& result,
                         const std::vector<bool>& fixedVertex,
                         const modeling::PolynomialSurface& surface);

}  // namespace flexure::optimize
