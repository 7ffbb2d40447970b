// Plasticity of the bending and membrane parts: the yield rule, the radial return and
// quasi-static forming (plasticity.h; docs/energies.md, "Plasticity").
#include "optimize/inelastic/plasticity.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

using curvature::RestCurvatureState;
using curvature::RestMetricState;

// The membrane term whose rest metric a plastic strain moves, and that state.
struct MembraneMetric {
  curvature::EnergyTerm* term = nullptr;
  RestMetricState* state = nullptr;
};

MembraneMetric membraneMetricOf(Problem& problem) {
  for (size_t k = 1; k < problem.terms.size(); ++k)
    if (RestMetricState* state = problem.terms[k]->restMetricState())
      return {problem.terms[k].get(), state};
  if (problem.terms.size() == 1)
    throw InputError(
        "PlasticityOptions.yieldStrain: the problem has no membrane; membrane plasticity needs "
        "ProblemOptions.membrane stvk (with ProblemOptions.dof xyz)");
  throw InputError("PlasticityOptions.yieldStrain: the " + problem.terms[1]->name() +
                   " membrane has no per-face strain tensor whose rest value a plastic strain "
                   "could move (springs: a rest length per edge and an area per face; conformal "
                   "and mips: shape only, no size); use ProblemOptions.membrane stvk");
}

RestCurvatureState& restCurvatureOf(Problem& problem) {
  curvature::EnergyTerm& bending = *problem.terms.front();
  RestCurvatureState* state = bending.restCurvatureState();
  if (state == nullptr) {
    throw InputError(
        "PlasticityOptions.yieldCurvature: the " + bending.name() +
        " energy has no per-face shape operator whose rest value a plastic strain could move "
        "(cotan's is one mean curvature per vertex); use " +
        curvature::energyNamesWhere(
            [](const curvature::EnergyEntry& e) { return e.plasticRestCurvature; }));
  }
  return *state;
}

// ‖A‖²_* = Tr(A²) + (Tr A)² of a face tensor row (a, b, c) = [[a, b], [b, c]].
double starNormSquared(const Eigen::RowVectorXd& m) {
  const double trace = m(0) + m(2);
  return m(0) * m(0) + 2.0 * m(1) * m(1) + m(2) * m(2) + trace * trace;
}

// The face whose centroid is nearest the vertices' centroid, among faces every one of whose
// vertices an element of the problem touches.
int centralFace(const Problem& problem, const Positions& x) {
  std::vector<bool> touched(static_cast<size_t>(x.rows()), false);
  for (const auto& term : problem.terms) term->markTouchedVertices(touched);
  const Eigen::RowVector3d centroid = x.colwise().mean();
  int best = -1;
  double nearest = std::numeric_limits<double>::infinity();
  for (int f = 0; f < problem.stencils.faceCount(); ++f) {
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    bool allTouched = true;
    for (int k = 0; k < 3; ++k) {
      const int v = problem.stencils.faces(f, k);
      allTouched = allTouched && touched[v];
      c += x.row(v) / 3.0;
    }
    const double distance = (c - centroid).squaredNorm();
    if (allTouched && distance < nearest) nearest = distance, best = f;
  }
  if (best < 0) throw InputError("the mesh has no face whose vertices the energy reads");
  return best;
}

// Face `face`'s vertices moved so that it sits at its plastic rest metric: with the formed
// F = Q U (polar, U = (FᵀF)^½), F' = Q Ā^½, Ā = I + 2 P the membrane's rest metric in the face's
// rest frame; edges F' D̄, centroid kept. NumericalError when Ā is not positive definite.
void placeAtRestMetric(Problem& problem, int face, Positions& x) {
  const MembraneMetric membrane = membraneMetricOf(problem);
  const RestMetricState& metric = *membrane.state;
  int element = -1;
  for (int e = 0; e < membrane.term->elementCount() && element < 0; ++e)
    if (metric.elementId(e) == face) element = e;
  if (element < 0) return;  // the membrane does not read this face: nothing to place
  const Eigen::RowVector3d p = metric.restStrains().row(element);
  Eigen::Matrix2d restMetric;
  restMetric << 1 + 2 * p(0), 2 * p(1), 2 * p(1), 1 + 2 * p(2);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> rest(restMetric);
  if (!(rest.eigenvalues().minCoeff() > 0.0))
    throw NumericalError("face " + std::to_string(face) +
                         ": its plastic rest metric is not positive definite (a plastic strain "
                         "below -1/2)");
  const int v[3] = {problem.stencils.faces(face, 0), problem.stencils.faces(face, 1),
                    problem.stencils.faces(face, 2)};
  Eigen::Matrix<double, 3, 2> edges;
  edges.col(0) = (x.row(v[1]) - x.row(v[0])).transpose();
  edges.col(1) = (x.row(v[2]) - x.row(v[0])).transpose();
  const Eigen::Matrix2d restEdges = metric.restEdgeMatrix(element);
  const Eigen::Matrix<double, 3, 2> f = edges * restEdges.inverse();
  const Eigen::Matrix2d stretch =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(f.transpose() * f).operatorSqrt();
  const Eigen::Matrix<double, 3, 2> placed =
      f * stretch.inverse() * rest.operatorSqrt() * restEdges;
  const Eigen::RowVector3d centroid = (x.row(v[0]) + x.row(v[1]) + x.row(v[2])) / 3.0;
  x.row(v[0]) = centroid - (placed.col(0) + placed.col(1)).transpose() / 3.0;
  x.row(v[1]) = x.row(v[0]) + placed.col(0).transpose();
  x.row(v[2]) = x.row(v[0]) + placed.col(1).transpose();
}

// Solves and updates until no element's plastic increment exceeds tolerance κ_y (bending) and no
// face's tolerance ε_y (membrane).
bool settle(Problem& problem, PlasticState& state, const PlasticityOptions& plasticity,
            const FormingOptions& forming, BoundaryConditions& bc, MinimizeOptions& options,
            FormingResult& out) {
  for (int update = 0; update < forming.maxUpdatesPerStep; ++update) {
    const MinimizeResult solve = minimize(problem, bc, options);
    ++out.report.solves;
    out.report.lastSolve = solve.report;
    options.start = Start::AsGiven;  // later solves start from the last minimizer
    if (!solve.report.converged) return false;
    out.positions = solve.positions;
    out.xi = solve.xi;
    for (Eigen::Index v = 0; v < bc.start.rows(); ++v)
      if (!bc.fixedVertex[v]) bc.start.row(v) = solve.positions.row(v);
    if (bc.xi.size() > 0)
      for (Eigen::Index e = 0; e < bc.xi.size(); ++e)
        if (!bc.fixedEdge[e]) bc.xi[e] = solve.xi[e];
    const PlasticUpdate step =
        updatePlasticStrains(problem, state, plasticity, solve.positions, solve.xi);
    const bool bendingSettled =
        !plasticity.yieldCurvature ||
        step.largestIncrement <= forming.tolerance * *plasticity.yieldCurvature;
    const bool membraneSettled =
        !plasticity.yieldStrain ||
        step.largestStrainIncrement <= forming.tolerance * *plasticity.yieldStrain;
    if (bendingSettled && membraneSettled) return true;
  }
  return false;
}

}  // namespace

std::string PlasticityOptions::measureName() const {
  if (yieldCurvature && yieldStrain) return "plastic strain / yield value";
  if (yieldStrain) return "membrane plastic strain (Green)";
  return "plastic strain (1 / length)";
}

void PlasticityOptions::validate() const {
  const auto positive = [](const std::optional<double>& v) {
    return !v || (std::isfinite(*v) && *v > 0.0);
  };
  if (!positive(yieldCurvature))
    throw InputError("PlasticityOptions.yieldCurvature " + numberText(*yieldCurvature) +
                     ": must be positive and finite");
  if (!positive(yieldStrain))
    throw InputError("PlasticityOptions.yieldStrain " + numberText(*yieldStrain) +
                     ": must be positive and finite");
  if (!(std::isfinite(hardening) && hardening >= 0.0))
    throw InputError("PlasticityOptions.hardening " + numberText(hardening) +
                     ": must be zero or positive");
}

void FormingOptions::validate() const {
  if (loadSteps < 1)
    throw InputError("FormingOptions.loadSteps " + std::to_string(loadSteps) +
                     ": must be at least 1");
  if (maxUpdatesPerStep < 1)
    throw InputError("FormingOptions.maxUpdatesPerStep " + std::to_string(maxUpdatesPerStep) +
                     ": must be at least 1");
  if (!(tolerance > 0.0)) throw InputError("FormingOptions.tolerance must be positive");
}

PlasticState initialPlasticState(Problem& problem, const PlasticityOptions& options) {
  options.validate();
  if (!options.enabled())
    throw InputError(
        "PlasticityOptions.yieldCurvature, PlasticityOptions.yieldStrain: neither is given "
        "(nothing can yield)");
  PlasticState state;
  if (options.yieldCurvature) {
    state.initialRest = restCurvatureOf(problem).restCurvatures();
    state.plasticStrain = Eigen::MatrixXd::Zero(state.initialRest.rows(), state.initialRest.cols());
    state.yielded.assign(static_cast<size_t>(state.initialRest.rows()), false);
  }
  if (options.yieldStrain) {
    const RestMetricState& metric = *membraneMetricOf(problem).state;
    state.membraneInitialRest = metric.restStrains();
    state.membranePlasticStrain = Eigen::MatrixXd::Zero(state.membraneInitialRest.rows(), 3);
    state.membraneYielded.assign(static_cast<size_t>(state.membraneInitialRest.rows()), false);
  }
  return state;
}

Eigen::VectorXd equivalentPlasticCurvatures(const PlasticState& state) {
  Eigen::VectorXd out(state.plasticStrain.rows());
  for (Eigen::Index e = 0; e < out.size(); ++e)
    out[e] = std::sqrt(starNormSquared(state.plasticStrain.row(e)) / 2.0);
  return out;
}

Eigen::VectorXd equivalentPlasticStrains(const PlasticState& state) {
  Eigen::VectorXd out(state.membranePlasticStrain.rows());
  for (Eigen::Index f = 0; f < out.size(); ++f)
    out[f] = std::sqrt(starNormSquared(state.membranePlasticStrain.row(f)) / 2.0);
  return out;
}

namespace {

// One part's trial A = E − (1 + γ) P per element, and its yield measure ‖A‖²_* / (2 y²).
struct Trial {
  Eigen::MatrixXd strain;  // A, #elements by components
  Eigen::VectorXd yield;   // ‖A‖²_* / (2 y²); then, where a face has both parts, their sum
};

Trial trialOf(Eigen::MatrixXd strain, double yieldValue) {
  Trial t{std::move(strain), Eigen::VectorXd(0)};
  t.yield.resize(t.strain.rows());
  for (Eigen::Index e = 0; e < t.strain.rows(); ++e)
    t.yield[e] = starNormSquared(t.strain.row(e)) / (2.0 * yieldValue * yieldValue);
  return t;
}

// Where a face carries both parts, each part's yield measure becomes the face's sum f_m + f_b, so
// both return with the one factor s = 1/√f.
void combineByFace(const Problem& problem, const RestCurvatureState& bending, Trial& bendingTrial,
                   const RestMetricState& metric, Trial& membraneTrial) {
  std::vector<int> bendingOfFace(static_cast<size_t>(problem.stencils.faceCount()), -1);
  for (Eigen::Index e = 0; e < bendingTrial.yield.size(); ++e)
    bendingOfFace[static_cast<size_t>(bending.elementId(static_cast<int>(e)))] =
        static_cast<int>(e);
  for (Eigen::Index m = 0; m < membraneTrial.yield.size(); ++m) {
    const int b = bendingOfFace[static_cast<size_t>(metric.elementId(static_cast<int>(m)))];
    if (b < 0) continue;
    const double sum = membraneTrial.yield[m] + bendingTrial.yield[b];
    membraneTrial.yield[m] = sum;
    bendingTrial.yield[b] = sum;
  }
}

// The radial return of every element with yield measure f > 1: ΔP = (1 − 1/√f) A / (1 + γ).
// Returns the count and max ‖ΔP‖_*/√2 (in the part's units).
std::pair<int, double> returnRadially(const Trial& trial, double gamma, Eigen::MatrixXd& plastic,
                                      std::vector<bool>& yielded) {
  int count = 0;
  double largest = 0.0;
  for (Eigen::Index e = 0; e < trial.strain.rows(); ++e) {
    const double f = trial.yield[e];
    if (!(f > 1.0)) continue;
    const double s = 1.0 / std::sqrt(f);
    const Eigen::RowVectorXd increment = (1.0 - s) / (1.0 + gamma) * trial.strain.row(e);
    largest = std::max(largest, std::sqrt(starNormSquared(increment) / 2.0));
    plastic.row(e) += increment;
    yielded[static_cast<size_t>(e)] = true;
    ++count;
  }
  return {count, largest};
}

}  // namespace

PlasticUpdate updatePlasticStrains(Problem& problem, PlasticState& state,
                                   const PlasticityOptions& options, const Positions& x,
                                   const Eigen::VectorXd& xi) {
  const double gamma = options.hardening;
  RestCurvatureState* bending = options.yieldCurvature ? &restCurvatureOf(problem) : nullptr;
  const MembraneMetric membrane =
      options.yieldStrain ? membraneMetricOf(problem) : MembraneMetric{};
  Trial bendingTrial, membraneTrial;
  if (bending) {
    // E_b = S − S̄₀, A = E_b − (1 + γ) P_b.
    Eigen::MatrixXd a = bending->elementCurvatures(x, xi) - state.initialRest;
    a -= (1.0 + gamma) * state.plasticStrain;
    bendingTrial = trialOf(std::move(a), *options.yieldCurvature);
  }
  if (membrane.state) {
    // E_m = ε − P₀ (P₀ = 0 as built), A = E_m − (1 + γ) P_m.
    Eigen::MatrixXd a = membrane.state->elementStrains(x) - state.membraneInitialRest;
    a -= (1.0 + gamma) * state.membranePlasticStrain;
    membraneTrial = trialOf(std::move(a), *options.yieldStrain);
  }
  if (bending && membrane.state)
    combineByFace(problem, *bending, bendingTrial, *membrane.state, membraneTrial);
  PlasticUpdate update;
  if (bending)
    std::tie(update.yieldedElements, update.largestIncrement) =
        returnRadially(bendingTrial, gamma, state.plasticStrain, state.yielded);
  if (membrane.state)
    std::tie(update.yieldedFaces, update.largestStrainIncrement) =
        returnRadially(membraneTrial, gamma, state.membranePlasticStrain, state.membraneYielded);
  if (update.yieldedElements == 0 && update.yieldedFaces == 0) return update;
  double before = 0.0, after = 0.0;
  if (update.yieldedElements > 0) {
    before += problem.terms.front()->energy(x, xi);
    bending->setRestCurvatures(state.initialRest + state.plasticStrain);
    after += problem.terms.front()->energy(x, xi);
  }
  if (update.yieldedFaces > 0) {
    before += membrane.term->energy(x, xi);
    membrane.state->setRestStrains(state.membraneInitialRest + state.membranePlasticStrain);
    after += membrane.term->energy(x, xi);
  }
  update.released = before - after;
  state.dissipation += update.released;
  return update;
}

FormingResult formPlastically(Problem& problem, const PlasticityOptions& plasticity,
                              const FormingOptions& forming, const MinimizeOptions& options) {
  forming.validate();
  if (options.linearized)
    throw InputError(
        "MinimizeOptions.linearized: plastic forming needs the nonlinear solve (the linearized "
        "energy is linearized about a rest state plasticity moves)");
  FormingResult out;
  out.state = initialPlasticState(problem, plasticity);
  MinimizeOptions solveOptions = options;
  const BoundaryConditions target = problem.boundary;
  BoundaryConditions bc = target;
  const Positions& restPositions = problem.rest.positions;
  bool settled = true;
  for (int k = 1; k <= forming.loadSteps && settled; ++k) {
    // The held values a fraction k / K of the way from rest (and ξ̄) to the target's.
    const double t = static_cast<double>(k) / forming.loadSteps;
    for (Eigen::Index v = 0; v < bc.start.rows(); ++v)
      if (target.fixedVertex[v])
        bc.start.row(v) = restPositions.row(v) + t * (target.start.row(v) - restPositions.row(v));
    for (Eigen::Index e = 0; e < bc.xi.size(); ++e)
      if (target.fixedEdge[e])
        bc.xi[e] = problem.restXi[e] + t * (target.xi[e] - problem.restXi[e]);
    settled = settle(problem, out.state, plasticity, forming, bc, solveOptions, out);
  }
  if (settled && forming.release) {
    // Vertices no element reads carry no energy: they stay where the forming left them.
    std::vector<bool> touched(bc.fixedVertex.size(), false);
    for (const auto& term : problem.terms) term->markTouchedVertices(touched);
    const int face = centralFace(problem, out.positions);
    out.report.releasePins = {problem.stencils.faces(face, 0), problem.stencils.faces(face, 1),
                              problem.stencils.faces(face, 2)};
    if (plasticity.yieldStrain) placeAtRestMetric(problem, face, bc.start);
    for (size_t v = 0; v < touched.size(); ++v) bc.fixedVertex[v] = !touched[v];
    for (int v : out.report.releasePins) bc.fixedVertex[v] = true;
    bc.fixedEdge.assign(bc.fixedEdge.size(), false);
    solveOptions.start = Start::AsGiven;
    settled = settle(problem, out.state, plasticity, forming, bc, solveOptions, out);
  }
  out.report.converged = settled && out.report.lastSolve.converged;
  out.report.dissipation = out.state.dissipation;
  for (bool y : out.state.yielded) out.report.yieldedElements += y ? 1 : 0;
  for (bool y : out.state.membraneYielded) out.report.yieldedFaces += y ? 1 : 0;
  return out;
}

}  // namespace flexure::optimize
