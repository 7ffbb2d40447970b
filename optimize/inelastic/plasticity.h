// Plasticity of thin shells (Gingold, Secord, Han, Grinspun, Zorin 2004, seed 002; the model and
// its formulas in docs/energies.md, "Plasticity"). Bending: per face a plastic strain P_b moves
// the rest curvature, S̄ = S̄₀ + P_b (the face's shape operator; for the hinge the tensor its edges'
// angle measures read as, curvature/hinge_face_tensors.h, whose rest angles it moves), with
// the bending strain E_b = S − S̄₀. Membrane (stvk): per face a plastic Green strain P_m moves the
// rest metric, Ā = I + 2 P_m (squared rest edge lengths ℓ̄² + 2 ūᵀ P_m ū), with the membrane strain
// E_m = ε = ½(FᵀF − I). With linear kinematic hardening γ, A = E − (1 + γ) P per part and
// ‖A‖²_* = Tr(A²) + (Tr A)²; a face yields when f = ‖A_m‖²_* / (2 ε_y²) + ‖A_b‖²_* / (2 κ_y²) > 1
// (a part without its yield value is elastic) and both parts return radially with one factor:
// A ← s A, ΔP = (1 − s) A / (1 + γ), s = 1 / √f.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

struct PlasticityOptions {
  std::optional<double> yieldCurvature;  // κ_y (1 / length); empty: bending stays elastic
  // ε_y, the membrane's yield strain (Green strain; stvk only); empty: the membrane stays elastic.
  std::optional<double> yieldStrain;
  double hardening = 0.0;  // γ ≥ 0, linear kinematic hardening

  bool enabled() const { return yieldCurvature.has_value() || yieldStrain.has_value(); }
  // What PlasticDynamics::vertexPlasticMeasure is, in words for a legend: the plastic curvature
  // (1 / length) with κ_y alone, the membrane's Green plastic strain with ε_y alone, the strain
  // over its yield value with both.
  std::string measureName() const;
  // InputError naming the field: a yield value that is not positive and finite, γ < 0.
  void validate() const;
};

// The plastic state of a problem's bending term, per face in its rest curvature's order
// (RestCurvatureState), and of its membrane, per face in the membrane term's order. A part without
// its yield value is empty (0 rows).
struct PlasticState {
  Eigen::MatrixXd initialRest;    // S̄₀, #faces by 3: (a, b, c) of [[a, b], [b, c]]
  Eigen::MatrixXd plasticStrain;  // P_b, the same shape
  std::vector<bool> yielded;      // faces whose bending part has ever yielded
  // The membrane's rest strain as built (zero) and P_m, #faces by 3: (a, b, c) of
  // [[a, b], [b, c]] in each face's rest frame.
  Eigen::MatrixXd membraneInitialRest;
  Eigen::MatrixXd membranePlasticStrain;
  std::vector<bool> membraneYielded;  // faces whose membrane part has ever yielded
  double dissipation = 0.0;  // Σ of the elastic energy each update released at fixed positions
};

// The plastic state of `problem` before any yield (P = 0): the bending part with a yield
// curvature, the membrane part with a yield strain. Throws InputError when `options` are invalid
// or give no yield value, when the bending term has no rest curvature to move (cotan: one mean
// curvature per vertex, whose rest value cannot carry a plastic strain tensor), or when a yield
// strain comes without a stvk membrane.
PlasticState initialPlasticState(Problem& problem, const PlasticityOptions& options);

struct PlasticUpdate {
  int yieldedElements = 0;            // faces whose bending part returned to the yield surface
  double largestIncrement = 0;        // max over them of ‖ΔP_b‖_*/√2
  double released = 0;                // elastic energy the update released at fixed positions
  int yieldedFaces = 0;               // faces whose membrane part returned
  double largestStrainIncrement = 0;  // max over faces of ‖ΔP_m‖_*/√2
};

// Per face, its plastic strain as a curvature, √(‖P‖²_* / 2):
// a plate bent cylindrically past κ_y and released keeps (κ − κ_y)/(1 + γ), which this equals.
Eigen::VectorXd equivalentPlasticCurvatures(const PlasticState& state);
// Per membrane face, its plastic strain as a Green strain, √(‖P_m‖²_* / 2): a strip stretched past
// ε_y with its width held and released keeps (ε − ε_y)/(1 + γ), which this equals.
Eigen::VectorXd equivalentPlasticStrains(const PlasticState& state);

// Returns every element outside the yield surface at (x, ξ) to it, moves the bending term's rest
// curvature to S̄₀ + P_b and the membrane's rest strain to P_m, and adds the released energy to
// state.dissipation.
PlasticUpdate updatePlasticStrains(Problem& problem, PlasticState& state,
                                   const PlasticityOptions& options, const Positions& x,
                                   const Eigen::VectorXd& xi);

// Quasi-static forming: the held values reached in `loadSteps` equal steps from rest, each a static
// solve followed by plastic updates (solve, update, until no element's ‖ΔP_b‖ exceeds
// `tolerance` κ_y and no face's ‖ΔP_m‖ `tolerance` ε_y); then, when `release`, only the three
// vertices of the face nearest the centroid stay held (with the midedge ξ free) and the same loop
// relaxes: the sprung-back shape. With a membrane part that face is first placed at its plastic
// rest metric (F = R (I + 2 P_m)^½ D̄⁻¹, R the rotation of its formed F, its centroid kept), so the
// pins remove the rigid motions and hold no strain.
struct FormingOptions {
  int loadSteps = 1;
  bool release = false;
  int maxUpdatesPerStep = 200;
  double tolerance = 1e-9;
  void validate() const;  // InputError naming the field
};

struct FormingReport {
  bool converged = false;  // every solve converged and every step's updates settled
  int solves = 0;
  int yieldedElements = 0;  // bending elements that ever yielded
  int yieldedFaces = 0;     // faces whose membrane part ever yielded
  double dissipation = 0.0;
  std::vector<int> releasePins;  // the vertices held in the release (empty without one)
  MinimizeReport lastSolve;
};

struct FormingResult {
  Positions positions;  // #V by 3
  Eigen::VectorXd xi;   // #E (midedge), else empty
  PlasticState state;
  FormingReport report;
};

// Throws InputError for what initialPlasticState refuses and for a linearized solve (its energy
// is linearized about a rest state plasticity moves). `problem`'s rest curvature is left at the
// formed state's.
FormingResult formPlastically(Problem& problem, const PlasticityOptions& plasticity,
                              const FormingOptions& forming, const MinimizeOptions& options);

}  // namespace flexure::optimize
