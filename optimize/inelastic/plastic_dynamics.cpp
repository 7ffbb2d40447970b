#include "optimize/inelastic/plastic_dynamics.h"

#include <algorithm>
#include <utility>

#include "curvature/face_frame.h"
#include "optimize/assembly/energy_evaluation.h"

namespace flexure::optimize {
namespace {

// Per mesh face the largest value of the elements on it (`values[e]` of mesh face ids[e]); 0 on
// a face without one.
Eigen::VectorXd faceValues(const modeling::Stencils& stencils, const Eigen::VectorXd& values,
                           const std::vector<int>& ids) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(stencils.faceCount());
  for (Eigen::Index e = 0; e < values.size(); ++e) {
    double& face = out[ids[static_cast<size_t>(e)]];
    face = std::max(face, values[e]);
  }
  return out;
}

// Per vertex the largest of the per-face `values` over the faces it belongs to.
Eigen::VectorXd vertexMaxima(const modeling::Stencils& stencils, const Eigen::VectorXd& values) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(stencils.vertexCount());
  for (int f = 0; f < stencils.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = stencils.faces(f, k);
      out[v] = std::max(out[v], values[f]);
    }
  return out;
}

// The membrane term whose rest metric a yield strain moves (the first after the bending term with
// one); null without.
curvature::EnergyTerm* membraneTermOf(Problem& problem) {
  for (size_t k = 1; k < problem.terms.size(); ++k)
    if (problem.terms[k]->restMetricState() != nullptr) return problem.terms[k].get();
  return nullptr;
}

// Mesh face f's rest triangle, and its rest frame (curvature/face_frame.h: the frame of the
// plastic strains' (a, b, c)).
Eigen::Matrix3d restTriangle(const Problem& problem, int f) {
  Eigen::Matrix3d corners;
  for (int k = 0; k < 3; ++k)
    corners.row(k) = problem.rest.positions.row(problem.stencils.faces(f, k));
  return corners;
}
curvature::FaceFrame restFrame(const Eigen::Matrix3d& corners) {
  return curvature::FaceFrame::of(corners.row(0), corners.row(1), corners.row(2));
}

// A symmetric tensor T = [[a, b], [b, c]] in frame `from`, in frame `to` of a face in the same
// plane: T' = Qᵀ T Q, Q_ij = from_i · to_j (the components of `to`'s axes in `from`), so that
// wᵀ T w is the same form of an in-plane vector w in either frame.
Eigen::RowVector3d inFrame(const Eigen::RowVector3d& t, const curvature::FaceFrame& from,
                           const curvature::FaceFrame& to) {
  Eigen::Matrix2d q, tensor;
  q << from.u.dot(to.u), from.u.dot(to.v), from.v.dot(to.u), from.v.dot(to.v);
  tensor << t[0], t[1], t[1], t[2];
  const Eigen::Matrix2d moved = q.transpose() * tensor * q;
  return {moved(0, 0), 0.5 * (moved(0, 1) + moved(1, 0)), moved(1, 1)};
}

// One part's per-element rows (plastic strains in their faces' rest frames) and yield flags,
// carried from the elements of `from` (mesh faces fromFace[e]) to those of `to` (toFace[e']): an
// element takes the row of the element its face was cut from (faceOrigin), in its own frame —
// bit for bit when the face is the same rest triangle — and zero, unyielded, when that face had
// no element.
void carryPart(const Problem& from, const std::vector<int>& fromFace, const Problem& to,
               const std::vector<int>& toFace, const std::vector<int>& faceOrigin,
               const Eigen::MatrixXd& rows, const std::vector<bool>& yielded,
               Eigen::MatrixXd& carriedRows, std::vector<bool>& carriedYielded) {
  std::vector<int> elementOfFace(static_cast<size_t>(from.stencils.faceCount()), -1);
  for (size_t e = 0; e < fromFace.size(); ++e) elementOfFace[fromFace[e]] = static_cast<int>(e);
  for (size_t k = 0; k < toFace.size(); ++k) {
    const int face = toFace[k], parentFace = faceOrigin[static_cast<size_t>(face)];
    const int parent = elementOfFace[static_cast<size_t>(parentFace)];
    if (parent < 0) continue;
    const Eigen::Matrix3d before = restTriangle(from, parentFace), after = restTriangle(to, face);
    const Eigen::Index row = static_cast<Eigen::Index>(k);
    carriedRows.row(row) = before == after
                               ? Eigen::RowVector3d(rows.row(parent))
                               : inFrame(rows.row(parent), restFrame(before), restFrame(after));
    carriedYielded[k] = yielded[static_cast<size_t>(parent)];
  }
}

// The mesh face of each of `count` elements.
template <class RestState>
std::vector<int> elementFaces(const RestState& state, Eigen::Index count) {
  std::vector<int> faces(static_cast<size_t>(count));
  for (size_t e = 0; e < faces.size(); ++e) faces[e] = state.elementId(static_cast<int>(e));
  return faces;
}

}  // namespace

PlasticDynamics::PlasticDynamics(Problem& problem, TimeStepper& stepper,
                                 const PlasticityOptions& options)
    : PlasticDynamics(problem, stepper, options, initialPlasticState(problem, options)) {}

PlasticDynamics::PlasticDynamics(Problem& problem, TimeStepper& stepper,
                                 const PlasticityOptions& options, PlasticState state)
    : problem_(&problem), stepper_(&stepper), options_(options), state_(std::move(state)) {
  if (options_.yieldStrain) membrane_ = membraneTermOf(*problem_);
  afterStep();
}

void PlasticDynamics::carryAcrossCut(Problem& cut, const std::vector<int>& faceOrigin) {
  PlasticState carried = initialPlasticState(cut, options_);
  std::vector<const curvature::EnergyTerm*> moved;
  if (options_.yieldCurvature) {
    const Eigen::Index count = carried.initialRest.rows();
    carryPart(
        *problem_,
        elementFaces(*problem_->terms.front()->restCurvatureState(), state_.initialRest.rows()),
        cut, elementFaces(*cut.terms.front()->restCurvatureState(), count), faceOrigin,
        state_.plasticStrain, state_.yielded, carried.plasticStrain, carried.yielded);
    moved.push_back(cut.terms.front().get());
  }
  curvature::EnergyTerm* membrane = options_.yieldStrain ? membraneTermOf(cut) : nullptr;
  if (membrane != nullptr) {
    carryPart(*problem_,
              elementFaces(*membrane_->restMetricState(), state_.membraneInitialRest.rows()), cut,
              elementFaces(*membrane->restMetricState(), carried.membraneInitialRest.rows()),
              faceOrigin, state_.membranePlasticStrain, state_.membraneYielded,
              carried.membranePlasticStrain, carried.membraneYielded);
    moved.push_back(membrane);
  }
  carried.dissipation = state_.dissipation;
  problem_ = &cut;
  membrane_ = membrane;
  state_ = std::move(carried);
  setRestStates(moved, state_.plasticStrain, state_.membranePlasticStrain);
}

void PlasticDynamics::setRestStates(const std::vector<const curvature::EnergyTerm*>& moved,
                                    const Eigen::MatrixXd& bending,
                                    const Eigen::MatrixXd& membrane) {
  for (const curvature::EnergyTerm* term : moved) {
    if (term == problem_->terms.front().get())
      problem_->terms.front()->restCurvatureState()->setRestCurvatures(state_.initialRest +
                                                                       bending);
    else
      membrane_->restMetricState()->setRestStrains(state_.membraneInitialRest + membrane);
  }
}

PlasticUpdate PlasticDynamics::afterStep() {
  const Eigen::MatrixXd bendingBefore = state_.plasticStrain;
  const Eigen::MatrixXd membraneBefore = state_.membranePlasticStrain;
  const PlasticUpdate update =
      updatePlasticStrains(*problem_, state_, options_, stepper_->positions(), stepper_->xi());
  if (update.yieldedElements == 0 && update.yieldedFaces == 0) return update;
  TimeStepper::State after = stepper_->state();
  after.balance.plastic += update.released;
  // Newmark's a_n satisfies M a_n + C v_n + ∇E(x_n) = M g with the rest state of the step; the
  // update changes ∇E at x_n, so a_n moves by −M⁻¹ Δ∇E (the next step's predictor and
  // trapezoidal rule then use the forces of the new rest state, which keeps the balance).
  std::vector<const curvature::EnergyTerm*> moved;
  if (update.yieldedElements > 0) moved.push_back(problem_->terms.front().get());
  if (update.yieldedFaces > 0) moved.push_back(membrane_);
  setRestStates(moved, bendingBefore, membraneBefore);
  const Eigen::VectorXd before = energyGradient(moved, after.x, after.xi).gradient;
  setRestStates(moved, state_.plasticStrain, state_.membranePlasticStrain);
  const Eigen::VectorXd change = energyGradient(moved, after.x, after.xi).gradient - before;
  const Eigen::VectorXd& mass = stepper_->masses();
  for (Eigen::Index v = 0; v < after.a.rows(); ++v)
    if (!problem_->boundary.fixedVertex[v])
      for (int c = 0; c < 3; ++c) after.a(v, c) -= change[3 * v + c] / mass[v];
  stepper_->restore(after);
  return update;
}

std::vector<int> PlasticDynamics::yieldedElements() const {
  std::vector<int> ids;
  for (size_t e = 0; e < state_.yielded.size(); ++e)
    if (state_.yielded[e])
      ids.push_back(problem_->terms.front()->restCurvatureState()->elementId(static_cast<int>(e)));
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

Eigen::VectorXd PlasticDynamics::facePlasticCurvatures() const {
  if (state_.yielded.empty()) return Eigen::VectorXd::Zero(problem_->stencils.faceCount());
  const curvature::RestCurvatureState& rest = *problem_->terms.front()->restCurvatureState();
  std::vector<int> ids(state_.yielded.size());
  for (size_t e = 0; e < ids.size(); ++e) ids[e] = rest.elementId(static_cast<int>(e));
  return faceValues(problem_->stencils, equivalentPlasticCurvatures(state_), ids);
}

Eigen::VectorXd PlasticDynamics::facePlasticStrains() const {
  if (membrane_ == nullptr) return Eigen::VectorXd::Zero(problem_->stencils.faceCount());
  const curvature::RestMetricState& metric = *membrane_->restMetricState();
  std::vector<int> ids(state_.membraneYielded.size());
  for (size_t f = 0; f < ids.size(); ++f) ids[f] = metric.elementId(static_cast<int>(f));
  return faceValues(problem_->stencils, equivalentPlasticStrains(state_), ids);
}

Eigen::VectorXd PlasticDynamics::facePlasticMeasure() const {
  if (!options_.yieldStrain) return facePlasticCurvatures();
  if (!options_.yieldCurvature) return facePlasticStrains();
  return (facePlasticCurvatures() / *options_.yieldCurvature)
      .cwiseMax(facePlasticStrains() / *options_.yieldStrain);
}

Eigen::VectorXd PlasticDynamics::vertexPlasticCurvatures() const {
  return vertexMaxima(problem_->stencils, facePlasticCurvatures());
}

Eigen::VectorXd PlasticDynamics::vertexPlasticStrains() const {
  return vertexMaxima(problem_->stencils, facePlasticStrains());
}

Eigen::VectorXd PlasticDynamics::vertexPlasticMeasure() const {
  return vertexMaxima(problem_->stencils, facePlasticMeasure());
}

}  // namespace flexure::optimize
