#include "optimize/solvers/newton_loop.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

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
  chordHessian_.clear();
  result.linearSolverSeconds += secondsSince(t);
  return ok;
}

// The static rule's Newton factor at y: the Hessian h, or, where it is not positive definite, the
// Gauss–Newton matrix JᵀJ at y — positive semidefinite by construction, and the curvature
// Ceres' LM uses — shifted by μI where singular. Measured against shifting the indefinite
// Hessian by μI: fairing lion-head all-interior (midedge, 49 851 unknowns) 12 iterations, 28 s
// against 51, 256 s (Ceres' LM: 36, 90 s); against projecting the element Hessians to positive
// semidefinite, hinge + StVK in xyz lifted by a unit quadratic: converged where projection did
// not in 400 iterations. h is replaced by what was factored.
bool NewtonLoop::factorNewtonStatic(Objective& objective, const Eigen::VectorXd& y,
                                    IndefiniteHessian indefinite, HessianEvaluation& h,
                                    NewtonResult& result) {
  const auto t = Clock::now();
  ++result.factorizations;
  const bool exact = factorization_.factor(h.values);
  result.linearSolverSeconds += secondsSince(t);
  chordHessian_.clear();
  if (exact) return haveFactor_ = true;
  if (indefinite == IndefiniteHessian::Shifted) return factorShifted(h.values, result, false);
  ++result.gaussNewtonSteps;
  if (indefinite == IndefiniteHessian::GaussNewton)
    h = evaluate(objective, y, curvature::SecondDerivatives::GaussNewton, result);
  else if (indefinite == IndefiniteHessian::Projected)
    h = evaluate(objective, y, curvature::SecondDerivatives::Projected, result);
  return factorShifted(h.values, result);
}

// Converged at y, whose predicted decrease is below the tolerance: the step δ already solved for
// is taken too where it does not raise f beyond roundoff (it costs no factorization and brings y
// closer by the step's contraction), and ∇f is evaluated for the report.
void NewtonLoop::finishStatic(Objective& objective, Eigen::VectorXd& y, const HessianEvaluation& at,
                              const Eigen::VectorXd& delta, const std::string& why,
                              const StaticStopRule& rule, NewtonResult& result) {
  Eigen::VectorXd trial = y + 1.0 * delta;
  if (objective.lineSearchValue(trial) <= at.energy + 1e-14 * std::abs(at.energy)) {
    y = std::move(trial);
    const HessianEvaluation end =
        evaluate(objective, y, curvature::SecondDerivatives::None, result);
    result.finalValue = end.energy;
    result.gradient = end.gradient;
  }
  result.stop = NewtonStop::Converged;
  result.convergedBy = why + " <= " + number(rule.functionTolerance) +
                       " E = " + number(rule.functionTolerance * std::abs(at.energy));
}

NewtonResult NewtonLoop::run(Objective& objective, Eigen::VectorXd& y, const StaticStopRule& rule) {
  NewtonResult result;
  double previousDecrement = std::numeric_limits<double>::infinity();
  for (int iteration = 0;; ++iteration) {
    const HessianEvaluation at = evaluate(objective, y, curvature::SecondDerivatives::None, result);
    if (iteration == 0) result.initialValue = at.energy;
    result.finalValue = at.energy;
    result.gradient = at.gradient;
    const double gradientMax = at.gradient.size() > 0 ? at.gradient.cwiseAbs().maxCoeff() : 0.0;
    if (!std::isfinite(at.energy) || !at.gradient.allFinite()) {
      result.stop = NewtonStop::NonFinite;
      return result;
    }
    if (gradientMax <= rule.gradientTolerance) {
      result.stop = NewtonStop::Converged;
      result.convergedBy =
          "gradient max-norm " + number(gradientMax) + " <= " + number(rule.gradientTolerance);
      return result;
    }
    if (rule.observer && rule.observer({result.iterations, at.energy, gradientMax})) {
      result.stop = NewtonStop::Stopped;
      return result;
    }
    if (iteration == rule.maxIterations) {
      result.stop = NewtonStop::MaxIterations;
      return result;
    }
    Eigen::VectorXd delta;
    double decrement = 0.0;
    bool chord = false;
    if (haveFactor_) {
      delta = solve(-at.gradient, result);
      decrement = -at.gradient.dot(delta);
      if (decrement > 0.0 && 0.5 * decrement <= rule.functionTolerance * std::abs(at.energy)) {
        finishStatic(objective, y, at, delta, "predicted decrease " + number(0.5 * decrement), rule,
                     result);
        return result;
      }
      chord =
          decrement > 0.0 && decrement <= kChordContraction * previousDecrement && rule.chordSteps;
    }
    if (!chord) {
      HessianEvaluation h = evaluate(objective, y, curvature::SecondDerivatives::Exact, result);
      if (!factorNewtonStatic(objective, y, rule.indefinite, h, result)) {
        result.stop = NewtonStop::NotPositiveDefinite;
        return result;
      }
      delta = solve(-h.gradient, result);
      decrement = -h.gradient.dot(delta);  // λ², > 0 for a positive definite H
      if (!std::isfinite(decrement) || decrement <= 0.0) {
        result.stop = NewtonStop::NotDescent;
        return result;
      }
      if (0.5 * decrement <= rule.functionTolerance * std::abs(at.energy)) {
        finishStatic(objective, y, at, delta, "Newton decrement " + number(0.5 * decrement), rule,
                     result);
        return result;
      }
    }
    // Armijo from the longest feasible α, α halved; a chord step that needs α < 0.1 asks for a
    // Newton step instead.
    double alpha = objective.stepBound(y, delta), trialValue = 0.0;
    Eigen::VectorXd trial;
    bool decreased = true;
    for (;; alpha *= 0.5) {
      trial = y + alpha * delta;
      trialValue = objective.lineSearchValue(trial);
      if (trialValue <= at.energy - 1e-4 * alpha * decrement + objective.roundoff(y, at.energy))
        break;
      if (alpha < (chord ? 0.1 : 1e-12)) {
        decreased = false;
        break;
      }
    }
    if (!decreased && !chord) {
      result.stop = NewtonStop::LineSearchFailed;
      return result;
    }
    // A chord step that needed damping, or failed, asks for a new factor next time.
    previousDecrement = chord && alpha < 1.0 ? 0.0 : decrement;
    if (!decreased) continue;
    y = std::move(trial);
    ++result.iterations;
    ++(chord ? result.chordSteps : result.newtonSteps);
    if (rule.progress) {
      std::fprintf(stderr,
                   "  iteration %3d  %-6s energy %.10e  |gradient|max %.3e  decrement %.3e  "
                   "step %.3g\n",
                   result.iterations, chord ? "chord" : "newton", trialValue, gradientMax,
                   decrement, alpha);
    }
  }
}

// The Newton step δ = −H⁻¹∇f by conjugate gradients on H preconditioned by the kept factor F of
// an earlier Hessian (the stale-factor Newton–Krylov of Hecht, Lee, Shewchuk & O'Brien 2012,
// "Updated sparse Cholesky factors for corotational elastodynamics": F ≈ H makes F⁻¹H's
// spectrum cluster near 1, so a few iterations, each one product with H and one solve with F,
// replace a factorization). On entry δ = −F⁻¹∇f (the chord step, the first preconditioned
// residual from δ₀ = 0); on success δ is the step. Accepted when rᵀF⁻¹r ≤ η² ∇fᵀF⁻¹∇f
// (η = rule.pcgTolerance: the residual in F's norm, the first one being the chord step's
// decrement). false — δ unusable, H to be factored — after rule.pcgMaxIterations iterations, or
// where pᵀHp ≤ 0 along a search direction p (H not positive definite: the factoring path's
// indefinite-Hessian rule applies).
bool NewtonLoop::preconditionedStep(const std::vector<double>& hessian,
                                    const Eigen::VectorXd& gradient, const StepStopRule& rule,
                                    Eigen::VectorXd& delta, NewtonResult& result) {
  const auto t = Clock::now();
  Eigen::VectorXd residual = -gradient, preconditioned = delta, direction = delta;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(gradient.size());
  const double initial = residual.dot(preconditioned);
  double current = initial;
  bool converged = false;
  for (int k = 0; k < rule.pcgMaxIterations && std::isfinite(current) && current > 0.0; ++k) {
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
    if (next <= rule.pcgTolerance * rule.pcgTolerance * initial) {
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

// Armijo on f from y along δ, α halved from α = bound. The first trial evaluates ∇f too, which
// the next iteration uses when it passes (it usually does); later ones f alone, and ∇f where one
// passes. A chord step gets two trials: one that fails them asks for a Newton step rather than a
// short step. When the obstacles bound the step (bound < 1), δ with each vertex's move scaled by
// its own bound α_v is searched first, from α = 1, when that is still a descent direction — a
// vertex about to touch an obstacle then no longer holds every other vertex back to its fraction
// of the step (measured on the drape benchmark: the capped Newton steps of a contact step fell
// from tens to a few). `shortened`: the step taken was damped or scaled. false: no decrease.
bool NewtonLoop::searchStep(Objective& objective, const Eigen::VectorXd& y,
                            const Eigen::VectorXd& gradient, const Eigen::VectorXd& delta,
                            double value, double decrement, double bound, bool chord,
                            Eigen::VectorXd& trial, HessianEvaluation& trialAt, bool& shortened) {
  NewtonResult unused;
  // f's roundoff: a decrease below it passes (the comparison cannot judge it, and the step is a
  // descent direction of a positive definite model).
  const double roundoff = objective.roundoff(y, value);
  double alpha = bound, slope = decrement;  // slope = −∇fᵀ direction
  Eigen::VectorXd direction = delta;
  bool scaledDirection = false;
  if (bound < 1.0) {
    const Eigen::VectorXd bounds = objective.vertexStepBounds(y, delta);
    const std::vector<int>& unknowns = objective.assembly().freeUnknowns();
    const long positionCount = 3 * bounds.size();
    Eigen::VectorXd scaled = delta;
    for (int k = 0; k < scaled.size(); ++k)
      if (unknowns[k] < positionCount) scaled[k] *= bounds[unknowns[k] / 3];
    const double scaledSlope = -gradient.dot(scaled);
    if (scaledSlope > 0.0) {
      direction = std::move(scaled);
      slope = scaledSlope;
      alpha = 1.0;
      scaledDirection = true;
    }
  }
  double trialValue = 0.0;
  for (int trials = 1;; ++trials, alpha *= 0.5) {
    trial = y + alpha * direction;
    if (trials == 1) {
      trialAt = evaluate(objective, trial, curvature::SecondDerivatives::None, unused);
      trialValue = trialAt.energy;
    } else {
      trialValue = objective.lineSearchValue(trial);
    }
    // +∞ inside an obstacle; NaN never passes.
    if (trialValue <= value - 1e-4 * alpha * slope + roundoff ||
        (std::isfinite(trialValue) && 0.5 * alpha * slope <= roundoff)) {
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
    if (chord ? trials == 2 : alpha < 1e-10) {
      shortened = alpha < 1.0 || scaledDirection;
      return false;
    }
  }
}

NewtonResult NewtonLoop::run(Objective& objective, Eigen::VectorXd& y, const StepStopRule& rule) {
  NewtonResult result;
  double previousDecrement = std::numeric_limits<double>::infinity();
  HessianEvaluation at = evaluate(objective, y, curvature::SecondDerivatives::None, result);
  bool freshFactor = false;  // F was factored at an iterate of this run
  // The Hessian of E the Newton steps factor: rule.hessian until the exact one is found
  // indefinite; then its Gauss–Newton part directly (one factorization per Newton step instead of
  // two) for as long as those Newton steps contract tenfold (previousNewtonDecrement: the last
  // one's λ²).
  curvature::SecondDerivatives hessian = rule.hessian;
  double previousNewtonDecrement = std::numeric_limits<double>::infinity();
  for (int iteration = 1;
       iteration <= 4 * rule.maxNewtonSteps && result.newtonSteps < rule.maxNewtonSteps;
       ++iteration) {
    result.iterations = iteration;
    Eigen::VectorXd delta;
    double decrement = 0.0;
    bool chord = false;
    if (rule.chordSteps && haveFactor_) {
      delta = -factorization_.solve(at.gradient);
      // The chord steps of a Hessian solved by PCG are its PCG steps: F alone is older.
      const bool solved = chordHessian_.empty() ||
                          preconditionedStep(chordHessian_, at.gradient, rule, delta, result);
      decrement = -at.gradient.dot(delta);
      chord = solved && decrement > 0.0 && decrement <= kChordContraction * previousDecrement;
    }
    bool trusted = chord && (freshFactor || std::isfinite(previousDecrement));
    if (!chord) {
      ++result.newtonSteps;
      const bool gaussNewton = hessian != rule.hessian;  // a fallback carried over
      HessianEvaluation h = evaluate(objective, y, hessian, result);
      at.energy = h.energy;
      at.gradient = std::move(h.gradient);
      const bool preconditioned = rule.preconditionedSteps && rule.chordSteps && haveFactor_ &&
                                  preconditionedStep(h.values, at.gradient, rule, delta, result);
      bool factored = preconditioned || factorization_.factor(h.values);
      if (!preconditioned) ++result.factorizations;
      if (!factored && !gaussNewton) {  // indefinite ∇²E (buckling, a compressed membrane)
        const HessianEvaluation gn =
            evaluate(objective, y, curvature::SecondDerivatives::GaussNewton, result);
        factored = factorization_.factor(gn.values);
        ++result.factorizations;
        ++result.gaussNewtonSteps;
        hessian = curvature::SecondDerivatives::GaussNewton;
      }
      haveFactor_ = factored;
      if (!factored) {
        result.stop = NewtonStop::NotPositiveDefinite;
        return result;
      }
      if (preconditioned) {
        chordHessian_ = std::move(h.values);
      } else {
        chordHessian_.clear();
        freshFactor = true;
        delta = -factorization_.solve(at.gradient);
      }
      trusted = true;
      decrement = -at.gradient.dot(delta);
      // The fallback's Newton steps converge only linearly: it stays while they contract
      // tenfold, and the next Newton step tries rule.hessian again once one does not (near the
      // solution the exact Hessian is often definite again; measured on the drape benchmark,
      // cotan at 2 500 vertices, Gauss–Newton steps alone stalled at |δ| ≈ 1e-8).
      if (gaussNewton && decrement > kChordContraction * previousNewtonDecrement)
        hessian = rule.hessian;
      if (hessian != rule.hessian) previousNewtonDecrement = decrement;
    }
    const double bound = objective.stepBound(y, delta);
    // Converged: the step itself is below the tolerance (taken whole, or as far as the obstacles
    // allow: near the minimizer f's change is at its roundoff, where a line search cannot judge);
    // or the decrease it predicts, ½ λ², is below f's roundoff (contact's stiff barrier can leave
    // a step above the tolerance whose gain no line search can measure).
    if (trusted && (delta.cwiseAbs().maxCoeff() <= rule.step ||
                    0.5 * decrement <= 1e-15 * std::abs(at.energy))) {
      y += bound * delta;
      result.stop = NewtonStop::Converged;
      break;
    }
    Eigen::VectorXd trial;
    HessianEvaluation trialAt;
    bool shortened = false;
    const bool decreased = searchStep(objective, y, at.gradient, delta, at.energy, decrement, bound,
                                      chord, trial, trialAt, shortened);
    if (!decreased && !chord) {
      result.stop = NewtonStop::LineSearchFailed;
      return result;
    }
    // A chord step that needed damping or scaling (or failed) asks for a new factor next time.
    previousDecrement = chord && shortened ? 0.0 : decrement;
    if (!decreased) continue;
    y = std::move(trial);
    at.energy = trialAt.energy;
    at.gradient = std::move(trialAt.gradient);
  }
  if (result.stop != NewtonStop::Converged) result.stop = NewtonStop::MaxIterations;
  result.finalValue = at.energy;
  result.gradient = at.gradient;
  return result;
}

}  // namespace flexure::optimize
