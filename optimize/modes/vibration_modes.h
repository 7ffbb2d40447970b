// Small vibrations about the rest state: the generalized eigenproblem K v = ω² M v.
//
// K = ∇²E at rest over the free unknowns. Every residual vanishes at rest, so K = JᵀJ, the
// Gauss–Newton matrix the Hessian assembly already builds (hessian_assembly.h). M is the lumped
// mass, ρh times a vertex area: barycentric (Discrete Shells: m_v = ρh/3 Σ incident Ā_T) or the
// mixed Voronoi area. The midedge ξ carry no mass: they are eliminated (K's Schur complement on
// the vertex unknowns), so a mode is a vertex motion.
//
// The smallest eigenpairs come from shift-invert Lanczos (Spectra) on C = M^{-1/2} S M^{-1/2},
// S the Schur complement, with (C − σ)⁻¹ = M^{1/2} (S − σM)⁻¹ M^{1/2} applied through one CHOLMOD
// factorization of the whole K − σM (ξ rows carry no mass): solving it with a right-hand side
// that is zero on the ξ rows applies (S − σM)⁻¹. σ < 0 sits just below the spectrum (K is
// positive semidefinite at rest), so free plates' rigid modes leave the factorization definite.
//
// Frequencies are reported as ω and as the dimensionless λ = ω L² √(ρh / D), D = 2 k_B: flexure's
// energy is k_B ∫ Ψ_ν and the continuum plate's is (D/2) ∫ Ψ_ν (docs/energies.md). On a square
// of side L simply supported, λ_mn = π² (m² + n²) exactly.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/energy_term.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "modeling/vertex_quantities.h"
#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

// How the boundary (ring 0) is held.
//  Clamped: zero deflection and slope. SimplySupported: ring 0 fixed, rotation free (midedge
//  boundary ξ free: no moment). Free: nothing fixed; the rigid motions (3 in height mode, 6 in
//  xyz) are zero modes, reported as such.
enum class Support { Clamped, SimplySupported, Free };
// How a clamp holds the slope: Rings fixes rings 0 and 1 (a band one edge wide held flat, what
// minimize's rings:2 does; any energy); Normals (midedge only) fixes ring 0 and holds the
// boundary midedge normals vertical: each boundary ξ becomes the linear function of the boundary
// face's free vertex that keeps the normal at the edge midpoint at its rest direction
// (curvature::linearizedClampedBoundaryXi with a flat boundary surface).
enum class Clamp { Rings, Normals };
using modeling::MassLumping;
using modeling::massLumpingName;

// "clamped" | "simply-supported" | "free"; "rings" | "normals".
const char* supportName(Support support);
const char* clampName(Clamp clamp);
// The names above; InputError naming ModesOptions.support / ModesOptions.clamp otherwise.
Support parseSupport(std::string_view name);
Clamp parseClamp(std::string_view name);

struct ModesOptions {
  int count = 12;  // flexible modes wanted (the expected rigid modes come on top)
  DofMode dof = DofMode::Height;
  Support support = Support::Clamped;
  Clamp clamp = Clamp::Rings;
  std::vector<bool> extraFixed;  // #V or empty: vertices held in addition to the support
  MassLumping mass = MassLumping::Barycentric;
  double density = 1.0;           // ρh: mass per unit rest area
  double bendingStiffness = 1.0;  // k_B, for λ (D = 2 k_B)
  double length = 0.0;            // L for λ; ≤ 0: the rest bounding box's largest side

  // Throws InputError naming the field for count < 1 or density ≤ 0 (what vibrationModes also
  // refuses, knowing the problem: checkModesRest's refusals, more modes than unknowns).
  void validate() const;
};

// What a modes run is, said once for the command and for Python, before its energies are known:
// the options (their clamp aside), the clamp when one is given, and whether a membrane is.
struct ModesSpec {
  ModesOptions modes;
  std::optional<Clamp> clamp;  // empty: each energy's own (forEnergy)
  bool membrane = false;       // a membrane is given (the body of dof xyz)

  // InputError naming the fields: the options' rules, a clamp without clamped support, a membrane
  // without dof xyz or dof xyz without one.
  void validate() const;
  // The options for one energy: the clamp given, else normals for an energy that owns edge
  // unknowns (midedge's ξ, which the clamp holds), else rings. InputError for a normals clamp of
  // an energy without them (clamped support).
  ModesOptions forEnergy(const curvature::BendingOptions& bending) const;
};

// A modes run as a person gives it (the command's flags, Python's keywords): the names of the
// support, mass lumping, dof and clamp (empty: none given), the numbers as they are.
struct ModesWords {
  int count = 12;
  std::string support = "clamped", mass = "barycentric", dof = "height", clamp;
  double density = 1.0, bendingStiffness = 1.0, length = 0.0;
  bool membrane = false;
};
// The spec the words say, each name parsed beside its enum, validated (InputError naming the
// fields).
ModesSpec modesSpec(const ModesWords& words);

// Height mode moves each vertex along z only: the transverse motion of a plate flat in the xy
// plane and nothing meaningful on a curved surface, whose z motions are partly tangential. A rest
// is flat when its z range is at most kFlatRestTolerance times its bounding box's largest side.
inline constexpr double kFlatRestTolerance = 1e-6;
bool restIsFlatPlate(const Positions& rest);

// What the rest surface rules out, before any assembly: height mode on a rest that is not flat,
// a normals clamp without ξ (`edgeUnknowns` false) or off a flat plate in height mode. Throws
// InputError naming the field and what to use instead; vibrationModes calls it too.
void checkModesRest(const ModesOptions& options, const Positions& rest, bool edgeUnknowns);

struct VibrationMode {
  double omegaSquared = 0.0;  // ω², the eigenvalue
  double omega = 0.0;         // √ω² (0 for a zero mode whose computed ω² rounds below 0)
  double lambda = 0.0;        // ω L² √(ρh / D)
  bool zero = false;          // λ < kZeroModeLambda: a rigid motion or a spurious zero mode
  int multiplicity = 1;  // modes whose λ agree to kDegenerateTolerance (relative), this one too
  double residual = 0.0;  // ‖K v − ω² M v‖ / ‖K v‖ (zero modes: ‖K v‖ / (‖K‖∞ ‖v‖))
  double nodalLength = 0.0;    // length of the nodal lines (rest metric), see nodalSegments
  double participation = 0.0;  // participationRatio of the shape
  bool localized = false;      // participation < kLocalizedParticipation
  Positions shape;             // #V by 3 displacement, M-normalized: Σ_v m_v |v_v|² = 1
};

inline constexpr double kZeroModeLambda = 1e-3;
inline constexpr double kDegenerateTolerance = 1e-6;
inline constexpr double kNodalFloor = 1e-4;
// A mode whose participation ratio is below this moves a small part of the mass: less than a
// tenth of what a smooth plate mode moves (4/9 for sin(mπx) sin(nπy) on a square), a few
// vertices on any mesh fine enough to resolve the plate's modes.
inline constexpr double kLocalizedParticipation = 0.1;

struct ModesResult {
  std::vector<VibrationMode> modes;  // ascending ω²: the zero modes first
  int rigidModes = 0;  // the dimension of the rigid motions the fixed vertices leave free
  // The zero modes (λ < kZeroModeLambda), counted exactly by inertia, and those beyond the rigid
  // ones (a vertex no element touches, say), which take the place of flexible modes: the solve
  // asks for as many more. `modes` holds every zero mode Lanczos returned (it may return fewer
  // copies of a repeated zero than there are) and `flexibleModes` flexible ones, fewer than
  // asked for only when a long run of zero modes kept Lanczos from converging.
  int zeroModes = 0;
  int spuriousZeroModes = 0;
  int flexibleModes = 0;
  double length = 0.0, flexuralRigidity = 0.0, shift = 0.0;  // L, D, σ
  int unknowns = 0, massUnknowns = 0, fixedVertices = 0;
  int operations = 0, restarts = 0;  // Lanczos: solves with the factor, restarts
  double assemblySeconds = 0.0, factorSeconds = 0.0, eigenSeconds = 0.0, totalSeconds = 0.0;
};

// The smallest `count` flexible modes (and every rigid one). Throws InputError for an unusable
// request (Normals without ξ, count < 1, more modes than unknowns, nothing free), NumericalError
// when the factorization or Lanczos fails.
ModesResult vibrationModes(const std::vector<const curvature::EnergyTerm*>& terms,
                           const modeling::Stencils& stencils, const modeling::RestState& rest,
                           const Eigen::VectorXd& restXi, const ModesOptions& options);

// The mass-weighted participation ratio of a displacement u (#V by 3) with vertex masses m (#V):
// (Σ_v m_v |u_v|²)² / (M Σ_v m_v |u_v|⁴), M = Σ_v m_v. 1 when every vertex moves alike, the moving
// share of the mass when a part moves alike and the rest is still, 4/9 for sin(mπx) sin(nπy) on
// the unit square; the count-weighted (Σ u²)² / (n Σ u⁴) for equal masses.
double participationRatio(const Positions& shape, const Eigen::VectorXd& vertexMass);

// The held vertices for a support (and Clamp::Rings / Normals), with `extra` added.
std::vector<bool> supportFixedVertices(const modeling::Stencils& stencils, Support support,
                                       Clamp clamp, const std::vector<bool>& extra);

// The nodal lines of a mode: the zero set of the normal displacement s_v = v_v · n̄_v (n̄_v the
// area-weighted rest vertex normal), linear over each rest face, as segments (pairs of rest-space
// points). Held vertices have s = 0, and so has every vertex where |s| ≤ kNodalFloor max |s|:
// the lines are where sand would settle, not the sign changes of a clamped corner's tiny
// oscillations. A nodal line that meets a zero vertex passes through it; one runs along an edge
// between two zeros when s changes sign across the edge (the held boundary, zero on both sides of
// its edges, is no nodal line).
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> nodalSegments(
    const modeling::Stencils& stencils, const modeling::RestState& rest, const Positions& shape);

// A point of a nodal line on a mesh edge: (1 − t) x_a + t x_b, t in [0, 1] (a vertex where the
// normal displacement is zero: a = b, t = 0), so that the line follows the mesh as it moves.
struct NodalPoint {
  int a = 0, b = 0;
  double t = 0.0;
};

// The segments of nodalSegments as edge points: nodalSegments maps each to rest-space points.
std::vector<std::pair<NodalPoint, NodalPoint>> nodalEdgeSegments(const modeling::Stencils& stencils,
                                                                 const modeling::RestState& rest,
                                                                 const Positions& shape);

}  // namespace flexure::optimize
