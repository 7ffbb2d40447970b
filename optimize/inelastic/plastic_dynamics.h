// Shell dynamics with plasticity (issue #29; Gingold, Secord, Han, Grinspun & Zorin 2004, seed
// 002; the model in plasticity.h and docs/energies.md, "Plasticity" and "Plasticity in time").
//
// After each accepted time step the plastic update (updatePlasticStrains: one radial return per
// face, bending and membrane parts together by the combined yield) runs on the
// step's end state (x_{n+1}, ξ_{n+1}); the rest curvature and the membrane's rest metric move, so
// the elastic energy at the fixed end state drops by ΔD ≥ 0. That drop is the plastic dissipation
// D; the stepper's energy balance counts it (EnergyBalance::plastic), so that
//   K + Σ E_terms + E_gravity + B + D_damping + D − S = E(0)
// along the motion. The step itself is computed with the plastic strains of its start, P_n: the
// update lags the motion by one step (an operator split, first order in h).
//
// Across a crack (fracturing.h; seed 002 runs plasticity and fracture together: the diving board,
// the bowl) the plastic state is a property of the material, so each face of the cut mesh keeps
// the plastic strains of the face it was cut from (P_b and P_m are tensors in the face's rest
// plane: a piece of a split face, in the same plane, takes its parent's tensor in its own rest
// frame; a face the cut left whole keeps its rows bit for bit), and whether it yielded. The
// elastic rest state S̄₀ and the zero membrane rest strain are the cut mesh's own. So a hinge the
// cut adds inside a split face (between two of its pieces) takes the rest angle its faces' tensors
// read, θ̄ = θ̄⁰ + ½ (c_e^f · P_f + c_e^g · P_g) with θ̄⁰ = 0 there: the parent's plastic curvature
// continued across it; an edge on the crack is a boundary and has no hinge. The dissipation D
// carries over, as does the balance's P (the cut keeps the stepper's balance).

#pragma once

#include <string>
#include <vector>

#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/plasticity.h"
#include "optimize/problem.h"

namespace flexure::optimize {

class PlasticDynamics {
 public:
  // `problem` is the one `stepper` moves (both outlive this object; the stepper has been
  // started). A start outside the yield surface yields at once: the update runs on it too.
  // InputError as initialPlasticState (cotan, invalid options).
  PlasticDynamics(Problem& problem, TimeStepper& stepper, const PlasticityOptions& options);
  // Continues `state` (another PlasticDynamics' on the same problem, whose rest states it set) with
  // `stepper`, e.g. a new one after the pins were released: the update runs on its start.
  PlasticDynamics(Problem& problem, TimeStepper& stepper, const PlasticityOptions& options,
                  PlasticState state);

  // Continues on `cut` (it outlives this object), the problem of the mesh a crack cut from this
  // one's, faceOrigin[f'] the face of this one's mesh that its face f' lies in
  // (modeling::CrackCut::faceOrigin): the plastic state carried per face as the header says, the
  // cut problem's rest curvature and rest metric set to it. The stepper is then to be followed
  // (follow) to the one built for `cut`.
  void carryAcrossCut(Problem& cut, const std::vector<int>& faceOrigin);

  // Continues with `stepper` instead (one that took over the state of the last, e.g. after pins
  // were released: FracturingDynamics::releasePins); the plastic state carries over.
  void follow(TimeStepper& stepper) { stepper_ = &stepper; }

  // The plastic update on the stepper's current state. When an element yields, the released
  // energy joins the stepper's balance and the stepper is restored to its own state, which
  // recomputes its energies with the moved rest curvature and rest metric and drops its kept
  // factor of the step's Hessian (assembled with the old ones).
  PlasticUpdate afterStep();

  const PlasticState& state() const { return state_; }
  double dissipation() const { return state_.dissipation; }
  // The mesh faces whose bending part carries a plastic strain (every energy's, the hinge's
  // included: curvature/hinge_face_tensors.h), ascending; empty without a yield curvature.
  std::vector<int> yieldedElements() const;
  std::string elementKind() const { return "face"; }
  int elementCount() const { return static_cast<int>(state_.yielded.size()); }
  // The mesh faces whose membrane part carries a plastic strain, ascending; empty without a yield
  // strain.
  std::vector<int> yieldedFaces() const;
  int membraneFaceCount() const { return static_cast<int>(state_.membraneYielded.size()); }
  // #F: per mesh face its equivalentPlasticCurvatures (0 for a face without a bending element,
  // and without a yield curvature).
  Eigen::VectorXd facePlasticCurvatures() const;
  // #F: per mesh face its equivalentPlasticStrains (0 without a yield strain).
  Eigen::VectorXd facePlasticStrains() const;
  // #F: the plastic measure of each face — facePlasticCurvatures with a yield curvature alone,
  // facePlasticStrains with a yield strain alone, and with both the larger of the two divided by
  // its yield value (κ_p/κ_y, ε_p/ε_y: dimensionless).
  Eigen::VectorXd facePlasticMeasure() const;
  // #V: per vertex the largest of its faces' facePlasticCurvatures, facePlasticStrains and
  // facePlasticMeasure (what the plastic render style colours).
  Eigen::VectorXd vertexPlasticCurvatures() const;
  Eigen::VectorXd vertexPlasticStrains() const;
  Eigen::VectorXd vertexPlasticMeasure() const;

 private:
  Problem* problem_;
  TimeStepper* stepper_;
  PlasticityOptions options_;
  PlasticState state_;
  curvature::EnergyTerm* membrane_ = nullptr;  // the term whose rest metric moves (yield strain)

  // Sets the bending term's rest curvature to S̄₀ + bending and the membrane's rest strain to
  // P₀ + membrane, for the parts `moved` names.
  void setRestStates(const std::vector<const curvature::EnergyTerm*>& moved,
                     const Eigen::MatrixXd& bending, const Eigen::MatrixXd& membrane);
};

}  // namespace flexure::optimize
