// Fairing a region of a real mesh (modeling/fairing_region.h): flexure's nonlinear fairing, CGAL's
// linear fair on the same patch, and the measures a fairing report compares them by.
//
// flexure's fairing (Clarenz et al. 2004's Willmore flow at its limit; Botsch & Kobbelt's
// variational modeling with a real bending energy): the region's vertices move in xyz to minimize
//
//   E = E_bend(x) + E_membrane(x),
//
// E_bend one of the five energies of docs/energies.md with a flat rest curvature and the input's
// metric (a fair surface has no preferred curvature), E_membrane a membrane on the input's metric
// (curvature/membrane.h; by default `conformal`) so that the triangles keep their shapes and the
// vertices do not slide. The held rings keep
// their positions bit for bit; for midedge every ξ is free (the held rings carry the normals).
#pragma once

#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/fairing_region.h"
#include "optimize/minimize.h"

namespace flexure::optimize {

// Where the nonlinear solve starts: at the linear fair (the cotangent bi-Laplacian of the input's
// metric, solved for x, y and z: what CGAL's fair computes, here with CHOLMOD), from which Gauss–
// Newton has a smooth surface to correct; at the input; or (Best) at whichever of the two has the
// lower bending energy. The membrane's rest shape is the start, so it costs nothing there and the
// solve, which never raises E_bend + E_membrane, ends with E_bend no higher than at the start:
// with Best, no higher than the input's or the linear fair's.
enum class FairingStart { Best, Biharmonic, Input };

struct FairingOptions {
  curvature::BendingOptions bending;  // its restCurvature is ignored: fairing's is flat
  curvature::MembraneModel membrane = curvature::MembraneModel::Conformal;
  double membraneWeight = 1.0;  // w below
  FairingStart start = FairingStart::Best;
  MinimizeOptions solver;  // dof and start are fairing's own: xyz, from `start`
};

// The membrane of weight w, bending stiffness k_B, mean rest edge length ℓ̄ of the region:
//   conformal: k_S = w k_B                      (the default: shapes kept, sizes free);
//   stvk:      Y = w k_B / ℓ̄² (ν = 0.3);        springs: k_L = w k_B / ℓ̄,  k_A = w k_B / ℓ̄².
// A triangle's change of shape (conformal: q → 1 as it collapses) or a strain ε of one triangle
// (stvk, springs: ≈ w k_B ε²) then weighs like the bending energy of a triangle curved at radius
// ℓ̄, ≈ k_B: w weighs the triangles' quality against bending at the mesh's own scale. All are
// unchanged by scaling the mesh, so a mesh and its scaled copy fair alike. stvk and springs also
// keep the input's lengths, so the surface can only bend near-isometrically: for small
// corrections. Too small a w lets vertices slide into degenerate triangles that lower the
// discrete bending energy.
curvature::MembraneOptions fairingMembrane(curvature::MembraneModel model, double weight,
                                           double bendingStiffness, double meanEdgeLength);

struct FairingResult {
  Positions positions;  // the patch's vertices, #patch vertices by 3
  MinimizeReport report;
  FairingStart start;  // Biharmonic or Input: where the solve started
};

// flexure's fairing of `patch`. Throws InputError for a degenerate element of the input (named in
// patch indices); the report says whether the solve converged.
FairingResult fairNonlinear(const modeling::FairingPatch& patch, const FairingOptions& options);

// The linear fair of `patch` with flexure's CHOLMOD solve (see FairingStart).
Positions fairBiharmonic(const modeling::FairingPatch& patch);

// CGAL's Polygon_mesh_processing::fair (continuity 1: the bi-Laplacian of the input's cotangent
// weights vanishes at the moving vertices) on the same patch.
Positions fairCgal(const modeling::FairingPatch& patch);

// Shape quality of the faces touching a moving vertex: the smallest angle, and the mean and
// smallest q = 4√3 A / (a² + b² + c²) (1 for an equilateral triangle, → 0 as it degenerates).
struct TriangleQuality {
  double minAngleDegrees = 0.0, meanShape = 0.0, minShape = 0.0;
};

struct EnergyMeasure {
  std::string energy;  // discretization name
  double value = 0.0;  // E_bend of the patch (flat rest, the input's metric)
  std::string error;   // non-empty: the energy could not be evaluated (value meaningless)
};

struct FairingMeasures {
  std::vector<EnergyMeasure> bending;  // all five discretizations, in docs/energies.md's order
  TriangleQuality quality;
  double maxDisplacement = 0.0;  // max |x_v − x_v(input)| over the patch
};

// The measures of `positions` (the patch's vertices) against the input patch. The five energies
// share `material`'s stiffness and, where the discretization takes one, its Poisson's ratio
// (hinge and cotan are ν = 1 models); midedge's ξ are minimized for the positions.
FairingMeasures measureFairing(const modeling::FairingPatch& patch, const Positions& positions,
                               const curvature::BendingOptions& material);

}  // namespace flexure::optimize
