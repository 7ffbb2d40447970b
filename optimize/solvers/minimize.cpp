#include "optimize/solvers/minimize.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "modeling/errors.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/linear/elimination_order.h"
#include "optimize/linear/linear_algebra_threads.h"
#include "optimize/linear/linearized_solver.h"
#include "optimize/problem.h"
#include "optimize/solvers/hessian_factorization.h"
#include "optimize/solvers/newton_solver.h"

namespace flexure::optimize {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void requireWellPosed(const std::vector<const EnergyTerm*>& terms, const BoundaryConditions& bc,
                      DofMode dof) {
  const int vertexCount = static_cast<int>(bc.fixedVertex.size());
  int fixed = 0;
  for (bool f : bc.fixedVertex) fixed += f;
  if (fixed == vertexCount) {
    throw InputError("every vertex is fixed: there is nothing to minimize (fix fewer rings)");
  }
  if (fixed == 0) {
    throw InputError(
        dof == DofMode::Height
            ? "no vertex is fixed: in ProblemOptions.dof height adding a plane z = a + bx + cy "
              "costs no bending energy, so the minimizer is not unique; fix the "
              "boundary (BoundaryConditions.fixedVertex rings:2)"
            : "no vertex is fixed: rigid motions cost no energy, so the minimizer is "
              "not unique; fix the boundary (BoundaryConditions.fixedVertex rings:2)");
  }
  std::vector<bool> touched(vertexCount, false);
  for (const EnergyTerm* term : terms) term->markTouchedVertices(touched);
  for (int v = 0; v < vertexCount; ++v) {
    if (!bc.fixedVertex[v] && !touched[v]) {
      throw InputError("free vertex " + std::to_string(v) +
                       " is touched by no element of the energy, so nothing determines it; fix "
                       "it or use more rings (BoundaryConditions.fixedVertex rings:K)");
    }
  }
}

class ProgressPrinter : public ceres::IterationCallback {
 public:
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    std::fprintf(stderr, "  iteration %3d  energy %.10e  |gradient| %.3e  |step| %.3e  %s\n",
                 s.iteration, s.cost, s.gradient_norm, s.step_norm,
                 s.step_is_successful ? "" : "(step rejected)");
    return ceres::SOLVER_CONTINUE;
  }
};

// Ceres' iterations shown to a MinimizeOptions::observer; true from it aborts the solve.
class ObserverCallback : public ceres::IterationCallback {
 public:
  explicit ObserverCallback(const IterationObserver& observer) : observer_(observer) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    stopped_ = observer_({s.iteration, s.cost, s.gradient_norm});
    return stopped_ ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }
  bool stopped() const { return stopped_; }

 private:
  const IterationObserver& observer_;
  bool stopped_ = false;
};

// The linearized solve is accepted when it brings the free gradient below this fraction of the
// start's.
constexpr double kLinearizedGradientDrop = 1e-6;

MinimizeResult minimizeLinearized(const std::vector<const EnergyTerm*>& terms,
                                  const BoundaryConditions& bc, const Positions& rest,
                                  const Eigen::VectorXd& restXi, DofMode dof) {
  const auto start = Clock::now();
  MinimizeResult result;
  // u = (X − X̄, ξ − ξ̄): the fixed entries from the boundary conditions, the free ones solved.
  LinearizedUnknowns unknowns{bc.fixedVertex, bc.fixedEdge, dof == DofMode::Height};
  unknowns.fixedMoveInPlane = (bc.start - rest).leftCols(2).cwiseAbs().maxCoeff() != 0.0;
  const LinearizedSolver solver(terms, rest, restXi, unknowns);
  const auto solveStart = Clock::now();
  LinearizedSolution solution = solver.solve(bc);
  result.report.evaluationSeconds = solver.jacobianSeconds();
  result.report.linearSolverSeconds = solver.factorSeconds() + secondsSince(solveStart);
  result.report.initialEnergy = solution.initialEnergy;
  result.report.finalEnergy = solution.energy;
  result.report.gradientNorm = solution.gradientNorm;
  result.positions = std::move(solution.positions);
  result.xi = std::move(solution.xi);
  // Checked, not assumed: the solve must leave the free gradient at a small fraction of the
  // start's (a direct solve leaves round-off, measured 2e-13 to 4e-12 of it for every energy on
  // delaunay n = 64 and patch48 n = 256) and must not raise E_lin. A singular or badly conditioned
  // system fails here rather than passing as a minimizer.
  const bool checked =
      std::isfinite(solution.energy) &&
      solution.energy <= solution.initialEnergy * (1.0 + 1e-12) + 1e-300 &&
      solution.gradientNorm <= kLinearizedGradientDrop * solution.initialGradientNorm;
  result.report.converged = checked;
  result.report.stop = checked ? NewtonStop::Converged : NewtonStop::SolverFailure;
  result.report.solver = "linearized";
  result.report.termination = checked
                                  ? "linearized: one sparse solve"
                                  : "linearized: the sparse solve left |gradient| " +
                                        std::to_string(solution.gradientNorm) + " of the start's " +
                                        std::to_string(solution.initialGradientNorm) +
                                        " (singular or badly conditioned system)";
  result.report.iterations = 1;
  result.report.factorizations = solver.factorizations();
  result.report.residuals = static_cast<int>(solver.jacobian().rows());
  result.report.unknowns = solver.freeCount();
  result.report.totalSeconds = secondsSince(start);
  return result;
}

// Ceres' termination as a NewtonStop. Ceres reports a residual that evaluates to inf or NaN only
// in its message ("Residual and Jacobian evaluation failed", "Evaluation of the residual ...
// failed"): this is the one place that reads it.
NewtonStop ceresStop(const ceres::Solver::Summary& summary) {
  switch (summary.termination_type) {
    case ceres::CONVERGENCE:
      return NewtonStop::Converged;
    case ceres::NO_CONVERGENCE:
      return NewtonStop::MaxIterations;
    default:
      return summary.message.find("valuation") != std::string::npos ||
                     summary.message.find("not finite") != std::string::npos
                 ? NewtonStop::NonFinite
                 : NewtonStop::SolverFailure;
  }
}

MinimizeResult minimizeNonlinear(const std::vector<const EnergyTerm*>& terms,
                                 const BoundaryConditions& bc, DofMode dof,
                                 const MinimizeOptions& options) {
  const auto start = Clock::now();
  MinimizeResult result;
  result.positions = bc.start;
  const bool withXi = usesEdgeUnknowns(terms);
  if (withXi) result.xi = bc.xi;

  ceres::Problem::Options problemOptions;
  problemOptions.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problemOptions);
  ceres::SubsetManifold heightOnly(3, {0, 1});
  int unknowns = 0;
  for (int v = 0; v < result.positions.rows(); ++v) {
    double* block = result.positions.data() + 3 * v;
    problem.AddParameterBlock(block, 3);
    if (bc.fixedVertex[v]) {
      problem.SetParameterBlockConstant(block);
    } else if (dof == DofMode::Height) {
      problem.SetManifold(block, &heightOnly);
      unknowns += 1;
    } else {
      unknowns += 3;
    }
  }
  if (withXi) {
    for (int e = 0; e < result.xi.size(); ++e) {
      problem.AddParameterBlock(result.xi.data() + e, 1);
      if (bc.fixedEdge[e]) {
        problem.SetParameterBlockConstant(result.xi.data() + e);
      } else {
        ++unknowns;
      }
    }
  }
  // Height mode: x and y are held by the manifold, so the residual blocks compute only ∂/∂z, ∂/∂ξ.
  const curvature::Derivatives derivatives =
      dof == DofMode::Height ? curvature::Derivatives::HeightOnly : curvature::Derivatives::All;
  for (const EnergyTerm* term : terms)
    term->addResidualBlocks(problem, result.positions.data(), withXi ? result.xi.data() : nullptr,
                            derivatives);

  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  // The bending Hessian is bi-Laplacian-like, condition number ~ n⁴: Ceres' default initial
  // radius (1e4, i.e. damping 1e-4 of the diagonal) all but freezes the smooth modes, and the
  // radius then grows only 3× per step. Start as Gauss–Newton; LM damping returns on a bad step.
  solver.initial_trust_region_radius = 1e12;
  solver.num_threads = options.threads;
  solver.max_num_iterations = options.maxIterations;
  solver.function_tolerance = options.functionTolerance;
  solver.gradient_tolerance = options.gradientTolerance;
  solver.parameter_tolerance = options.parameterTolerance;
  solver.minimizer_progress_to_stdout = false;
  solver.logging_type = ceres::SILENT;
  const auto orderingStart = Clock::now();
  if (options.nestedDissection) solver.linear_solver_ordering = nestedDissectionGroups(problem);
  const double orderingSeconds = secondsSince(orderingStart);
  ProgressPrinter printer;
  if (options.progress) solver.callbacks.push_back(&printer);
  ObserverCallback observer(options.observer);
  if (options.observer) solver.callbacks.push_back(&observer);

  ceres::Solver::Summary summary;
  {
    const SingleThreadedLinearAlgebra oneThread;  // Ceres' CHOLMOD runs on this thread
    ceres::Solve(solver, &problem, &summary);
  }

  MinimizeReport& r = result.report;
  r.converged = summary.termination_type == ceres::CONVERGENCE;
  r.solver = "ceres";
  r.factorizations = summary.num_linear_solves;
  r.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " +
                  summary.message;
  r.stop = observer.stopped() ? NewtonStop::Stopped : ceresStop(summary);
  if (observer.stopped()) {
    r.converged = false;
    r.termination = std::string("NO_CONVERGENCE: ") + newtonStopMessage(NewtonStop::Stopped);
  }
  r.iterations = summary.iterations.empty() ? 0 : static_cast<int>(summary.iterations.size()) - 1;
  r.initialEnergy = summary.initial_cost;
  r.finalEnergy = summary.final_cost;
  r.gradientNorm = summary.iterations.empty() ? 0.0 : summary.iterations.back().gradient_norm;
  r.evaluationSeconds =
      summary.residual_evaluation_time_in_seconds + summary.jacobian_evaluation_time_in_seconds;
  r.linearSolverSeconds = summary.linear_solver_time_in_seconds;
  r.orderingSeconds = orderingSeconds;
  r.unknowns = unknowns;
  r.residuals = problem.NumResiduals();
  r.totalSeconds = secondsSince(start);
  return result;
}

}  // namespace

const char* solverName(Solver solver) {
  return solver == Solver::Newton ? "newton" : "ceres";
}

const char* hessianModeName(HessianMode mode) {
  switch (mode) {
    case HessianMode::Exact:
      return "exact";
    case HessianMode::Projected:
      return "projected";
    case HessianMode::Shifted:
      return "shifted";
    case HessianMode::ExactOrProjected:
      return "exact-projected";
  }
  return "exact";
}

Start parseStart(std::string_view name) {
  if (name == "linearized") return Start::Linearized;
  if (name == "given") return Start::AsGiven;
  throw InputError("MinimizeOptions.start " + std::string(name) + ": expected linearized or given");
}

Solver parseSolver(std::string_view name) {
  for (Solver s : {Solver::Newton, Solver::Ceres})
    if (name == solverName(s)) return s;
  throw InputError("MinimizeOptions.solver " + std::string(name) + ": expected newton or ceres");
}

HessianMode parseHessianMode(std::string_view name) {
  for (HessianMode m : {HessianMode::Exact, HessianMode::Projected, HessianMode::Shifted,
                        HessianMode::ExactOrProjected})
    if (name == hessianModeName(m)) return m;
  throw InputError("MinimizeOptions.hessian " + std::string(name) +
                   ": expected exact, projected, shifted or exact-projected");
}

void MinimizeOptions::validate() const {
  if (maxIterations < 1)
    throw InputError("MinimizeOptions.maxIterations " + std::to_string(maxIterations) +
                     ": expected at least 1");
  if (threads < 1)
    throw InputError("MinimizeOptions.threads " + std::to_string(threads) +
                     ": expected at least 1");
  for (double tolerance : {functionTolerance, gradientTolerance, parameterTolerance})
    if (!(tolerance > 0.0))
      throw InputError("MinimizeOptions: a tolerance " + numberText(tolerance) + ": expected > 0");
  if (solver == Solver::Ceres && hessian != HessianMode::Exact)
    throw InputError("MinimizeOptions.hessian " + std::string(hessianModeName(hessian)) +
                     ": applies to MinimizeOptions.solver newton (Ceres factors JᵀJ, not the "
                     "Hessian)");
}

KeptFactorization::KeptFactorization() = default;
KeptFactorization::~KeptFactorization() = default;
KeptFactorization::KeptFactorization(KeptFactorization&&) noexcept = default;
KeptFactorization& KeptFactorization::operator=(KeptFactorization&&) noexcept = default;

MinimizeResult minimize(const Problem& problem, const MinimizeOptions& options,
                        KeptFactorization* kept) {
  const std::vector<bool>& heldEdge = problem.boundary.fixedEdge;
  if (options.linearized != problem.linearizedClamp &&
      std::find(heldEdge.begin(), heldEdge.end(), true) != heldEdge.end())
    throw InputError(std::string("MinimizeOptions.linearized is ") +
                     (options.linearized ? "true" : "false") +
                     " but the problem's boundary ξ are clamped for the other solve "
                     "(ProblemOptions.linearizedClamp): build the problem with the same value");
  return minimize(problem, problem.boundary, options, kept);
}

MinimizeResult minimize(const Problem& problem, const BoundaryConditions& conditions,
                        const MinimizeOptions& options, KeptFactorization* kept) {
  const std::vector<const EnergyTerm*> terms = problem.termPointers();
  const Positions& rest = problem.rest.positions;
  const Eigen::VectorXd& restXi = problem.restXi;
  requireWellPosed(terms, conditions, problem.dof);
  const bool newton = !options.linearized && options.solver == Solver::Newton;
  if (problem.externalForce.rows() > 0 && !newton)
    throw InputError(
        "a load (ProblemOptions.load.gravity) needs the nonlinear Newton solve: not "
        "MinimizeOptions.linearized, not MinimizeOptions.solver ceres");
  if (!problem.obstacles.empty() && !newton)
    throw InputError(
        "ProblemOptions.obstacles needs the nonlinear Newton solve: not "
        "MinimizeOptions.linearized, not MinimizeOptions.solver ceres");
  MinimizeResult result;
  if (options.linearized) {
    result = minimizeLinearized(terms, conditions, rest, restXi, problem.dof);
  } else if (options.solver == Solver::Newton) {
    result = minimizeNewton(problem, conditions, options, kept);
  } else if (options.start == Start::Linearized) {
    const MinimizeResult predictor =
        minimizeLinearized(terms, conditions, rest, restXi, problem.dof);
    BoundaryConditions warm = conditions;
    warm.start = predictor.positions;
    if (predictor.xi.size() > 0) warm.xi = predictor.xi;
    result = minimizeNonlinear(terms, warm, problem.dof, options);
    MinimizeReport& r = result.report;
    r.totalSeconds += predictor.report.totalSeconds;
    r.evaluationSeconds += predictor.report.evaluationSeconds;
    r.linearSolverSeconds += predictor.report.linearSolverSeconds;
    r.orderingSeconds += predictor.report.orderingSeconds;
    r.factorizations += predictor.report.factorizations;
  } else {
    result = minimizeNonlinear(terms, conditions, problem.dof, options);
  }
  MinimizeReport& r = result.report;
  r.vertices = static_cast<int>(conditions.fixedVertex.size());
  for (bool f : conditions.fixedVertex) r.fixedVertices += f;
  for (size_t e = 0; e < conditions.fixedEdge.size(); ++e)
    r.freeEdgeUnknowns += usesEdgeUnknowns(terms) && !conditions.fixedEdge[e];
  return result;
}

}  // namespace flexure::optimize
