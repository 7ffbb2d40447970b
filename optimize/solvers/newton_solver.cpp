#include "optimize/solvers/newton_solver.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "modeling/errors.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/linear/linearized_solver.h"
#include "optimize/problem.h"
#include "optimize/solvers/hessian_factorization.h"
#include "optimize/solvers/newton_loop.h"
#include "optimize/solvers/static_energy.h"

namespace flexure::optimize {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The configuration (x, ξ) as one vector of all unknowns, and back.
Eigen::VectorXd unknownVector(const Positions& x, const Eigen::VectorXd& xi, bool withXi) {
  const Eigen::Index positions = x.size();
  Eigen::VectorXd u(positions + (withXi ? xi.size() : 0));
  u.head(positions) = Eigen::Map<const Eigen::VectorXd>(x.data(), positions);
  if (withXi) u.tail(xi.size()) = xi;
  return u;
}

class NewtonSolver {
 public:
  // `kept`: the factorization of an earlier solve, used (with its factor, when `haveFactor`) if
  // it serves this problem's pattern; else null.
  NewtonSolver(const Problem& problem, const BoundaryConditions& bc, const MinimizeOptions& options,
               std::unique_ptr<HessianFactorization> kept, bool haveFactor)
      : terms_(problem.termPointers()),
        bc_(bc),
        rest_(problem.rest.positions),
        restXi_(problem.restXi),
        dof_(problem.dof),
        externalForce_(problem.externalForce),
        obstacles_(problem.obstacles),
        options_(options),
        withXi_(usesEdgeUnknowns(terms_)),
        derivatives_(dof_ == DofMode::Height ? curvature::Derivatives::HeightOnly
                                             : curvature::Derivatives::All),
        free_(freeUnknowns()),
        assembly_(terms_, free_, static_cast<int>(rest_.rows()), derivatives_),
        inherited_(kept != nullptr && kept->serves(assembly_)),
        factorization_(inherited_ ? std::move(kept) : analysed()),
        loop_(assembly_, *factorization_),
        projection_(options.hessian == HessianMode::Projected
                        ? HessianProjection::PositiveSemidefinite
                        : HessianProjection::Exact) {
    if (inherited_ && haveFactor) loop_.adoptFactor();
  }

  // The factorization, and whether it holds a factor, for the next solve (KeptFactorization).
  std::unique_ptr<HessianFactorization> releaseFactorization() { return std::move(factorization_); }
  bool haveFactor() const { return loop_.haveFactor(); }

  // The fill-reducing order: the geometric nested dissection of the free vertices in height
  // mode without ξ; otherwise one CHOLMOD computes (computedOrder). Measured against AMD, one run
  // each: the n = 512 plate's cotan solve (height) spent 8.0 s in linear solves on the geometric
  // order against 12.9 s; cotan fairing of a 50 000-vertex region of the bunny (xyz,
  // scripts/bench fair) took 30.4 s on it against 15.2 s, so xyz takes none.
  std::vector<int> eliminationOrder() const {
    return dof_ == DofMode::Height ? hessianOrder(assembly_, rest_) : std::vector<int>();
  }
  // The order CHOLMOD computes where no order is given, chosen by measurement. A height field
  // with free ξ (midedge's plate: from the linearized start, about two factorizations) takes
  // AMD: on the n = 512 plate (bench/solve_bench.cpp, that size, midedge, the Newton solve;
  // 1 044 489 unknowns, 4 iterations, 2 factorizations; both builds in one run, idle machine)
  // the solve took 13.5 s (2.6 × the floor; analysis 1.4 s, nnz(L) 1.17e8) against 24.9 s
  // (4.8 ×; analysis 12.9 s, nnz(L) 1.09e8) with CHOLMOD's nested dissection, and at n = 256
  // 2.6 s against 5.0. METIS (nnz(L) 1.11e8) took 18 s to find on a loaded machine; the geometric
  // nested dissection of vertices and ξ (each ξ at its edge), 2 s, but nnz(L) 2.33e8 and 3.1 GB.
  // xyz (fairing, shells: more factorizations of fewer unknowns) takes the nested dissection:
  // fairing 50 000 vertices of the bunny (bench/fair_bench.cpp, midedge on Newton; 7 iterations,
  // 6 factorizations) took 26.3 s and 1.26 GB with it, 30.2 s and 1.49 GB with AMD.
  FillReducingOrder computedOrder() const {
    return withXi_ && dof_ == DofMode::Height ? FillReducingOrder::Amd
                                              : FillReducingOrder::NestedDissection;
  }
  // The symbolic analysis of this problem's pattern.
  std::unique_ptr<HessianFactorization> analysed() const {
    return std::make_unique<HessianFactorization>(
        assembly_, options_.simplicialBaseline ? std::vector<int>() : eliminationOrder(),
        computedOrder(), options_.simplicialBaseline);
  }

  MinimizeResult run(Clock::time_point start) {
    report_.orderingSeconds = secondsSince(start);  // the pattern, the order and the analysis
    Configuration result{bc_.start, withXi_ ? bc_.xi : Eigen::VectorXd()};
    Configuration base = result;  // where the solve starts, feasible
    if (options_.start == Start::Linearized) {
      for (Eigen::Index v = 0; v < rest_.rows(); ++v)
        if (!bc_.fixedVertex[v]) base.positions.row(v) = rest_.row(v);
      for (Eigen::Index e = 0; withXi_ && e < restXi_.size(); ++e)
        if (!bc_.fixedEdge[e]) base.xi[e] = restXi_[e];
    }
    if (!obstacles_.empty()) obstacles_.requireOutside(base.positions, "the start");
    if (options_.start == Start::Linearized) {
      if (!predict(result)) return finish(std::move(result), start);
      if (!obstacles_.empty()) {
        // The predictor ignores the obstacles: go from the feasible start towards it only as far
        // as the obstacles allow.
        const double alpha =
            obstacles_.stepBound(base.positions, Positions(result.positions - base.positions));
        result.positions = base.positions + alpha * (result.positions - base.positions);
        if (withXi_) result.xi = base.xi + alpha * (result.xi - base.xi);
      }
    }
    StaticEnergy objective = staticEnergy(result);
    Eigen::VectorXd y = objective.freeValues(result);
    StaticStopRule rule;
    rule.functionTolerance = options_.functionTolerance;
    rule.gradientTolerance = options_.gradientTolerance;
    rule.maxIterations = options_.maxIterations;
    rule.chordSteps = !options_.simplicialBaseline;
    rule.quasiNewtonPairs = options_.quasiNewton ? kQuasiNewtonPairs : 0;
    rule.keepGaussNewton = options_.keepGaussNewton;
    rule.progress = options_.progress;
    rule.observer = options_.observer;
    rule.inheritedFactor = loop_.factorAdopted();  // not when the predictor factored
    if (options_.hessian == HessianMode::Shifted) rule.indefinite = IndefiniteHessian::Shifted;
    if (options_.hessian == HessianMode::ExactOrProjected)
      rule.indefinite = IndefiniteHessian::Projected;
    const NewtonResult loop = loop_.run(objective, y, rule);
    add(loop);
    report_.iterations = loop.iterations;
    report_.initialEnergy = loop.initialValue;
    report_.finalEnergy = loop.finalValue;
    gradient_ = loop.gradient;
    newtonSteps_ = loop.newtonSteps;
    chordSteps_ = loop.chordSteps;
    gaussNewtonIterations_ = loop.gaussNewtonSteps;
    stop(loop.stop, loop.stop == NewtonStop::Converged ? loop.convergedBy : std::string());
    return finish(objective.configuration(y), start);
  }

 private:
  std::vector<bool> freeUnknowns() const {
    return freeUnknownMask(bc_.fixedVertex, withXi_ ? bc_.fixedEdge : std::vector<bool>(), dof_);
  }

  // The objective with the fixed unknowns of `at`.
  StaticEnergy staticEnergy(const Configuration& at) const {
    return StaticEnergy(assembly_, at, terms_, externalForce_, obstacles_, projection_);
  }

  // The counts and times of a loop (or the predictor's factor and solve) into the report.
  void add(const NewtonResult& part) {
    report_.factorizations += part.factorizations;
    report_.evaluationSeconds += part.evaluationSeconds;
    report_.linearSolverSeconds += part.linearSolverSeconds;
    shiftedFactorizations_ += part.shiftedFactorizations;
  }

  // Why the solve stopped, in the report's words.
  void stop(NewtonStop why, const std::string& convergedBy) {
    report_.stop = why;
    report_.converged = why == NewtonStop::Converged;
    if (why == NewtonStop::Converged)
      report_.termination = "CONVERGENCE: " + convergedBy;
    else if (why == NewtonStop::MaxIterations)
      report_.termination =
          "no convergence in " + std::to_string(options_.maxIterations) + " iterations";
    else
      report_.termination = newtonStopMessage(why);
  }

  // The minimizer of the linearized energy ½ |J (u − ū)|² (minimize.h) over the free unknowns, J
  // the residual Jacobian at rest with all derivatives (the fixed vertices move in x, y too), u's
  // fixed entries the boundary values: the linearized solve of minimize() itself.
  void predictLinearized(Configuration& result) {
    const auto t = Clock::now();
    LinearizedUnknowns unknowns{bc_.fixedVertex, bc_.fixedEdge, true};
    unknowns.fixedMoveInPlane = true;
    const LinearizedSolver solver(terms_, rest_, restXi_, unknowns);
    LinearizedSolution solution = solver.solve(bc_);
    report_.evaluationSeconds += solver.jacobianSeconds();
    report_.linearSolverSeconds += secondsSince(t) - solver.jacobianSeconds();
    report_.factorizations += solver.factorizations();
    result.positions = std::move(solution.positions);
    if (withXi_) result.xi = std::move(solution.xi);
  }

  // The Gauss–Newton step from the rest state with the fixed unknowns moved to their values:
  // JᵀJ from first derivatives, which at a stress-free rest (r = 0) is the exact Hessian, so
  // that the step is the Newton step and the linearized minimizer. Its factor serves the first
  // chord steps. false (the report says why) when it fails.
  bool predict(Configuration& result) {
    const Positions move = bc_.start - rest_;
    if (dof_ == DofMode::Height && move.leftCols(2).cwiseAbs().maxCoeff() != 0.0) {
      // x, y moved in height mode: the z-only Hessian has no coupling to them. Start from the
      // linearized minimizer with all derivatives (one least-squares solve) instead.
      predictLinearized(result);
      return true;
    }
    const Eigen::VectorXd fixedMove = unknownVector(
        move, withXi_ ? Eigen::VectorXd(bc_.xi - restXi_) : Eigen::VectorXd(), withXi_);
    const Eigen::VectorXd restXi = withXi_ ? restXi_ : Eigen::VectorXd();
    NewtonResult part;
    const auto t = Clock::now();
    const HessianEvaluation h = staticEnergy(result).evaluateAt(
        Configuration{rest_, restXi}, curvature::SecondDerivatives::GaussNewton, &fixedMove);
    part.evaluationSeconds += secondsSince(t);
    const bool factored = loop_.factorShifted(h.values, part);
    const Eigen::VectorXd delta =
        factored ? loop_.solve(-(h.gradient + h.fixedCoupling), part) : Eigen::VectorXd();
    add(part);
    if (!factored) {
      stop(NewtonStop::NotPositiveDefinite, "");
      report_.termination = "the Hessian at rest could not be factored";
      return false;
    }
    if (!delta.allFinite()) {
      stop(NewtonStop::NonFinite, "");
      report_.termination = "the linearized predictor is not finite";
      return false;
    }
    Configuration atRest{bc_.start, withXi_ ? bc_.xi : Eigen::VectorXd()};
    // the fixed unknowns at their values, the free ones at rest
    const std::vector<int>& unknowns = assembly_.freeUnknowns();
    const long positions = rest_.size();
    for (int u : unknowns) {
      if (u < positions)
        atRest.positions.data()[u] = rest_.data()[u];
      else
        atRest.xi[u - positions] = restXi_[u - positions];
    }
    const StaticEnergy fromRest = staticEnergy(atRest);
    result = fromRest.configuration(fromRest.freeValues(atRest) + 1.0 * delta);
    return true;
  }

  MinimizeResult finish(Configuration at, Clock::time_point start) {
    report_.solver = "newton";
    if (!report_.converged) report_.termination = "NO_CONVERGENCE: " + report_.termination;
    report_.termination += " after " + std::to_string(newtonSteps_) + " Newton and " +
                           std::to_string(chordSteps_) + " chord steps";
    if (gaussNewtonIterations_ > 0 || shiftedFactorizations_ > 0) {
      const char* indefiniteStep = options_.hessian == HessianMode::ExactOrProjected
                                       ? " projected where the Hessian was indefinite, "
                                       : " on J^T J where the Hessian was indefinite, ";
      report_.termination += " (" + std::to_string(gaussNewtonIterations_) + indefiniteStep +
                             std::to_string(shiftedFactorizations_) + " shifted by mu I)";
    }
    report_.gradientNorm = gradient_.size() > 0 ? gradient_.norm() : 0.0;
    report_.unknowns = assembly_.size();
    report_.totalSeconds = secondsSince(start);
    MinimizeResult result;
    result.positions = std::move(at.positions);
    result.xi = std::move(at.xi);
    result.report = report_;
    return result;
  }

  const std::vector<const EnergyTerm*> terms_;
  const BoundaryConditions& bc_;
  const Positions& rest_;
  const Eigen::VectorXd& restXi_;
  const DofMode dof_;
  const Positions& externalForce_;
  const ObstacleBarrier& obstacles_;
  const MinimizeOptions& options_;
  const bool withXi_;
  const curvature::Derivatives derivatives_;
  const std::vector<bool> free_;
  HessianAssembly assembly_;
  const bool inherited_;  // the factorization is a KeptFactorization's
  std::unique_ptr<HessianFactorization> factorization_;
  NewtonLoop loop_;
  const HessianProjection projection_;
  MinimizeReport report_;
  Eigen::VectorXd gradient_;
  int newtonSteps_ = 0, chordSteps_ = 0;
  int gaussNewtonIterations_ = 0, shiftedFactorizations_ = 0;
};

}  // namespace

MinimizeResult minimizeNewton(const Problem& problem, const BoundaryConditions& conditions,
                              const MinimizeOptions& options, KeptFactorization* kept) {
  const auto start = Clock::now();
  NewtonSolver solver(problem, conditions, options,
                      kept ? std::move(kept->factorization_) : nullptr, kept && kept->haveFactor_);
  MinimizeResult result = solver.run(start);
  if (kept) {
    kept->haveFactor_ = solver.haveFactor();
    kept->factorization_ = solver.releaseFactorization();
  }
  return result;
}

}  // namespace flexure::optimize
