// Plasticity of the bending part: the yield rule, the radial return and quasi-static forming
// (plasticity.h; docs/energies.md, "Plasticity").
#include "optimize/inelastic/plasticity.h"

#include <cmath>
#include <limits>
#include <string>

#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

using curvature::RestCurvatureState;

RestCurvatureState& restCurvatureOf(Problem& problem) {
  curvature::EnergyTerm& bending = *problem.terms.front();
  RestCurvatureState* state = bending.restCurvatureState();
  if (state == nullptr) {
    throw InputError(
        "PlasticityOptions.yieldCurvature: the " + bending.name() +
        " energy has no per-face shape operator or per-edge angle whose rest value a plastic "
        "strain could move (cotan's is one mean curvature per vertex); use triavg, midedge, "
        "quadfit or hinge");
  }
  return *state;
}

// ‖A‖²_* = Tr(A²) + (Tr A)² of a face tensor row (a, b, c) = [[a, b], [b, c]]; for a hinge's
// scalar (already a curvature) the one-dimensional law, A², so that it yields at |A| = κ_y as a
// plate bent into a cylinder does.
double starNormSquared(const Eigen::RowVectorXd& m) {
  if (m.size() == 1) return 2.0 * m(0) * m(0);
  const double trace = m(0) + m(2);
  return m(0) * m(0) + 2.0 * m(1) * m(1) + m(2) * m(2) + trace * trace;
}

Eigen::VectorXd hingeLengths(const Problem& problem, const RestCurvatureState& state) {
  if (state.components() != 1) return {};
  Eigen::VectorXd length(problem.terms.front()->elementCount());
  for (Eigen::Index e = 0; e < length.size(); ++e) {
    const int edge = state.elementId(static_cast<int>(e));
    const int f = problem.stencils.edgeFaces(edge, 0), g = problem.stencils.edgeFaces(edge, 1);
    length[e] = 2.0 * (problem.rest.faceAreas[f] + problem.rest.faceAreas[g]) /
                (3.0 * problem.rest.edgeLengths[edge]);
  }
  return length;
}

// The three vertices of the face whose centroid is nearest the vertices' centroid, among faces
// every one of whose vertices an element of the problem touches.
std::vector<int> centralFaceVertices(const Problem& problem, const Positions& x) {
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
  return {problem.stencils.faces(best, 0), problem.stencils.faces(best, 1),
          problem.stencils.faces(best, 2)};
}

// Solves and updates until no element's plastic increment exceeds tolerance κ_y.
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
    if (step.largestIncrement <= forming.tolerance * *plasticity.yieldCurvature) return true;
  }
  return false;
}

}  // namespace

void PlasticityOptions::validate() const {
  const auto positive = [](const std::optional<double>& v) {
    return !v || (std::isfinite(*v) && *v > 0.0);
  };
  if (!positive(yieldCurvature))
    throw InputError("PlasticityOptions.yieldCurvature " + std::to_string(*yieldCurvature) +
                     ": must be positive and finite");
  if (!positive(yieldStrain))
    throw InputError("PlasticityOptions.yieldStrain " + std::to_string(*yieldStrain) +
                     ": must be positive and finite");
  if (!(std::isfinite(hardening) && hardening >= 0.0))
    throw InputError("PlasticityOptions.hardening " + std::to_string(hardening) +
                     ": must be zero or positive");
  if (yieldStrain)
    throw InputError(
        "PlasticityOptions.yieldStrain: membrane plasticity is not modelled yet (the membrane "
        "stays elastic); give only PlasticityOptions.yieldCurvature");
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
  if (!options.yieldCurvature)
    throw InputError("PlasticityOptions.yieldCurvature: needed for the bending part");
  RestCurvatureState& rest = restCurvatureOf(problem);
  PlasticState state;
  state.initialRest = rest.restCurvatures();
  state.plasticStrain = Eigen::MatrixXd::Zero(state.initialRest.rows(), state.initialRest.cols());
  state.hingeLength = hingeLengths(problem, rest);
  state.yielded.assign(static_cast<size_t>(state.initialRest.rows()), false);
  return state;
}

Eigen::VectorXd equivalentPlasticCurvatures(const PlasticState& state) {
  Eigen::VectorXd out(state.plasticStrain.rows());
  for (Eigen::Index e = 0; e < out.size(); ++e) {
    out[e] = std::sqrt(starNormSquared(state.plasticStrain.row(e)) / 2.0);
    if (state.hingeLength.size() > 0) out[e] /= state.hingeLength[e];
  }
  return out;
}

PlasticUpdate updatePlasticStrains(Problem& problem, PlasticState& state,
                                   const PlasticityOptions& options, const Positions& x,
                                   const Eigen::VectorXd& xi) {
  RestCurvatureState& rest = restCurvatureOf(problem);
  const double gamma = options.hardening, yield = *options.yieldCurvature;
  // E = S − S̄₀, A = E − (1 + γ) P; a hinge's angle measure divided by 2 h̄_e is a curvature.
  Eigen::MatrixXd trial = rest.elementCurvatures(x, xi) - state.initialRest;
  trial -= (1.0 + gamma) * state.plasticStrain;
  if (state.hingeLength.size() > 0) trial.col(0).array() /= state.hingeLength.array();
  PlasticUpdate update;
  for (Eigen::Index e = 0; e < trial.rows(); ++e) {
    const double f = starNormSquared(trial.row(e)) / (2.0 * yield * yield);
    if (!(f > 1.0)) continue;
    const double s = 1.0 / std::sqrt(f);
    Eigen::RowVectorXd increment = (1.0 - s) / (1.0 + gamma) * trial.row(e);
    update.largestIncrement =
        std::max(update.largestIncrement, std::sqrt(starNormSquared(increment) / 2.0));
    if (state.hingeLength.size() > 0) increment *= state.hingeLength[e];
    state.plasticStrain.row(e) += increment;
    state.yielded[static_cast<size_t>(e)] = true;
    ++update.yieldedElements;
  }
  if (update.yieldedElements == 0) return update;
  const double before = problem.terms.front()->energy(x, xi);
  rest.setRestCurvatures(state.initialRest + state.plasticStrain);
  update.released = before - problem.terms.front()->energy(x, xi);
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
    out.report.releasePins = centralFaceVertices(problem, out.positions);
    for (size_t v = 0; v < touched.size(); ++v) bc.fixedVertex[v] = !touched[v];
    for (int v : out.report.releasePins) bc.fixedVertex[v] = true;
    bc.fixedEdge.assign(bc.fixedEdge.size(), false);
    solveOptions.start = Start::AsGiven;
    settled = settle(problem, out.state, plasticity, forming, bc, solveOptions, out);
  }
  out.report.converged = settled && out.report.lastSolve.converged;
  out.report.dissipation = out.state.dissipation;
  for (bool y : out.state.yielded) out.report.yieldedElements += y ? 1 : 0;
  return out;
}

}  // namespace flexure::optimize
