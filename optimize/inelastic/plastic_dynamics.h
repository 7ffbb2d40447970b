// Shell dynamics with plasticity (issue #29; Gingold, Secord, Han, Grinspun & Zorin 2004, seed
// 002; the model in plasticity.h and docs/energies.md, "Plasticity" and "Plasticity in time").
//
// After each accepted time step the plastic update (updatePlasticStrains: the radial return per
// face or hinge) runs on the step's end state (x_{n+1}, ξ_{n+1}); the rest curvature moves, so the
// elastic energy at the fixed end state drops by ΔD ≥ 0. That drop is the plastic dissipation D;
// the stepper's energy balance counts it (EnergyBalance::plastic), so that
//   K + Σ E_terms + E_gravity + B + D_damping + D − S = E(0)
// along the motion. The step itself is computed with the plastic strain of its start, P_n: the
// update lags the motion by one step (an operator split, first order in h).
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

  // The plastic update on the stepper's current state. When an element yields, the released
  // energy joins the stepper's balance and the stepper is restored to its own state, which
  // recomputes its energies with the moved rest curvature and drops its kept factor of the step's
  // Hessian (assembled with the old one).
  PlasticUpdate afterStep();

  const PlasticState& state() const { return state_; }
  double dissipation() const { return state_.dissipation; }
  // The mesh elements ("face" or "edge", elementKind()) that carry a plastic strain, ascending.
  std::vector<int> yieldedElements() const;
  std::string elementKind() const;
  // #V: per vertex the largest equivalentPlasticCurvatures of the faces or edges it belongs to.
  Eigen::VectorXd vertexPlasticCurvatures() const;
  int elementCount() const { return static_cast<int>(state_.yielded.size()); }

 private:
  Problem& problem_;
  TimeStepper& stepper_;
  PlasticityOptions options_;
  PlasticState state_;
};

}  // namespace flexure::optimize
