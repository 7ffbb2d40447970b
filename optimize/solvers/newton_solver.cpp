#include "optimize/solvers/newton_solver.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "modeling/errors.h"
#include "optimize/solvers/energy_evaluation.h"
#include "optimize/solvers/hessian_assembly.h"

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
  NewtonSolver(const std::vector<const EnergyTerm*>& terms, const BoundaryConditions& bc,
               const Positions& rest, const Eigen::VectorXd& restXi, const MinimizeOptions& options)
      : terms_(terms),
        bc_(bc),
        rest_(rest),
        restXi_(restXi),
        options_(options),
        withXi_(usesEdgeUnknowns(terms)),
        derivatives_(options.dof == DofMode::Height ? curvature::Derivatives::HeightOnly
                                                    : curvature::Derivatives::All),
        free_(freeUnknowns()),
        assembly_(terms, free_, static_cast<int>(rest.rows()), derivatives_),
        factorization_(assembly_,
                       options.simplicialBaseline ? std::vector<int>() : eliminationOrder(options),
                       options.simplicialBaseline),
        projection_(options.hessian == HessianMode::Projected
                        ? HessianProjection::PositiveSemidefinite
                        : HessianProjection::Exact) {}

  // The fill-reducing order: the geometric nested dissection of the free vertices in height
  // mode, CHOLMOD's AMD in xyz mode (empty). Measured, one run each: the n = 512 plate's cotan
  // solve (height) spent 8.0 s in linear solves on the geometric order against 12.9 s on AMD;
  // cotan fairing of a 50 000-vertex region of the bunny (xyz, scripts/bench fair) 30.4 s
  // against 15.2 s.
  std::vector<int> eliminationOrder(const MinimizeOptions& options) const {
    return options.dof == DofMode::Height ? hessianOrder(assembly_, rest_) : std::vector<int>();
  }

  MinimizeResult run(Clock::time_point start) {
    report_.orderingSeconds = secondsSince(start);  // the pattern, the order and the analysis
    MinimizeResult result;
    result.positions = bc_.start;
    if (withXi_) result.xi = bc_.xi;
    MinimizeResult base;  // where the solve starts, feasible
    base.positions = bc_.start;
    base.xi = result.xi;
    if (options_.start == Start::Linearized) {
      for (Eigen::Index v = 0; v < rest_.rows(); ++v)
        if (!bc_.fixedVertex[v]) base.positions.row(v) = rest_.row(v);
      for (Eigen::Index e = 0; withXi_ && e < restXi_.size(); ++e)
        if (!bc_.fixedEdge[e]) base.xi[e] = restXi_[e];
    }
    if (!options_.obstacles.empty()) options_.obstacles.requireOutside(base.positions, "the start");
    if (options_.start == Start::Linearized) {
      if (!predict(result)) return finish(std::move(result), start);
      if (!options_.obstacles.empty()) {
        // The predictor ignores the obstacles: go from the feasible start towards it only as far
        // as the obstacles allow.
        const double alpha = options_.obstacles.stepBound(
            base.positions, Positions(result.positions - base.positions));
        result.positions = base.positions + alpha * (result.positions - base.positions);
        if (withXi_) result.xi = base.xi + alpha * (result.xi - base.xi);
      }
    }
    iterate(result);
    return finish(std::move(result), start);
  }

 private:
  std::vector<bool> freeUnknowns() const {
    const int vertexCount = static_cast<int>(rest_.rows());
    std::vector<bool> free(3 * vertexCount + (withXi_ ? restXi_.size() : 0), false);
    for (int v = 0; v < vertexCount; ++v) {
      if (bc_.fixedVertex[v]) continue;
      for (int c = options_.dof == DofMode::Height ? 2 : 0; c < 3; ++c) free[3 * v + c] = true;
    }
    if (withXi_)
      for (int e = 0; e < restXi_.size(); ++e) free[3 * vertexCount + e] = !bc_.fixedEdge[e];
    return free;
  }

  HessianEvaluation evaluate(
      const Positions& x, const Eigen::VectorXd& xi, HessianProjection projection,
      const Eigen::VectorXd* fixedMove,
      curvature::SecondDerivatives kind = curvature::SecondDerivatives::Exact) {
    const auto t = Clock::now();
    HessianEvaluation e = assembly_.evaluate(x, xi, projection, fixedMove, kind);
    if (options_.externalForce.rows() > 0) {  // − fᵀx and its gradient − f
      e.energy -= loadEnergy(x);
      const std::vector<int>& unknowns = assembly_.freeUnknowns();
      for (size_t k = 0; k < unknowns.size(); ++k)
        if (unknowns[k] < x.size())
          e.gradient[static_cast<Eigen::Index>(k)] -= options_.externalForce.data()[unknowns[k]];
    }
    options_.obstacles.add(assembly_, x, e,
                           kind != curvature::SecondDerivatives::Exact ||
                               projection == HessianProjection::PositiveSemidefinite);
    report_.evaluationSeconds += secondsSince(t);
    return e;
  }

  // The displacement (#V by 3) of the step δ over the free unknowns.
  Positions displacement(const Eigen::VectorXd& delta) const {
    Positions dx = Positions::Zero(rest_.rows(), 3);
    const std::vector<int>& unknowns = assembly_.freeUnknowns();
    for (size_t k = 0; k < unknowns.size(); ++k)
      if (unknowns[k] < dx.size()) dx.data()[unknowns[k]] = delta[static_cast<Eigen::Index>(k)];
    return dx;
  }

  // The longest fraction of δ from x that keeps every vertex outside the obstacles (1 without).
  double feasibleStep(const MinimizeResult& x, const Eigen::VectorXd& delta) const {
    return options_.obstacles.empty()
               ? 1.0
               : options_.obstacles.stepBound(x.positions, displacement(delta));
  }

  // fᵀx of the external load (0 without one).
  double loadEnergy(const Positions& x) const {
    return options_.externalForce.rows() > 0 ? options_.externalForce.cwiseProduct(x).sum() : 0.0;
  }

  // Factors h's matrix, or where it is singular (or not positive definite) the matrix + μI with
  // the smallest μ = μ₀ 10^k that makes it so; μ₀ = μ_last / 10 (the previous iteration's μ, so
  // that a run of such iterations does not search from scratch each time), at least 1e-8 of the
  // largest diagonal magnitude.
  bool factor(HessianEvaluation& h) {
    const auto t = Clock::now();
    ++report_.factorizations;
    bool ok = factorization_.factor(h.values);
    if (ok) {
      lastShift_ = 0.0;
    } else {
      double largest = 0.0;
      for (int q = 0; q < assembly_.size(); ++q)
        largest = std::max(largest, std::abs(h.values[assembly_.columnStart()[q + 1] - 1]));
      for (double shift = std::max(1e-8 * largest, 0.1 * lastShift_); !ok && shift <= 1e8 * largest;
           shift *= 10.0) {
        ++report_.factorizations;
        ok = factorization_.factor(h.values, shift);
        if (ok) lastShift_ = shift;
      }
      ++shiftedFactorizations_;
    }
    report_.linearSolverSeconds += secondsSince(t);
    return ok;
  }

  // The Newton factorization at x: the exact Hessian h, or, where it is not positive definite
  // (away from a minimizer: a fairing start, a compressed membrane), the Gauss–Newton matrix JᵀJ
  // at x — positive semidefinite by construction, and the curvature Ceres' LM uses — shifted by
  // μI where singular. Near a strict minimizer the exact Hessian is positive definite, so the
  // last steps are Newton's. Measured against shifting the indefinite exact Hessian by μI:
  // fairing lion-head all-interior (midedge, 49 851 unknowns) 12 iterations, 28 s against 51,
  // 256 s (Ceres' LM: 36, 90 s); against projecting the element Hessians to positive
  // semidefinite (HessianMode::Projected), hinge + StVK in xyz lifted by a unit quadratic:
  // converged where projection did not in 400 iterations. h is replaced by what was factored.
  bool factorNewton(HessianEvaluation& h, const MinimizeResult& x) {
    const auto t = Clock::now();
    ++report_.factorizations;
    const bool exact = factorization_.factor(h.values);
    report_.linearSolverSeconds += secondsSince(t);
    if (exact) return true;
    ++gaussNewtonIterations_;
    h = evaluate(x.positions, x.xi, projection_, nullptr,
                 curvature::SecondDerivatives::GaussNewton);
    return factor(h);
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b) {
    const auto t = Clock::now();
    Eigen::VectorXd x = factorization_.solve(b);
    report_.linearSolverSeconds += secondsSince(t);
    return x;
  }

  // (x, ξ) + α δ, δ over the free unknowns.
  void step(const MinimizeResult& from, const Eigen::VectorXd& delta, double alpha,
            MinimizeResult& to) const {
    to.positions = from.positions;
    to.xi = from.xi;
    const std::vector<int>& unknowns = assembly_.freeUnknowns();
    const long positions = from.positions.size();
    for (size_t k = 0; k < unknowns.size(); ++k) {
      const long u = unknowns[k];
      if (u < positions)
        to.positions.data()[u] += alpha * delta[static_cast<Eigen::Index>(k)];
      else
        to.xi[u - positions] += alpha * delta[static_cast<Eigen::Index>(k)];
    }
  }

  // E (− fᵀx under an external load), or +∞ where an element is degenerate.
  double energy(const MinimizeResult& at) const {
    double sum = 0.0;
    try {
      for (const EnergyTerm* term : terms_) sum += term->energy(at.positions, at.xi);
    } catch (const NumericalError&) {
      return std::numeric_limits<double>::infinity();
    }
    sum -= loadEnergy(at.positions);
    sum += options_.obstacles.energy(at.positions);  // +∞ inside an obstacle
    return std::isfinite(sum) ? sum : std::numeric_limits<double>::infinity();
  }

  // The Gauss–Newton step from the rest state with the fixed unknowns moved to their values:
  // JᵀJ from first derivatives, which at a stress-free rest (r = 0) is the exact Hessian, so
  // that the step is the Newton step and the linearized minimizer. Its factor serves the first
  // chord steps. false (the report says why) when it fails.
  bool predict(MinimizeResult& result) {
    const Positions move = bc_.start - rest_;
    if (options_.dof == DofMode::Height && move.leftCols(2).cwiseAbs().maxCoeff() != 0.0) {
      // x, y moved in height mode: the z-only Hessian has no coupling to them. Start from the
      // linearized minimizer with all derivatives (one least-squares solve) instead.
      MinimizeOptions linear = options_;
      linear.linearized = true;
      const MinimizeResult predictor = minimize(terms_, bc_, rest_, restXi_, linear);
      result.positions = predictor.positions;
      if (withXi_) result.xi = predictor.xi;
      report_.factorizations += 1;
      report_.evaluationSeconds += predictor.report.evaluationSeconds;
      report_.linearSolverSeconds += predictor.report.linearSolverSeconds;
      return true;
    }
    const Eigen::VectorXd fixedMove = unknownVector(
        move, withXi_ ? Eigen::VectorXd(bc_.xi - restXi_) : Eigen::VectorXd(), withXi_);
    const Eigen::VectorXd restXi = withXi_ ? restXi_ : Eigen::VectorXd();
    HessianEvaluation h =
        evaluate(rest_, restXi, projection_, &fixedMove, curvature::SecondDerivatives::GaussNewton);
    if (!factor(h)) {
      report_.termination = "the Hessian at rest could not be factored";
      return false;
    }
    const Eigen::VectorXd delta = solve(-(h.gradient + h.fixedCoupling));
    if (!delta.allFinite()) {
      report_.termination = "the linearized predictor is not finite";
      return false;
    }
    MinimizeResult atRest;
    atRest.positions = bc_.start;  // the fixed unknowns at their values, the free ones at rest
    if (withXi_) atRest.xi = bc_.xi;
    const std::vector<int>& unknowns = assembly_.freeUnknowns();
    const long positions = rest_.size();
    for (int u : unknowns) {
      if (u < positions)
        atRest.positions.data()[u] = rest_.data()[u];
      else
        atRest.xi[u - positions] = restXi_[u - positions];
    }
    step(atRest, delta, 1.0, result);
    haveFactor_ = true;
    return true;
  }

  // E and ∇E over the free unknowns at x, from first derivatives only (no Hessian).
  HessianEvaluation gradientAt(const MinimizeResult& x) {
    return evaluate(x.positions, x.xi, HessianProjection::Exact, nullptr,
                    curvature::SecondDerivatives::None);
  }

  // Each iteration evaluates E and ∇E (first derivatives) and, while a factor is at hand, the
  // step δ = −F⁻¹∇E with it. The iteration has converged when the decrease ½ ∇Eᵀ F⁻¹ ∇E it
  // predicts is below functionTolerance · E — no new factorization is made to confirm. Otherwise
  // δ is taken as a chord step if the predicted decrease shrank at least kChordContraction-fold
  // since the last step (the factor still describes E well: modified Newton converges linearly
  // with that rate), else the exact Hessian at x is assembled and factored: a Newton step.
  void iterate(MinimizeResult& x) {
    MinimizeResult trial;
    double previousDecrement = std::numeric_limits<double>::infinity();
    for (int iteration = 0;; ++iteration) {
      HessianEvaluation at = gradientAt(x);
      if (iteration == 0) report_.initialEnergy = at.energy;
      report_.finalEnergy = at.energy;
      gradient_ = at.gradient;
      const double gradientMax = at.gradient.size() > 0 ? at.gradient.cwiseAbs().maxCoeff() : 0.0;
      if (!std::isfinite(at.energy) || !at.gradient.allFinite()) {
        report_.termination = "the energy or its gradient is not finite";
        return;
      }
      if (gradientMax <= options_.gradientTolerance) {
        converge("gradient max-norm " + number(gradientMax) +
                 " <= " + number(options_.gradientTolerance));
        return;
      }
      if (iteration == options_.maxIterations) {
        report_.termination = "no convergence in " + std::to_string(iteration) + " iterations";
        return;
      }
      Eigen::VectorXd delta;
      double decrement = 0.0;
      bool chord = false;
      if (haveFactor_) {
        delta = solve(-at.gradient);
        decrement = -at.gradient.dot(delta);
        if (decrement > 0.0 &&
            0.5 * decrement <= options_.functionTolerance * std::abs(at.energy)) {
          finalStep(x, at, delta, "predicted decrease " + number(0.5 * decrement));
          return;
        }
        chord = decrement > 0.0 && decrement <= kChordContraction * previousDecrement &&
                !options_.simplicialBaseline;
      }
      if (!chord) {
        HessianEvaluation h = evaluate(x.positions, x.xi, projection_, nullptr);
        if (!factorNewton(h, x)) {
          report_.termination = "the Hessian could not be made positive definite";
          return;
        }
        haveFactor_ = true;
        delta = solve(-h.gradient);
        decrement = -h.gradient.dot(delta);  // λ², > 0 for a positive definite H
        if (!std::isfinite(decrement) || decrement <= 0.0) {
          report_.termination = "the Newton step is not a descent direction";
          return;
        }
        if (0.5 * decrement <= options_.functionTolerance * std::abs(at.energy)) {
          finalStep(x, at, delta, "Newton decrement " + number(0.5 * decrement));
          return;
        }
      }
      double alpha = feasibleStep(x, delta), trialEnergy = 0.0;
      bool decreased = true;
      for (;; alpha *= 0.5) {
        step(x, delta, alpha, trial);
        trialEnergy = energy(trial);
        // Armijo, with room for the roundoff of E itself when the decrease is at that level.
        if (trialEnergy <= at.energy - 1e-4 * alpha * decrement + 1e-14 * std::abs(at.energy))
          break;
        if (alpha < (chord ? 0.1 : 1e-12)) {
          decreased = false;
          break;
        }
      }
      if (!decreased && !chord) {
        report_.termination = "the line search found no decrease of the energy";
        return;
      }
      // A chord step that needed damping, or failed, asks for a new factor next time.
      previousDecrement = chord && alpha < 1.0 ? 0.0 : decrement;
      if (!decreased) continue;
      std::swap(x, trial);
      ++report_.iterations;
      ++(chord ? chordSteps_ : newtonSteps_);
      if (options_.progress) {
        std::fprintf(stderr,
                     "  iteration %3d  %-6s energy %.10e  |gradient|max %.3e  decrement %.3e  "
                     "step %.3g\n",
                     report_.iterations, chord ? "chord" : "newton", trialEnergy, gradientMax,
                     decrement, alpha);
      }
    }
  }

  // Converged at x, whose predicted decrease is below the tolerance: the step δ already solved
  // for is taken too where it does not raise E beyond roundoff (it costs no factorization and
  // brings x closer by the step's contraction), and ∇E is evaluated for the report.
  void finalStep(MinimizeResult& x, const HessianEvaluation& at, const Eigen::VectorXd& delta,
                 const std::string& why) {
    MinimizeResult trial;
    step(x, delta, 1.0, trial);
    if (energy(trial) <= at.energy + 1e-14 * std::abs(at.energy)) {
      std::swap(x, trial);
      const HessianEvaluation end = gradientAt(x);
      report_.finalEnergy = end.energy;
      gradient_ = end.gradient;
    }
    converge(why + " <= " + number(options_.functionTolerance) +
             " E = " + number(options_.functionTolerance * std::abs(at.energy)));
  }

  void converge(const std::string& why) {
    report_.converged = true;
    report_.termination = "CONVERGENCE: " + why;
  }

  static std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
  }

  MinimizeResult finish(MinimizeResult result, Clock::time_point start) {
    report_.solver = "newton";
    if (!report_.converged && report_.termination.rfind("NO_CONVERGENCE", 0) != 0)
      report_.termination = "NO_CONVERGENCE: " + report_.termination;
    report_.termination += " after " + std::to_string(newtonSteps_) + " Newton and " +
                           std::to_string(chordSteps_) + " chord steps";
    if (gaussNewtonIterations_ > 0 || shiftedFactorizations_ > 0) {
      report_.termination += " (" + std::to_string(gaussNewtonIterations_) +
                             " on J^T J where the Hessian was indefinite, " +
                             std::to_string(shiftedFactorizations_) + " shifted by mu I)";
    }
    report_.gradientNorm = gradient_.size() > 0 ? gradient_.norm() : 0.0;
    report_.unknowns = assembly_.size();
    report_.totalSeconds = secondsSince(start);
    result.report = report_;
    return result;
  }

  const std::vector<const EnergyTerm*>& terms_;
  const BoundaryConditions& bc_;
  const Positions& rest_;
  const Eigen::VectorXd& restXi_;
  const MinimizeOptions& options_;
  const bool withXi_;
  const curvature::Derivatives derivatives_;
  const std::vector<bool> free_;
  HessianAssembly assembly_;
  HessianFactorization factorization_;
  const HessianProjection projection_;
  MinimizeReport report_;
  Eigen::VectorXd gradient_;
  // A chord step is taken while the predicted decrease shrinks at least this much per step
  // (the error about √ of it).
  static constexpr double kChordContraction = 0.1;
  bool haveFactor_ = false;  // a factor from an earlier point (the predictor's or a Newton step's)
  int newtonSteps_ = 0, chordSteps_ = 0;
  int gaussNewtonIterations_ = 0, shiftedFactorizations_ = 0;
  double lastShift_ = 0.0;
};

}  // namespace

MinimizeResult minimizeNewton(const std::vector<const EnergyTerm*>& terms,
                              const BoundaryConditions& conditions, const Positions& rest,
                              const Eigen::VectorXd& restXi, const MinimizeOptions& options) {
  const auto start = Clock::now();
  NewtonSolver solver(terms, conditions, rest, restXi, options);
  return solver.run(start);
}

}  // namespace flexure::optimize
