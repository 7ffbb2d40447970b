#include "optimize/inelastic/plastic_dynamics.h"

#include <algorithm>
#include <utility>

#include "optimize/assembly/energy_evaluation.h"

namespace flexure::optimize {
namespace {

// Per vertex the largest of `values` over the mesh faces (`ids`) it belongs to.
Eigen::VectorXd vertexMaxima(const modeling::Stencils& stencils, const Eigen::VectorXd& values,
                             const std::vector<int>& ids) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(stencils.vertexCount());
  for (Eigen::Index e = 0; e < values.size(); ++e)
    for (int k = 0; k < 3; ++k) {
      const int v = stencils.faces(ids[static_cast<size_t>(e)], k);
      out[v] = std::max(out[v], values[e]);
    }
  return out;
}

}  // namespace

PlasticDynamics::PlasticDynamics(Problem& problem, TimeStepper& stepper,
                                 const PlasticityOptions& options)
    : PlasticDynamics(problem, stepper, options, initialPlasticState(problem, options)) {}

PlasticDynamics::PlasticDynamics(Problem& problem, TimeStepper& stepper,
                                 const PlasticityOptions& options, PlasticState state)
    : problem_(problem), stepper_(&stepper), options_(options), state_(std::move(state)) {
  if (options_.yieldStrain)
    for (size_t k = 1; k < problem_.terms.size() && membrane_ == nullptr; ++k)
      if (problem_.terms[k]->restMetricState() != nullptr) membrane_ = problem_.terms[k].get();
  afterStep();
}

void PlasticDynamics::setRestStates(const std::vector<const curvature::EnergyTerm*>& moved,
                                    const Eigen::MatrixXd& bending,
                                    const Eigen::MatrixXd& membrane) {
  for (const curvature::EnergyTerm* term : moved) {
    if (term == problem_.terms.front().get())
      problem_.terms.front()->restCurvatureState()->setRestCurvatures(state_.initialRest + bending);
    else
      membrane_->restMetricState()->setRestStrains(state_.membraneInitialRest + membrane);
  }
}

PlasticUpdate PlasticDynamics::afterStep() {
  const Eigen::MatrixXd bendingBefore = state_.plasticStrain;
  const Eigen::MatrixXd membraneBefore = state_.membranePlasticStrain;
  const PlasticUpdate update =
      updatePlasticStrains(problem_, state_, options_, stepper_->positions(), stepper_->xi());
  if (update.yieldedElements == 0 && update.yieldedFaces == 0) return update;
  TimeStepper::State after = stepper_->state();
  after.balance.plastic += update.released;
  // Newmark's a_n satisfies M a_n + C v_n + ∇E(x_n) = M g with the rest state of the step; the
  // update changes ∇E at x_n, so a_n moves by −M⁻¹ Δ∇E (the next step's predictor and
  // trapezoidal rule then use the forces of the new rest state, which keeps the balance).
  std::vector<const curvature::EnergyTerm*> moved;
  if (update.yieldedElements > 0) moved.push_back(problem_.terms.front().get());
  if (update.yieldedFaces > 0) moved.push_back(membrane_);
  setRestStates(moved, bendingBefore, membraneBefore);
  const Eigen::VectorXd before = energyGradient(moved, after.x, after.xi).gradient;
  setRestStates(moved, state_.plasticStrain, state_.membranePlasticStrain);
  const Eigen::VectorXd change = energyGradient(moved, after.x, after.xi).gradient - before;
  const Eigen::VectorXd& mass = stepper_->masses();
  for (Eigen::Index v = 0; v < after.a.rows(); ++v)
    if (!problem_.boundary.fixedVertex[v])
      for (int c = 0; c < 3; ++c) after.a(v, c) -= change[3 * v + c] / mass[v];
  stepper_->restore(after);
  return update;
}

std::vector<int> PlasticDynamics::yieldedElements() const {
  std::vector<int> ids;
  for (size_t e = 0; e < state_.yielded.size(); ++e)
    if (state_.yielded[e])
      ids.push_back(problem_.terms.front()->restCurvatureState()->elementId(static_cast<int>(e)));
  std::sort(ids.begin(), ids.end());
  return ids;
}

std::vector<int> PlasticDynamics::yieldedFaces() const {
  std::vector<int> ids;
  for (size_t f = 0; f < state_.membraneYielded.size(); ++f)
    if (state_.membraneYielded[f])
      ids.push_back(membrane_->restMetricState()->elementId(static_cast<int>(f)));
  std::sort(ids.begin(), ids.end());
  return ids;
}

Eigen::VectorXd PlasticDynamics::vertexPlasticCurvatures() const {
  if (state_.yielded.empty()) return Eigen::VectorXd::Zero(problem_.stencils.vertexCount());
  const curvature::RestCurvatureState& rest = *problem_.terms.front()->restCurvatureState();
  std::vector<int> ids(state_.yielded.size());
  for (size_t e = 0; e < ids.size(); ++e) ids[e] = rest.elementId(static_cast<int>(e));
  return vertexMaxima(problem_.stencils, equivalentPlasticCurvatures(state_), ids);
}

Eigen::VectorXd PlasticDynamics::vertexPlasticStrains() const {
  if (membrane_ == nullptr) return Eigen::VectorXd::Zero(problem_.stencils.vertexCount());
  const curvature::RestMetricState& metric = *membrane_->restMetricState();
  std::vector<int> ids(state_.membraneYielded.size());
  for (size_t f = 0; f < ids.size(); ++f) ids[f] = metric.elementId(static_cast<int>(f));
  return vertexMaxima(problem_.stencils, equivalentPlasticStrains(state_), ids);
}

Eigen::VectorXd PlasticDynamics::vertexPlasticMeasure() const {
  if (!options_.yieldStrain) return vertexPlasticCurvatures();
  if (!options_.yieldCurvature) return vertexPlasticStrains();
  return (vertexPlasticCurvatures() / *options_.yieldCurvature)
      .cwiseMax(vertexPlasticStrains() / *options_.yieldStrain);
}

}  // namespace flexure::optimize
