// Plasticity of the bending part (Gingold, Secord, Han, Grinspun, Zorin 2004, seed 002; the model
// and its formulas in docs/energies.md, "Plasticity"): per element a plastic strain P moves the
// rest curvature, S̄ = S̄₀ + P (a face's shape operator; a hinge's angle measure φ(θ̄)). With the
// bending strain E = S − S̄₀ and linear kinematic hardening γ, A = E − (1 + γ) P and
// ‖A‖²_* = Tr(A²) + (Tr A)²; an element yields when ‖A‖²_* / (2 κ_y²) > 1 and returns radially:
// A ← s A, ΔP = (1 − s) A / (1 + γ), s = 1 / √(‖A‖²_* / (2 κ_y²)).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

struct PlasticityOptions {
  std::optional<double> yieldCurvature;  // κ_y (1 / length); empty: bending stays elastic
  // ε_y, the membrane's yield strain: not modelled yet (validate refuses it).
  std::optional<double> yieldStrain;
  double hardening = 0.0;  // γ ≥ 0, linear kinematic hardening

  bool enabled() const { return yieldCurvature.has_value() || yieldStrain.has_value(); }
  // InputError naming the field: a yield value that is not positive and finite, γ < 0, a yield
  // strain (the membrane stays elastic).
  void validate() const;
};

// The plastic state of a problem's bending term, per element in the term's order.
struct PlasticState {
  Eigen::MatrixXd initialRest;    // S̄₀ (or φ(θ̄₀)), #elements by components
  Eigen::MatrixXd plasticStrain;  // P, the same shape
  // 2 h̄_e = 2 (Ā_f + Ā_g) / (3 ℓ̄_e) per hinge: the length over which its angle measures curvature
  // (θ_e ≈ κ 2 h̄_e across an edge normal to a cylinder's axis); empty for face energies.
  Eigen::VectorXd hingeLength;
  std::vector<bool> yielded;  // elements that have ever yielded
  double dissipation = 0.0;   // Σ of the elastic energy each update released at fixed positions
};

// The plastic state of `problem`'s bending term before any yield (P = 0). Throws InputError when
// the term has no rest curvature to move (cotan: one mean curvature per vertex, whose rest value
// cannot carry a plastic strain tensor) or `options` are invalid.
PlasticState initialPlasticState(Problem& problem, const PlasticityOptions& options);

struct PlasticUpdate {
  int yieldedElements = 0;      // elements that returned to the yield surface in this update
  double largestIncrement = 0;  // max over elements of ‖ΔP‖_* (or |ΔP| for a hinge, in curvature)
  double released = 0;          // elastic energy the update released at fixed positions
};

// Per element, its plastic strain as a curvature, √(‖P‖²_* / 2) (a hinge's P divided by 2 h̄_e):
// a plate bent cylindrically past κ_y and released keeps (κ − κ_y)/(1 + γ), which this equals.
Eigen::VectorXd equivalentPlasticCurvatures(const PlasticState& state);

// Returns every element outside the yield surface at (x, ξ) to it, moves the bending term's rest
// curvature to S̄₀ + P and adds the released energy to state.dissipation.
PlasticUpdate updatePlasticStrains(Problem& problem, PlasticState& state,
                                   const PlasticityOptions& options, const Positions& x,
                                   const Eigen::VectorXd& xi);

// Quasi-static forming: the held values reached in `loadSteps` equal steps from rest, each a static
// solve followed by plastic updates (solve, update, until no element's ‖ΔP‖ exceeds
// `tolerance` κ_y); then, when `release`, only the three vertices of the face nearest the
// centroid stay held (with the midedge ξ free) and the same loop relaxes: the sprung-back shape.
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
  int yieldedElements = 0;  // elements that ever yielded
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
