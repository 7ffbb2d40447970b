// Fairing a region of a real mesh (modeling/fairing_region.h): flexure's nonlinear fairing, CGAL's
// linear fair on the same patch, and the measures a fairing report compares them by.
//
// flexure's fairing (Clarenz et al. 2004's Willmore flow at its limit; Botsch & Kobbelt's
// variational modeling with a real bending energy): the region's vertices move in xyz to minimize
//
//   E = E_bend(x) + E_membrane(x),
//
// E_bend one of the five energies of docs/energies.md with a flat rest curvature (a fair surface
// has no preferred curvature) on the current surface's metric (FairingMetric below), E_membrane a
// membrane on the start's triangles (curvature/membrane.h; by default `mips`, the conformal shape
// change as a barrier) so that the triangles keep their shapes and the vertices do not slide. The
// held rings keep their positions bit for bit; for midedge every ξ is free (the held rings carry
// the normals).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/membrane_energy.h"
#include "modeling/fairing_region.h"
#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

// Where the nonlinear solve starts: at the linear fair (the cotangent bi-Laplacian of the input's
// metric, solved for x, y and z: what CGAL's fair computes, here with CHOLMOD), from which Gauss–
// Newton has a smooth surface to correct; at the input; or (Best) at whichever of the two has the
// lower bending energy — the input when the linear fair fails checkFairing's triangle checks
// or, on the current metric, folds a hinge past kFoldCeilingDegrees where the input does not. The
// membrane's rest shape is the start, so it costs nothing there and the solve, which never raises
// E_bend + E_membrane, ends with E_bend no higher than at the start: with Best, no higher than the
// input's or the linear fair's.
enum class FairingStart { Best, Biharmonic, Input };
// "best" | "biharmonic" | "input"; InputError naming FairingOptions.start otherwise.
FairingStart parseFairingStart(std::string_view name);

// Whose metric the bending energy measures curvature in (curvature::CurvatureMetric).
//  Input:   the input's (areas, lengths, cotangents of the input region): an elastic energy of the
//           displacement from the input. Its minimizers remember the input's defect — a cap
//           pressed flat keeps a flat cap's metric — so they do not approach a sphere under
//           refinement (issue #15).
//  Current: the current surface's (curvature/current_metric.h): a geometric functional of the
//           surface alone, a discretization of ∫ (4H² − 2(1 − ν)K) dA with the derivatives
//           through the metric taken exactly (autodiff, as every kernel's), so its critical points
//           approximate Willmore surfaces — spheres and the Clifford torus among them. Measured by
//           scripts/bench fair-sphere (bench/fair_sphere_bench.cpp). Each edge's ℓ² / 2A is
//           capped on slivers (the secure metric: faces of angles ≥ 2.56° are unchanged).
//  CurrentExact: the current surface's without the secure metric's cap on slivers
//           (curvature/current_metric.h): the exact discretization, for comparison.
enum class FairingMetric { Input, Current, CurrentExact };
// "input" | "current" | "current-exact"; InputError naming FairingOptions.metric otherwise.
FairingMetric parseFairingMetric(std::string_view name);
// `flexure fair`'s membrane weight on the current metric (1 on the input's): the membrane pulls the
// result towards the start's triangle shapes, which on the current metric is the error that
// remains on a sphere (scripts/bench fair-sphere: midedge's error on a flattened cap at w = 1 is
// twice w = 0.1's); the angle barrier, not the membrane, keeps the triangles from collapsing.
inline constexpr double kCurrentMetricMembraneWeight = 0.1;
// The membrane's fade (FairingOptions::membraneFadeStages): each stage lowers w by this factor.
inline constexpr double kMembraneFadeFactor = 0.1;
// `flexure fair`'s fade on the current metric: w = 0.1 → 0.01. Measured (scripts/bench fair-sphere,
// midedge, levels 3/4/5): the flattened cap's max error falls from 1.2e-2 / 7.0e-3 / 3.8e-3 at
// w = 0.1 to 1.05e-2 / 5.9e-3 / 2.9e-3, and the smallest angle rises; a second stage (w = 0.001)
// gains 2–3 % more at 1.3 times the time. The noisy cap's error falls by under 6 % at any lower w:
// the membrane is not its floor.
inline constexpr int kCurrentMetricMembraneFadeStages = 1;
// The fairing's quasi-Newton chord steps on the current metric (MinimizeOptions::quasiNewton):
// its Hessian, through the metric, costs more to assemble than the input metric's, so steps on a
// kept factor pay. Measured on the bunny region (scripts/bench fair, midedge, medians of three
// runs; together with the fade's KeptFactorization): 54.3 s → 42.3 s, 9 factorizations → 6 (5
// Newton steps → 3 at w = 0.1, 2 at w = 0.01), the same result. On the input's metric they change
// nothing worth a default (6 factorizations → 5, 24.1 s → 24.6 s: one run each, not side by side,
// so the times compare only roughly).
inline constexpr bool kCurrentMetricQuasiNewton = true;
// The fairing on the current metric keeps JᵀJ after an indefinite Hessian
// (MinimizeOptions::keepGaussNewton): there most Newton steps meet one (b9_mesh's holes: 109 of
// 116), each then factored twice. Measured (the fairing on the current metric, defaults otherwise,
// three runs of the binaries with and without it in turn, medians of the wall time): b9_mesh's
// holes 5.57 s → 0.82 times that (257 factorizations → 188), lion-head's all-interior 12.66 s →
// 0.78 times that (18 → 12); the same results (E_midedge to 5 digits, smallest angle to 1e-8
// degrees); the bunny region 6 factorizations either way (20 iterations against 19: few of its
// Hessians are indefinite).
inline constexpr bool kCurrentMetricKeepGaussNewton = true;
// The membrane's rest triangle shapes: the start's (the default: the membrane costs nothing at
// the start and holds the triangles against sliding) or the input's (noisy or flattened shapes
// included).
enum class FairingShape { Input, Start };

struct FairingOptions {
  curvature::BendingOptions bending;  // its restCurvature is ignored: fairing's is flat
  curvature::MembraneModel membrane = curvature::MembraneModel::Mips;
  double membraneWeight =
      1.0;  // w below (kCurrentMetricMembraneWeight advised on the current metric)
  FairingStart start = FairingStart::Best;
  FairingMetric metric = FairingMetric::Input;
  FairingShape membraneShape = FairingShape::Start;
  // The membrane fades as the solve converges: after the solve at w, this many further solves at
  // w·kMembraneFadeFactor^k (k = 1, 2, …), each started at the previous result with the same
  // membrane rest shape and barriers. The membrane holds the triangles while the surface moves
  // far; once it has arrived, its pull towards the start's shapes (the error it leaves) is lowered
  // and the angle barrier alone keeps the triangles. A stage that does not converge or fails
  // checkFairing's checks is dropped and ends the fade: the result is the last converged stage's.
  int membraneFadeStages = 0;
  // The angle barrier (curvature/membrane.h) on the faces touching a moving vertex, its floor
  // kAngleFloorMarginDegrees above the smallest-angle rule's limit, so that the result keeps the
  // rule (see kSliverToleranceDegrees). Stiffness k_B, band kAngleBarrierBandDegrees.
  bool angleBarrier = true;
  // On the current metric, the dihedral barrier (curvature/dihedral_barrier.h) on every hinge
  // with a moving vertex: no hinge folds past kFoldCeilingDegrees (or, folded sharper at the
  // start, further than the band beyond it), so that the result passes the
  // triangle check. The geometric energy needs it: a discrete bending energy prices a fold
  // finitely, and the membrane does not see a face swing over its edge. Stiffness k_B, band
  // kFoldBarrierBandDegrees.
  bool foldBarrier = true;
  MinimizeOptions solver;  // dof and start are fairing's own: xyz, from `start`
};

// The options a fairing on `metric` starts from. On the current metric: the membrane weight
// kCurrentMetricMembraneWeight faded in kCurrentMetricMembraneFadeStages stages, quasi-Newton chord
// steps (kCurrentMetricQuasiNewton), JᵀJ kept after an indefinite Hessian
// (kCurrentMetricKeepGaussNewton), and cotan's
// barycentric vertex area — the mixed Voronoi area switches formula where a current angle crosses
// 90°, and on the current metric that kink stalls Newton (the shark's holes: 200 iterations). On
// the input's: w = 1 and the Voronoi area.
inline FairingOptions defaultFairingOptions(FairingMetric metric) {
  FairingOptions options;
  options.metric = metric;
  if (metric != FairingMetric::Input) {
    options.membraneWeight = kCurrentMetricMembraneWeight;
    options.membraneFadeStages = kCurrentMetricMembraneFadeStages;
    options.solver.quasiNewton = kCurrentMetricQuasiNewton;
    options.solver.keepGaussNewton = kCurrentMetricKeepGaussNewton;
    options.bending.vertexArea = curvature::VertexArea::Barycentric;
  }
  return options;
}

// The membrane of weight w, bending stiffness k_B, mean rest edge length ℓ̄ of the region:
//   mips, conformal: k_S = w k_B                (shapes kept, sizes free; mips the default:
//                                               measured on three_peaks' all-interior, conformal
//                                               let 4 faces turn over, mips none);
//   stvk:      Y = w k_B / ℓ̄² (ν = 0.3);        springs: k_L = w k_B / ℓ̄,  k_A = w k_B / ℓ̄².
// A triangle's change of shape (conformal: q → 1 as it collapses, mips: p → ∞) or a strain ε of one
// triangle (stvk, springs: ≈ w k_B ε²) then weighs like the bending energy of a triangle curved at
// radius ℓ̄, ≈ k_B: w weighs the triangles' quality against bending at the mesh's own scale. All are
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
  // |∇E| (2-norm over the free unknowns: the moving vertices' x, y, z and, for midedge, every ξ)
  // of E = E_bend + E_membrane at the start and at the result.
  double startGradientNorm = 0.0, finalGradientNorm = 0.0;
  // The membrane weight of the solve the result is from, and the fade stages kept to reach it
  // (FairingOptions::membraneFadeStages; fewer when a stage was dropped).
  double membraneWeight = 0.0;
  int membraneFadeStages = 0;
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
  // The same on the current metric: the geometric energy of the surface alone, independent of
  // the input's triangles (what FairingOptions.metric Current minimizes).
  std::vector<EnergyMeasure> bendingCurrent;
  TriangleQuality quality;
  double maxDisplacement = 0.0;  // max |x_v − x_v(input)| over the patch
};

// A fairing result is called converged only when it passes these checks (besides the solver's own
// stopping rule, which can stop at a stall: Ceres' parameter tolerance on a mesh with folded
// triangles stopped with |∇E| larger than at the start):
//  - gradient (flexure's fairing only): |∇E(result)| ≤ kFairingGradientReduction · |∇E(start)|,
//    the 2-norms of FairingResult: the solve reached a stationary point (or |∇E(result)| ≤
//    kFairingGradientFloor, the solver's default gradient tolerance: a start that was already
//    stationary has nothing to reduce);
//  - triangles (either method): no face touching a moving vertex is degenerate in the result
//    (2A ≤ kDegenerateFlatness · (its longest edge)²: flattened onto a line or a point) or
//    inverted: its normal n = (x1 − x0) × (x2 − x0) has turned over against the input's
//    (n · n_input ≤ 0) and against a neighbouring face's in the result (n · n_g ≤ 0) — both, since
//    a smooth result may turn a region far from the input (a filled hole's input is CGAL's flat
//    patch; on a cone the faired fill turns its faces near the rim by more than 90°), and a crease
//    of the input may sharpen past 90° without any triangle turning over.
// The smallest angle of those faces is reported against the input's and not judged here.
inline constexpr double kFairingGradientReduction = 1e-3;
// The smallest-angle rule (issue #15): a faired region's smallest angle may fall at most this far
// below the smaller of the input's and CGAL's fair's.
inline constexpr double kSliverToleranceDegrees = 1.0;
inline constexpr double kAngleFloorMarginDegrees = 0.25;
inline constexpr double kAngleBarrierBandDegrees = 2.0;
// The dihedral barrier's ceiling: below the triangle check's 90° turn against a neighbour.
inline constexpr double kFoldCeilingDegrees = 85.0;
inline constexpr double kFoldBarrierBandDegrees = 10.0;
inline constexpr double kFairingGradientFloor = 1e-10;
inline constexpr double kDegenerateFlatness = 1e-6;

struct DegenerateFace {
  int vertices[3];        // the face's vertices, in the mesh's numbering (patch.inputVertex)
  double flatness = 0.0;  // 2A / (longest edge)² in the result
};

struct InvertedFace {
  int vertices[3];
  double inputTurnDegrees = 0.0;      // angle between its normal and the input's
  double neighbourTurnDegrees = 0.0;  // largest angle between its normal and a neighbour's
};

struct FairingChecks {
  bool gradientChecked = false;  // false for CGAL's fair, which has no energy to check
  double startGradientNorm = 0.0, finalGradientNorm = 0.0;
  std::vector<DegenerateFace> degenerateFaces;
  std::vector<InvertedFace> invertedFaces;
  double inputMinAngleDegrees = 0.0, resultMinAngleDegrees = 0.0;

  bool gradientPassed() const;
  bool trianglesPassed() const { return degenerateFaces.empty() && invertedFaces.empty(); }
  bool passed() const { return gradientPassed() && trianglesPassed(); }
  // The failed checks in words (with the threshold), "" when all passed.
  std::string failure() const;
};

// The checks of `positions` (the patch's vertices) against the input patch; `solve` is flexure's
// fairing result (nullptr for CGAL's fair: no gradient check).
FairingChecks checkFairing(const modeling::FairingPatch& patch, const Positions& positions,
                           const FairingResult* solve);

// The measures of `positions` (the patch's vertices) against the input patch. The five energies
// share `material`'s stiffness and, where the discretization takes one, its Poisson's ratio
// (hinge and cotan are ν = 1 models); midedge's ξ are minimized for the positions.
FairingMeasures measureFairing(const modeling::FairingPatch& patch, const Positions& positions,
                               const curvature::BendingOptions& material);

// The smallest-angle rule (issue #15), beside checkFairing's gradient and triangle checks: the
// faired region's faces (those touching a moving vertex) may not have a smallest angle more than
// kSliverToleranceDegrees below min(the input's, CGAL's fair's) — a fair surface bought with
// slivers is no better surface to work on, and CGAL's linear fair (the same held rings, the
// input's cotangent weights) shows what fairing the region costs in angle. flexure's fairing
// keeps it by the angle barrier (FairingOptions::angleBarrier).
struct SliverCheck {
  double inputDegrees = 0.0, cgalDegrees = 0.0, resultDegrees = 0.0;
  double limitDegrees() const;
  bool passed() const { return resultDegrees >= limitDegrees(); }
  // "smallest-angle check: …" with the three angles and the limit.
  std::string failure() const;
};

enum class FairingMethod { Flexure, Cgal };
// "flexure" | "cgal"; InputError naming FairingOptions.method otherwise.
FairingMethod parseFairingMethod(std::string_view name);

// A region faired by `method`, with CGAL's fair always beside it (the result with Cgal, the
// smallest-angle rule's baseline otherwise), measured (measureFairing with `material`) and
// checked.
struct FairingOutcome {
  FairingMeasures before, cgalMeasures, after;
  Positions patchAfter;  // the method's result (the patch's vertices)
  Positions cgalPatch;
  std::optional<FairingResult> fairing;  // flexure's solve (none with Cgal)
  double solveSeconds = 0.0;             // the method's own
  double cgalSeconds = 0.0;
  FairingChecks checks;
  SliverCheck slivers;
  bool sliversPassed = false;    // the rule judges flexure's result only (always true with Cgal)
  bool solverConverged = false;  // true with Cgal

  // Converged: the solver's own stop, the checks and — unless `allowSlivers` — the rule.
  bool converged(bool allowSlivers) const;
  // The failed checks in words, each with its numbers and threshold ("" when all passed).
  std::string failure(bool allowSlivers) const;
};

FairingOutcome fairAndCheck(const modeling::FairingPatch& patch, const FairingOptions& options,
                            FairingMethod method, const curvature::BendingOptions& material);

}  // namespace flexure::optimize
