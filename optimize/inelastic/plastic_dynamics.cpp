#include "optimize/inelastic/plastic_dynamics.h"

#include <algorithm>

#include "optimize/solvers/energy_evaluation.h"

namespace flexure::optimize {

PlasticDynamics::PlasticDynamics(Problem& problem, TimeStepper& stepper,
                                 const PlasticityOptions& options)
    : problem_(problem),
      stepper_(stepper),
      options_(options),
      state_(initialPlasticState(problem, options)) {
  afterStep();
}

PlasticUpdate PlasticDynamics::afterStep() {
  const Eigen::MatrixXd plasticBefore = state_.plasticStrain;
  const PlasticUpdate update =
      updatePlasticStrains(problem_, state_, options_, stepper_.positions(), stepper_.xi());
  if (update.yieldedElements == 0) return update;
  TimeStepper::State after = stepper_.state();
  after.balance.plastic += update.released;
  // Newmark's a_n satisfies M a_n + C v_n + ∇E(x_n) = M g with the rest curvature of the step;
  // the update changes ∇E at x_n, so a_n moves by −M⁻¹ Δ∇E (the next step's predictor and
  // trapezoidal rule then use the forces of the new rest state, which keeps the balance).
  curvature::RestCurvatureState& rest = *problem_.terms.front()->restCurvatureState();
  const std::vector<const curvature::EnergyTerm*> bending = {problem_.terms.front().get()};
  rest.setRestCurvatures(state_.initialRest + plasticBefore);
  const Eigen::VectorXd before = energyGradient(bending, after.x, after.xi).gradient;
  rest.setRestCurvatures(state_.initialRest + state_.plasticStrain);
  const Eigen::VectorXd change = energyGradient(bending, after.x, after.xi).gradient - before;
  const Eigen::VectorXd& mass = stepper_.masses();
  for (Eigen::Index v = 0; v < after.a.rows(); ++v)
    if (!problem_.boundary.fixedVertex[v])
      for (int c = 0; c < 3; ++c) after.a(v, c) -= change[3 * v + c] / mass[v];
  stepper_.restore(after);
  return update;
}

std::vector<int> PlasticDynamics::yieldedElements() const {
  const curvature::RestCurvatureState& rest = *problem_.terms.front()->restCurvatureState();
  std::vector<int> ids;
  for (size_t e = 0; e < state_.yielded.size(); ++e)
    if (state_.yielded[e]) ids.push_back(rest.elementId(static_cast<int>(e)));
  std::sort(ids.begin(), ids.end());
  return ids;
}

Eigen::VectorXd PlasticDynamics::vertexPlasticCurvatures() const {
  const curvature::RestCurvatureState& rest = *problem_.terms.front()->restCurvatureState();
  const Eigen::VectorXd strain = equivalentPlasticCurvatures(state_);
  const bool faces = rest.components() == 3;
  Eigen::VectorXd out = Eigen::VectorXd::Zero(problem_.stencils.vertexCount());
  for (Eigen::Index e = 0; e < strain.size(); ++e) {
    const int id = rest.elementId(static_cast<int>(e));
    for (int k = 0; k < (faces ? 3 : 2); ++k) {
      const int v = faces ? problem_.stencils.faces(id, k) : problem_.stencils.edges(id, k);
      out[v] = std::max(out[v], strain[e]);
    }
  }
  return out;
}

std::string PlasticDynamics::elementKind() const {
  return problem_.terms.front()->elementKind();
}

}  // namespace flexure::optimize
