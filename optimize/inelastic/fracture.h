// The fracture criterion of Gingold, Secord, Han, Grinspun & Zorin 2004 (seed 002, "Fracture"):
// per face, the strain at the top and bottom fibres of a shell of thickness h,
//
//   E_± = E_m ± (h/2) E_b,
//
// E_m the membrane (Green) strain and E_b the bending strain, both 2×2 tensors in the rest face's
// frame (curvature/face_frame.h). Where the largest eigenvalue of E_+ or E_− exceeds the fracture
// strain ε_f the shell cracks perpendicular to that eigenvector (docs/energies.md, "Fracture").
//
//   E_m = ½ (Fᵀ F − I),  F = [x1 − x0, x2 − x0] [x̄1 − x̄0, x̄2 − x̄0]⁻¹ (3 × 2, rest frame),
//
// which is the strain whose quadratic form on each rest edge ē_i gives the change of its squared
// length: ē_iᵀ E_m ē_i = (ℓ_i² − ℓ̄_i²) / 2.
//
//   E_b = Σ_i (φ_i − φ̄_i) ℓ̄_i / (2 Ā) n̂_i n̂_iᵀ,  φ = 2 tan(θ/2),
//
// the change of the triangle-averaged shape operator (curvature/triangle_averaged.h) over the
// face's edges that have a neighbour (a boundary edge adds nothing), n̂_i the rest in-plane
// normal of edge i, θ_i its bending angle.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "curvature/face_frame.h"
#include "curvature/triangle_averaged.h"
#include "modeling/crack_cut.h"
#include "modeling/mesh.h"
#include "modeling/stencils.h"

namespace flexure::optimize {

struct FractureOptions {
  double fractureStrain = 0.0;  // ε_f > 0: the largest principal strain a face bears
  double thickness = 0.0;       // h ≥ 0: the fibres at ± h/2 (0: the membrane strain alone)

  // InputError naming FractureOptions.fractureStrain or .thickness: ε_f not positive and finite,
  // h negative or not finite.
  void validate() const;
};

// One face's strains in its rest frame (u, v): symmetric 2×2 tensors.
struct FaceStrains {
  Eigen::Matrix2d membrane = Eigen::Matrix2d::Zero();  // E_m
  Eigen::Matrix2d bending = Eigen::Matrix2d::Zero();   // E_b, per unit length of thickness
};

// The largest principal fibre strain of a face and where it acts.
struct FacePrincipalStrain {
  int face = -1;
  double strain = 0.0;                                        // λ_max of E_+ or E_−
  Eigen::Vector3d strainDirection = Eigen::Vector3d::Zero();  // its eigenvector, unit, rest face
  Eigen::Vector3d crackDirection = Eigen::Vector3d::Zero();   // n̄ × strainDirection
  int fibre = 0;                                              // +1 top (E_+), −1 bottom (E_−)
};

// The criterion on one rest mesh: what depends on the rest shape alone (its stencils, each face's
// rest frame, [x̄1 − x̄0, x̄2 − x̄0]⁻¹, edge tensors and rest shape operator S̄_T) made once, so that a
// check evaluates only the current strains; kept by a simulation until a cut changes the mesh.
class FractureCriterion {
 public:
  explicit FractureCriterion(const modeling::Mesh& rest);

  const modeling::Mesh& rest() const { return rest_; }
  const modeling::Stencils& stencils() const { return stencils_; }
  // E_m and E_b of every face (#F) deformed to `current` (#V by 3; InputError otherwise).
  std::vector<FaceStrains> strains(const Eigen::Ref<const modeling::Positions>& current) const;
  // The largest principal fibre strain of every face (#F) for thickness h, from `strains`.
  std::vector<FacePrincipalStrain> principalStrains(const std::vector<FaceStrains>& strains,
                                                    double thickness) const;

 private:
  struct RestFace {
    curvature::FaceFrame frame;
    Eigen::Matrix2d inverseRestEdges;  // [x̄1 − x̄0, x̄2 − x̄0]⁻¹ in the frame
    curvature::TriangleAveragedResidual shapeOperator;
    Eigen::Matrix2d restShapeOperator;  // S̄_T
  };
  modeling::Mesh rest_;
  modeling::Stencils stencils_;
  std::vector<RestFace> faces_;
};

// E_m and E_b of every face (#F) of `rest` deformed to `current` (#V by 3).
std::vector<FaceStrains> faceStrains(const modeling::Mesh& rest,
                                     const Eigen::Ref<const modeling::Positions>& current);

// The largest principal fibre strain of every face (#F) for thickness h.
std::vector<FacePrincipalStrain> facePrincipalStrains(
    const modeling::Mesh& rest, const Eigen::Ref<const modeling::Positions>& current,
    double thickness);

// The face with the largest principal fibre strain when it exceeds ε_f; empty otherwise (no
// crack). Validates `options`; InputError when `current` does not have the rest mesh's rows.
std::optional<FacePrincipalStrain> criticalFace(
    const modeling::Mesh& rest, const Eigen::Ref<const modeling::Positions>& current,
    const FractureOptions& options);

// The faces whose strain reaching ε_f is a fracture event (#F): all but those with a vertex on an
// earlier crack's lips (a rest point where two or more vertices are) that are not around an open
// tip of `openTips`. Such a face unloads as the lips open; fractureShell starts no crack from it,
// and cuts it only on a crack grown from a tip.
std::vector<bool> fractureEventFaces(const modeling::Mesh& rest,
                                     const std::vector<Eigen::Vector3d>& openTips);

// A shell after one fracture check that cracked: the cut rest mesh (its rest state is rebuilt from
// it by buildProblem), the configuration and velocities carried over per vertex (a vertex made on
// an edge interpolates its ends, a duplicated one inherits its original's), the held vertices (a
// new vertex is held when both ends of its edge are) and the crack.
struct FracturedShell {
  modeling::Mesh rest;
  modeling::Positions positions;   // #V' by 3
  modeling::Positions velocities;  // #V' by 3
  std::vector<bool> heldVertex;    // #V' (empty when the input's was)
  FacePrincipalStrain critical;    // the face the crack started from, before the cut
  modeling::CrackCut cut;
  std::vector<Eigen::Vector3d> openTips;  // rest points where cracks stop inside the shell
};

// Checks the criterion on (rest, x) and, when a face is critical, cuts the shell along the crack
// through every face over ε_f (modeling::cutAlongCrack). A crack grows from an open tip first
// (seed 002: the crack grows from its tip in later steps): when a face around one of `openTips`
// (rest points of earlier cracks' tips) is over ε_f, the one of them with the largest strain seeds
// the cut at the tip, perpendicular to the principal direction of the tip's mean fibre strain
// (tipStrainDirection); otherwise the face with the largest strain seeds it through its centroid.
// Empty when no face exceeds ε_f. InputError for bad options or sizes that do not match.
std::optional<FracturedShell> fractureShell(const modeling::Mesh& rest,
                                            const modeling::Positions& x,
                                            const modeling::Positions& v,
                                            const std::vector<bool>& heldVertex,
                                            const FractureOptions& options,
                                            const std::vector<Eigen::Vector3d>& openTips = {});
// The same with the criterion made for the rest mesh (criterion.rest()).
std::optional<FracturedShell> fractureShell(const FractureCriterion& criterion,
                                            const modeling::Positions& x,
                                            const modeling::Positions& v,
                                            const std::vector<bool>& heldVertex,
                                            const FractureOptions& options,
                                            const std::vector<Eigen::Vector3d>& openTips = {});

// The open tips of a cut mesh: of `candidates` (rest points: earlier tips and the new crack's two
// ends), those where exactly one vertex of `rest` is, i.e. the crack stops inside the shell
// there (a crack's end on the boundary or on another crack is split in two).
std::vector<Eigen::Vector3d> openCrackTips(const modeling::Mesh& rest,
                                           const std::vector<Eigen::Vector3d>& candidates);

// Opens the fresh lips of `shell` by `gap` > 0, at rest and in its positions alike (so that no
// strain is added): the vertices that share both their cut rest point and their position (a cut's
// twins; a crack through an earlier lip makes twins of that lip's vertex on one side only) each
// move by `gap` towards the mean of their faces' centroids, into their own side of the crack, in
// both. The rest starts from `carriedRest` (#V' by 3: the rest positions the run had before the
// cut, carried to the cut mesh), so earlier lips keep the opening they were given, and it replaces
// shell.rest.positions; held vertices stay. Self-contact cannot repel pairs that touch (a log
// barrier is infinite at d = 0); lips apart by a small gap are pairs it inset-repels from the next
// step on (optimize/assembly/self_contact.h), so abutting fragments cannot pass through each
// other even by a sliver. The fracture bookkeeping needs the unopened rest mesh (lips are rest
// points of two or more vertices). Returns how many vertices moved in the positions; InputError
// when `carriedRest` does not fit the cut mesh.
int openLips(FracturedShell& shell, const modeling::Positions& carriedRest, double gap);

// The connected components of `mesh` (through shared vertices), each its own mesh with its
// vertices renumbered in their order: the fragments a fractured shell is written as.
std::vector<modeling::Mesh> meshFragments(const modeling::Mesh& mesh);

}  // namespace flexure::optimize
