#include "optimize/solvers/newton_loop.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "modeling/errors.h"
#include "optimize/solvers/lbfgs_update.h"

namespace flexure::optimize {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// A chord step is taken while the predicted decrease shrinks at least this much per step (the
// error about √ of it): modified Newton converges linearly with that rate.
constexpr double kChordContraction = 0.1;
// An L-BFGS step on the kept factor is taken while λ² shrinks at least this much per step.
// Measured on the drape benchmark (2 500 vertices, 40 steps, m = 6; factorizations per step with
// 0.1 / 0.5 / 0.8): hinge 1.56 / 1.00 / 0.79, cotan 1.56 / 0.85 / 0.62, midedge 0.33 / 0.10 /
// 0.08 (chord steps at 0.1: 1.62, 1.77, 0.46), with iterations per step 5.2 / 5.9 / 6.3,
// 5.4 / 6.8 / 7.5, 4.4 / 5.4 / 5.3 — a Newton step near contact contracts λ² only 0.1–0.7-fold
// itself, so a factorization bought by the stricter test often gains no more than the
// quasi-Newton step it replaced.
constexpr double kQuasiNewtonContraction = 0.5;

// H x for the symmetric H whose upper triangle (diagonal included) `values` holds in the
// compressed columns (columnStart, rowIndex).
Eigen::VectorXd symmetricProduct(const std::vector<int>& columnStart,
                                 const std::vector<int>& rowIndex,
                                 const std::vector<double>& values, const Eigen::VectorXd& x) {
  Eigen::VectorXd product = Eigen::VectorXd::Zero(x.size());
  for (long j = 0; j < x.size(); ++j) {
    double column = 0.0;
    for (int e = columnStart[j]; e < columnStart[j + 1]; ++e) {
      const int i = rowIndex[e];
      column += values[e] * x[i];
      if (i != j) product[i] += values[e] * x[j];
    }
    product[j] += column;
  }
  return product;
}

}  // namespace

const char* newtonStopMessage(NewtonStop stop) {
  switch (stop) {
    case NewtonStop::Running:
      return "not stopped";
    case NewtonStop::Converged:
      return "converged";
    case NewtonStop::MaxIterations:
      return "no convergence within the iteration limit";
    case NewtonStop::NonFinite:
      return "the energy or its gradient is not finite";
    case NewtonStop::NotPositiveDefinite:
      return "the Hessian could not be made positive definite";
    case NewtonStop::NotDescent:
      return "the Newton step is not a descent direction";
    case NewtonStop::LineSearchFailed:
      return "the line search found no decrease of the energy";
    case NewtonStop::Infeasible:
      return "a fixed vertex is moved into an obstacle";
    case NewtonStop::SolverFailure:
      return "the solver failed";
    case NewtonStop::Stopped:
      return "stopped by its observer";
  }
  return "";
}

Eigen::VectorXd Objective::freeValues(const Configuration& at) const {
  const std::vector<int>& unknowns = assembly_.freeUnknowns();
  const long positions = at.positions.size();
  Eigen::VectorXd y(size());
  for (int k = 0; k < size(); ++k) {
    const long u = unknowns[k];
    y[k] = u < positions ? at.positions.data()[u] : at.xi[u - positions];
  }
  return y;
}

void Objective::place(const Eigen::VectorXd& y, Configuration& at) const {
  const std::vector<int>& unknowns = assembly_.freeUnknowns();
  const long positions = at.positions.size();
  for (int k = 0; k < size(); ++k) {
    const long u = unknowns[k];
    (u < positions ? at.positions.data()[u] : at.xi[u - positions]) = y[k];
  }
}

Configuration Objective::configuration(const Eigen::VectorXd& y) const {
  if (y.size() != size())
    throw InputError("x has " + std::to_string(y.size()) + " entries, the problem " +
                     std::to_string(size()) + " free unknowns");
  Configuration at = fixedPart_;
  place(y, at);
  return at;
}

Positions Objective::displacement(const Eigen::VectorXd& delta) const {
  Positions dx = Positions::Zero(fixedPart_.positions.rows(), 3);
  const std::vector<int>& unknowns = assembly_.freeUnknowns();
  for (int k = 0; k < size(); ++k)
    if (unknowns[k] < dx.size()) dx.data()[unknowns[k]] = delta[k];
  return dx;
}

double Objective::stepBound(const Eigen::VectorXd& y, const Eigen::VectorXd& delta) {
  const Eigen::VectorXd bounds = vertexStepBounds(y, delta);
  return bounds.size() == 0 ? 1.0 : bounds.minCoeff();
}

HessianEvaluation NewtonLoop::evaluate(Objective& objective, const Eigen::VectorXd& y,
                                       curvature::SecondDerivatives kind, NewtonResult& result) {
  const auto t = Clock::now();
  HessianEvaluation at = objective.evaluate(y, kind);
  result.evaluationSeconds += secondsSince(t);
  return at;
}

Eigen::VectorXd NewtonLoop::solve(const Eigen::VectorXd& b, NewtonResult& result) {
  const auto t = Clock::now();
  Eigen::VectorXd x = factorization_.solve(b);
  result.linearSolverSeconds += secondsSince(t);
  return x;
}

// Factors H, or where it is singular (or not positive definite) H + μI with the smallest
// μ = μ₀ 10^k that makes it so; μ₀ = μ_last / 10 (the previous shifted factor's μ, so that a run
// of such iterations does not search from scratch each time), at least 1e-8 of the largest
// diagonal magnitude.
bool NewtonLoop::factorShifted(const std::vector<double>& values, NewtonResult& result,
                               bool tryUnshifted) {
  const auto t = Clock::now();
  bool ok = false;
  if (tryUnshifted) {
    ++result.factorizations;
    ok = factorization_.factor(values);
  }
  if (ok) {
    lastShift_ = 0.0;
  } else {
    double largest = 0.0;  // sorted upper columns end on the diagonal
    for (int q = 0; q < assembly_.size(); ++q)
      largest = std::max(largest, std::abs(values[assembly_.columnStart()[q + 1] - 1]));
    for (double shift = std::max(1e-8 * largest, 0.1 * lastShift_); !ok && shift <= 1e8 * largest;
         shift *= 10.0) {
      ++result.factorizations;
      ok = factorization_.factor(values, shift);
      if (ok) lastShift_ = shift;
    }
    ++result.shiftedFactorizations;
  }
  haveFactor_ = ok;
  adopted_ = false;
  chordHessian_.clear();
  result.linearSolverSeconds += secondsSince(t);
  return ok;
}

// The Newton factor at y: the Hessian of `kind` in h, or, where it is not positive definite, the
// rule's: H + μI (Shifted), or the Gauss–Newton matrix JᵀJ at y — positive semidefinite by
// construction, and the curvature Ceres' LM uses — or the element Hessians projected to positive
// semidefinite (Projected), each shifted by μI where singular. Measured against shifting the
// indefinite Hessian by μI: fairing lion-head all-interior (midedge, 49 851 unknowns) 12
// iterations, 28 s against 51, 256 s (Ceres' LM: 36, 90 s); against projecting the element
// Hessians, hinge + StVK in xyz lifted by a unit quadratic: converged where projection did not in
// 400 iterations. h is replaced by what was factored.
bool NewtonLoop::factorNewton(Objective& objective, const Eigen::VectorXd& y,
                              IndefiniteHessian indefinite, bool fallback, HessianEvaluation& h,
                              NewtonResult& result) {
  const auto t = Clock::now();
  ++result.factorizations;
  const bool exact = factorization_.factor(h.values);
  result.linearSolverSeconds += secondsSince(t);
  chordHessian_.clear();
  adopted_ = false;
  if (exact) return haveFactor_ = true;
  // Already the fallback's matrix (a step that keeps it), or the rule shifts: H + μI.
  if (fallback || indefinite == IndefiniteHessian::Shifted)
    return factorShifted(h.values, result, false);
  ++result.gaussNewtonSteps;
  h = evaluate(objective, y,
               indefinite == IndefiniteHessian::Projected
                   ? curvature::SecondDerivatives::Projected
                   : curvature::SecondDerivatives::GaussNewton,
               result);
  return factorShifted(h.values, result);
}

// The Newton step δ = −H⁻¹∇f by conjugate gradients on H preconditioned by the kept factor F of
// an earlier Hessian (the stale-factor Newton–Krylov of Hecht, Lee, Shewchuk & O'Brien 2012,
// "Updated sparse Cholesky factors for corotational elastodynamics": F ≈ H makes F⁻¹H's
// spectrum cluster near 1, so a few iterations, each one product with H and one solve with F,
// replace a factorization). On entry δ = −F⁻¹∇f (the chord step, the first preconditioned
// residual from δ₀ = 0); on success δ is the step. Accepted when rᵀF⁻¹r ≤ η² ∇fᵀF⁻¹∇f
// (η = policy.pcgTolerance: the residual in F's norm, the first one being the chord step's
// decrement). false — δ unusable, H to be factored — after policy.pcgMaxIterations iterations, or
// where pᵀHp ≤ 0 along a search direction p (H not positive definite: the factoring path's
// indefinite-Hessian rule applies).
bool NewtonLoop::preconditionedStep(const std::vector<double>& hessian,
                                    const Eigen::VectorXd& gradient, const Policy& policy,
                                    Eigen::VectorXd& delta, NewtonResult& result) {
  const auto t = Clock::now();
  Eigen::VectorXd residual = -gradient, preconditioned = delta, direction = delta;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(gradient.size());
  const double initial = residual.dot(preconditioned);
  double current = initial;
  bool converged = false;
  for (int k = 0; k < policy.pcgMaxIterations && std::isfinite(current) && current > 0.0; ++k) {
    ++result.pcgIterations;
    const Eigen::VectorXd product =
        symmetricProduct(assembly_.columnStart(), assembly_.rowIndex(), hessian, direction);
    const double curvature = direction.dot(product);
    if (!(curvature > 0.0)) break;
    const double alpha = current / curvature;
    x += alpha * direction;
    residual -= alpha * product;
    preconditioned = factorization_.solve(residual);
    const double next = residual.dot(preconditioned);
    if (next <= policy.pcgTolerance * policy.pcgTolerance * initial) {
      converged = x.allFinite();
      break;
    }
    direction = preconditioned + (next / current) * direction;
    current = next;
  }
  result.linearSolverSeconds += secondsSince(t);
  if (!converged) return false;
  ++result.pcgSolves;
  delta = std::move(x);
  return true;
}

// Armijo on f from y along δ, α halved from α = bound: f(y + αδ) ≤ f(y) − 10⁻⁴ α λ² + f's
// roundoff (the comparison cannot judge a decrease below it, and δ descends on a positive
// definite model). The first trial evaluates ∇f too, which the next iteration uses when it passes
// (it usually does); later ones f alone, and ∇f where one passes. A chord step gets
// search.chordTrials trials: one that fails them asks for a Newton step rather than a short step.
// With search.scaleByVertexBounds, when the obstacles bound the step (bound < 1), δ with each
// vertex's move scaled by its own bound α_v is searched first, from α = 1, when that is still a
// descent direction — a vertex about to touch an obstacle then no longer holds every other vertex
// back to its fraction of the step (measured on the drape benchmark: the capped Newton steps of a
// contact step fell from tens to a few). `shortened`: the step taken was damped or scaled.
// false: no decrease.
bool NewtonLoop::searchStep(Objective& objective, const Eigen::VectorXd& y,
                            const HessianEvaluation& at, const Eigen::VectorXd& delta,
                            double decrement, double bound, bool chord, const LineSearch& search,
                            Eigen::VectorXd& trial, HessianEvaluation& trialAt, bool& shortened) {
  NewtonResult unused;
  const double roundoff = objective.roundoff(y, at.energy);
  double alpha = bound, slope = decrement;  // slope = −∇fᵀ direction
  Eigen::VectorXd direction = delta;
  bool scaledDirection = false;
  if (search.scaleByVertexBounds && bound < 1.0) {
    const Eigen::VectorXd bounds = objective.vertexStepBounds(y, delta);
    const std::vector<int>& unknowns = objective.assembly().freeUnknowns();
    const long positionCount = 3 * bounds.size();
    Eigen::VectorXd scaled = delta;
    for (int k = 0; k < scaled.size(); ++k)
      if (unknowns[k] < positionCount) scaled[k] *= bounds[unknowns[k] / 3];
    const double scaledSlope = -at.gradient.dot(scaled);
    if (scaledSlope > 0.0) {
      direction = std::move(scaled);
      slope = scaledSlope;
      alpha = 1.0;
      scaledDirection = true;
    }
  }
  for (int trials = 1;; ++trials, alpha *= 0.5) {
    trial = y + alpha * direction;
    double trialValue = 0.0;
    if (trials == 1) {
      try {
        trialAt = evaluate(objective, trial, curvature::SecondDerivatives::None, unused);
        trialValue = trialAt.energy;
      } catch (const NumericalError&) {  // a degenerate element: as lineSearchValue says
        trialValue = std::numeric_limits<double>::infinity();
      }
    } else {
      trialValue = objective.lineSearchValue(trial);
    }
    // +∞ inside an obstacle; NaN never passes.
    if (trialValue <= at.energy - 1e-4 * alpha * slope + roundoff ||
        (search.acceptBelowRoundoff && std::isfinite(trialValue) &&
         0.5 * alpha * slope <= roundoff)) {
      if (trials > 1)
        trialAt = evaluate(objective, trial, curvature::SecondDerivatives::None, unused);
      shortened = alpha < 1.0 || scaledDirection;
      return true;
    }
    if (scaledDirection && trials == 3) {  // back to δ itself, from α = bound
      scaledDirection = false;
      direction = delta;
      slope = decrement;
      alpha = 2.0 * bound;
      continue;
    }
    if (chord ? trials == search.chordTrials : alpha < search.smallestStep) {
      shortened = alpha < 1.0 || scaledDirection;
      return false;
    }
  }
}

// The static rule: converged when ‖∇f‖∞ ≤ gradientTolerance at an iterate, or when a step's
// predicted decrease ½ λ² ≤ functionTolerance · |f| (a chord step's, whether or not it would be
// taken: no factorization is made only to confirm); then the step already solved for is taken
// too where it does not raise f beyond roundoff (it costs no factorization and brings y closer by
// the step's contraction), and ∇f is evaluated for the report. Counts accepted steps.
class NewtonLoop::StaticStop {
 public:
  StaticStop(const StaticStopRule& rule) : rule_(rule) {}

  bool stopsAt(const HessianEvaluation& at, int iteration, NewtonResult& result) const {
    const double gradientMax = at.gradient.size() > 0 ? at.gradient.cwiseAbs().maxCoeff() : 0.0;
    if (!std::isfinite(at.energy) || !at.gradient.allFinite()) {
      result.stop = NewtonStop::NonFinite;
    } else if (gradientMax <= rule_.gradientTolerance) {
      result.stop = NewtonStop::Converged;
      result.convergedBy =
          "gradient max-norm " + number(gradientMax) + " <= " + number(rule_.gradientTolerance);
    } else if (rule_.observer && rule_.observer({result.iterations, at.energy, gradientMax})) {
      result.stop = NewtonStop::Stopped;
    } else if (iteration == rule_.maxIterations) {
      result.stop = NewtonStop::MaxIterations;
    }
    return result.stop != NewtonStop::Running;
  }
  bool converged(const HessianEvaluation& at, const Eigen::VectorXd&, double decrement,
                 bool trusted) const {
    return (trusted || !rule_.inheritedFactor) && decrement > 0.0 &&
           0.5 * decrement <= rule_.functionTolerance * std::abs(at.energy);
  }
  void finish(NewtonLoop& loop, Objective& objective, Eigen::VectorXd& y,
              const HessianEvaluation& at, const Eigen::VectorXd& delta, double decrement, double,
              bool chord, NewtonResult& result) const {
    Eigen::VectorXd trial = y + 1.0 * delta;
    if (objective.lineSearchValue(trial) <= at.energy + 1e-14 * std::abs(at.energy)) {
      y = std::move(trial);
      const HessianEvaluation end =
          loop.evaluate(objective, y, curvature::SecondDerivatives::None, result);
      result.finalValue = end.energy;
      result.gradient = end.gradient;
    }
    result.stop = NewtonStop::Converged;
    result.convergedBy = std::string(chord ? "predicted decrease " : "Newton decrement ") +
                         number(0.5 * decrement) + " <= " + number(rule_.functionTolerance) +
                         " E = " + number(rule_.functionTolerance * std::abs(at.energy));
  }
  void accepted(NewtonResult& result) const { ++result.iterations; }
  void counted(int, NewtonResult&) const {}

 private:
  const StaticStopRule& rule_;
};

// A time step's rule: converged when the step moves no unknown more than `step`, or predicts a
// decrease ½ λ² below f's roundoff (contact's stiff barrier can leave a step above the tolerance
// whose gain no line search can measure), with F known to describe f near y (`trusted`); the
// step is then taken whole, or as far as the obstacles allow (near the minimizer f's change is at
// its roundoff, where a line search cannot judge). At most maxNewtonSteps Newton steps, and 4 ×
// as many iterations in all; counts iterations made.
class NewtonLoop::StepStop {
 public:
  StepStop(const StepStopRule& rule) : rule_(rule) {}

  bool stopsAt(const HessianEvaluation&, int iteration, NewtonResult& result) const {
    if (iteration >= 4 * rule_.maxNewtonSteps || result.newtonSteps >= rule_.maxNewtonSteps)
      result.stop = NewtonStop::MaxIterations;
    return result.stop != NewtonStop::Running;
  }
  bool converged(const HessianEvaluation& at, const Eigen::VectorXd& delta, double decrement,
                 bool trusted) const {
    return trusted && (delta.cwiseAbs().maxCoeff() <= rule_.step ||
                       0.5 * decrement <= 1e-15 * std::abs(at.energy));
  }
  void finish(NewtonLoop&, Objective&, Eigen::VectorXd& y, const HessianEvaluation&,
              const Eigen::VectorXd& delta, double, double bound, bool,
              NewtonResult& result) const {
    y += bound * delta;
    result.stop = NewtonStop::Converged;
  }
  void accepted(NewtonResult&) const {}
  void counted(int iteration, NewtonResult& result) const { result.iterations = iteration + 1; }

 private:
  const StepStopRule& rule_;
};

// One iteration body for both rules. Each iteration has f and ∇f at y (carried from the line
// search that reached y). With a factor F of an earlier Hessian at hand, the chord step
// δ = −F⁻¹∇f (by PCG with the Hessian F preconditions, after a PCG Newton step) and its decrement
// λ² = −∇fᵀδ; it is taken while λ² shrinks at least tenfold per iteration (modified Newton:
// linear convergence at that rate). Otherwise a Newton step: the Hessian at y (of `hessian`)
// solved by PCG preconditioned by F where the policy allows, else factored with the indefinite
// rule. A policy that keeps the Gauss–Newton matrix after an indefinite Hessian keeps it for as
// long as its Newton steps contract tenfold, and the next Newton step tries the exact Hessian
// again once one does not (near the solution it is often definite again; measured on the drape
// benchmark, cotan at 2 500 vertices, Gauss–Newton steps alone stalled at |δ| ≈ 1e-8).
template <class Stop>
NewtonResult NewtonLoop::iterate(Objective& objective, Eigen::VectorXd& y, const Stop& stop,
                                 const Policy& policy) {
  NewtonResult result;
  HessianEvaluation at = evaluate(objective, y, curvature::SecondDerivatives::None, result);
  result.initialValue = at.energy;
  double previousDecrement = std::numeric_limits<double>::infinity();
  double previousNewtonDecrement = std::numeric_limits<double>::infinity();
  bool freshFactor = false;  // F was factored at an iterate of this run
  curvature::SecondDerivatives hessian = policy.hessian;
  LbfgsPairs pairs(policy.quasiNewtonPairs);  // of the steps since F was factored, in this run
  const auto solveWithFactor = [&](const Eigen::VectorXd& b) { return solve(b, result); };
  for (int iteration = 0;; ++iteration) {
    result.finalValue = at.energy;
    result.gradient = at.gradient;
    if (stop.stopsAt(at, iteration, result)) return result;
    stop.counted(iteration, result);
    Eigen::VectorXd delta;
    double decrement = 0.0;
    bool chord = false;
    if (haveFactor_) {
      // With quasiNewtonPairs, the L-BFGS step −H_k∇f whose H₀ is F⁻¹ (H_k = F⁻¹ without pairs).
      delta = chordHessian_.empty() ? pairs.apply(-at.gradient, solveWithFactor)
                                    : solve(-at.gradient, result);
      if (chordHessian_.empty() && pairs.size() > 0)
        objective.keepTranslationResidual(at.gradient, delta);
      // The chord steps of a Hessian solved by PCG are its PCG steps: F alone is older.
      const bool quasiNewton = policy.quasiNewtonPairs > 0 && chordHessian_.empty();
      const bool solved = chordHessian_.empty() ||
                          preconditionedStep(chordHessian_, at.gradient, policy, delta, result);
      const double contraction = quasiNewton ? kQuasiNewtonContraction : kChordContraction;
      decrement = -at.gradient.dot(delta);
      chord = solved && policy.chordSteps && decrement > 0.0 &&
              decrement <= contraction * previousDecrement;
      const bool trusted = chord && (freshFactor || std::isfinite(previousDecrement));
      if (solved && stop.converged(at, delta, decrement, trusted)) {
        stop.finish(*this, objective, y, at, delta, decrement, objective.stepBound(y, delta), true,
                    result);
        return result;
      }
    }
    if (!chord) {
      ++result.newtonSteps;
      const bool fallback = hessian != policy.hessian;  // a Gauss–Newton matrix kept
      HessianEvaluation h = evaluate(objective, y, hessian, result);
      const bool preconditioned = policy.preconditionedSteps && policy.chordSteps && haveFactor_ &&
                                  preconditionedStep(h.values, h.gradient, policy, delta, result);
      const int gaussNewtonBefore = result.gaussNewtonSteps;
      if (!preconditioned && !factorNewton(objective, y, policy.indefinite, fallback, h, result)) {
        result.stop = NewtonStop::NotPositiveDefinite;
        return result;
      }
      pairs.clear();
      if (policy.keepGaussNewton && result.gaussNewtonSteps > gaussNewtonBefore)
        hessian = curvature::SecondDerivatives::GaussNewton;
      at.energy = h.energy;
      at.gradient = std::move(h.gradient);
      if (preconditioned) {
        chordHessian_ = std::move(h.values);
      } else {
        freshFactor = true;
        delta = solve(-at.gradient, result);
      }
      decrement = -at.gradient.dot(delta);  // λ², > 0 for a positive definite H
      if (fallback && decrement > kChordContraction * previousNewtonDecrement)
        hessian = policy.hessian;
      if (hessian != policy.hessian) previousNewtonDecrement = decrement;
      if (stop.converged(at, delta, decrement, true)) {
        stop.finish(*this, objective, y, at, delta, decrement, objective.stepBound(y, delta), false,
                    result);
        return result;
      }
      if (!std::isfinite(decrement) || decrement <= 0.0) {
        result.stop = NewtonStop::NotDescent;
        return result;
      }
    }
    Eigen::VectorXd trial;
    HessianEvaluation trialAt;
    bool shortened = false;
    const bool decreased =
        searchStep(objective, y, at, delta, decrement, objective.stepBound(y, delta), chord,
                   policy.search, trial, trialAt, shortened);
    if (!decreased && !chord) {
      result.stop = NewtonStop::LineSearchFailed;
      return result;
    }
    // A chord step that needed damping or scaling (or failed) asks for a new factor next time.
    previousDecrement = chord && shortened ? 0.0 : decrement;
    if (!decreased) continue;
    if (policy.quasiNewtonPairs > 0) pairs.add(trial - y, trialAt.gradient - at.gradient);
    y = std::move(trial);
    if (policy.progress) {
      std::fprintf(stderr,
                   "  iteration %3d  %-6s energy %.10e  |gradient|max %.3e  decrement %.3e%s\n",
                   result.iterations + 1, chord ? "chord" : "newton", trialAt.energy,
                   at.gradient.cwiseAbs().maxCoeff(), decrement, shortened ? "  damped" : "");
    }
    at = std::move(trialAt);
    stop.accepted(result);
    if (chord) ++result.chordSteps;
  }
}

NewtonResult NewtonLoop::run(Objective& objective, Eigen::VectorXd& y, const StaticStopRule& rule) {
  Policy policy;
  policy.chordSteps = rule.chordSteps;
  policy.indefinite = rule.indefinite;
  policy.keepGaussNewton =
      rule.keepGaussNewton && rule.indefinite == IndefiniteHessian::GaussNewton;
  policy.progress = rule.progress;
  policy.quasiNewtonPairs = rule.chordSteps ? rule.quasiNewtonPairs : 0;
  policy.search.chordTrials = 5;  // a chord step that needs α < 0.1 asks for a Newton step
  policy.search.smallestStep = 1e-12;
  return iterate(objective, y, StaticStop(rule), policy);
}

NewtonResult NewtonLoop::run(Objective& objective, Eigen::VectorXd& y, const StepStopRule& rule) {
  Policy policy;
  policy.hessian = rule.hessian;
  policy.keepGaussNewton = true;
  policy.chordSteps = rule.chordSteps;
  policy.preconditionedSteps = rule.preconditionedSteps;
  policy.pcgTolerance = rule.pcgTolerance;
  policy.pcgMaxIterations = rule.pcgMaxIterations;
  policy.quasiNewtonPairs = rule.chordSteps ? rule.quasiNewtonPairs : 0;
  policy.search.chordTrials = 2;
  policy.search.smallestStep = 1e-10;
  policy.search.scaleByVertexBounds = true;
  policy.search.acceptBelowRoundoff = true;
  return iterate(objective, y, StepStop(rule), policy);
}

}  // namespace flexure::optimize
