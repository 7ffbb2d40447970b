// The Newton loop for every objective (objective.h): static minimizers (newton_solver.h) and each
// implicit time step (dynamics/time_stepping.h), one iteration body (NewtonLoop::iterate) with
// policies.
//
// Every iteration has f and ∇f at the iterate y and, while a factor F of an earlier Hessian is at
// hand, the chord step δ = −F⁻¹∇f with its decrement λ² = −∇fᵀδ. δ is taken as a chord step
// (modified Newton) while λ² shrinks at least 10-fold per iteration; otherwise the Hessian at y is
// assembled and factored with CHOLMOD (analysis once per pattern) for a Newton step.
// Either rule may take quasi-Newton steps on F instead (quasiNewtonPairs = m > 0;
// Liu, Bouaziz & Kavan 2017, "Quasi-Newton methods for real-time simulation of hyperelastic
// materials"; DOT's L-BFGS-H, Li et al. 2019): δ = −H_k∇f with H_k the L-BFGS inverse Hessian of
// the last m pairs s = y_{j+1} − y_j, t = ∇f_{j+1} − ∇f_j of the steps accepted since F was
// factored within this run, on H₀ = F⁻¹ (the two-loop recursion, lbfgs_update.h: one solve with F
// and 4m vector operations; H_k t = s for the newest pair). Such a step is taken while λ² shrinks
// at least 2-fold per iteration (near contact a Newton step itself contracts λ² only 0.1–0.7-fold,
// so a factorization bought by the chord step's tenfold test often gains nothing), under the
// chord step's other tests (descent, trials, vertex step bounds); otherwise the Newton step.
// The objective then restores the step's rigid-translation part where it knows it
// (Objective::keepTranslationResidual: the momentum a step on F cancels exactly). Where
// the Hessian is not positive definite (away from a minimizer: a fairing start, a compressed
// membrane about to buckle) the indefinite-Hessian rule factors another matrix (IndefiniteHessian;
// the Gauss–Newton matrix JᵀJ by default), shifted by μI where singular. Steps are searched on the
// objective (Armijo: f(y + αδ) ≤ f(y) − 10⁻⁴ α λ² + roundoff, α halved) from the longest feasible
// α ≤ 1 (obstacles).
//
// The stop rule is chosen by its type:
// - StaticStopRule (minimize): converged when the predicted decrease ½ λ² ≤ functionTolerance · |f|
//   or ‖∇f‖∞ ≤ gradientTolerance; no factorization is made only to confirm.
// - StepStopRule (a time step): converged when the step moves no unknown more than `step`, or
//   predicts a decrease ½ λ² below f's roundoff, with F known to describe f near y (factored in
//   this solve, or its chord steps here contracted). A factor from an earlier solve is never
//   trusted alone: it may be stiffer than f is now (a contact since released).
// Each rule also sets the policies its solver was measured with: the static rule gives a chord
// step five trials (α down to 1/16) and a Newton step down to α = 10⁻¹², and takes its
// indefinite-Hessian rule from the caller; the step rule gives a chord step two trials, first
// searches δ scaled per vertex by its own bound where an obstacle bounds the step, passes steps
// whose predicted decrease is below roundoff, keeps JᵀJ for its Newton steps while they contract
// tenfold, and may solve Newton steps by PCG on the kept factor.
#pragma once

#include <Eigen/Core>
#include <string>

#include "optimize/solvers/hessian_factorization.h"
#include "optimize/solvers/newton_stop.h"
#include "optimize/solvers/objective.h"

namespace flexure::optimize {

// The static rule's Newton matrix at an iterate whose Hessian H is not positive definite: the
// Gauss–Newton matrix JᵀJ (+ μI where singular); H + μI with μ grown tenfold until it factors
// (Nocedal & Wright 2006, §3.4, from a tenth of the last such μ); or the sum of the element
// Hessians each projected to positive semidefinite (projected_hessian.h; + μI where singular).
enum class IndefiniteHessian { GaussNewton, Shifted, Projected };

struct StaticStopRule {
  double functionTolerance = 1e-12;  // on ½ λ² / |f|
  double gradientTolerance = 1e-10;  // on ‖∇f‖∞
  int maxIterations = 200;           // accepted steps
  bool chordSteps = true;            // false: every step factors the Hessian at its iterate
  // With chordSteps, m > 0: each chord step is the L-BFGS step on F⁻¹, as StepStopRule's.
  int quasiNewtonPairs = 0;
  IndefiniteHessian indefinite = IndefiniteHessian::GaussNewton;
  // With the GaussNewton rule: after an indefinite Hessian the Newton steps factor JᵀJ while they
  // contract tenfold, as StepStopRule's, instead of trying the Hessian (a second factorization)
  // at every one.
  bool keepGaussNewton = false;
  bool progress = false;  // one line per iteration on stderr
  // Called at each iterate before the iteration limit is tested (the start included).
  IterationObserver observer;
  // The loop's factor is of another problem's Hessian (KeptFactorization, minimize.h): a chord
  // step's decrement on it proves convergence only once a chord step has contracted, as the step
  // rule's `trusted` (the factor may be stiffer than the Hessian here, its decrement too small).
  bool inheritedFactor = false;
};

struct StepStopRule {
  double step = 0.0;        // the largest |δ_k| of a converged step
  int maxNewtonSteps = 30;  // factoring iterations, and 4 × as many iterations in all
  bool chordSteps = true;   // false: every iteration factors the Hessian at its iterate
  // The Newton steps' Hessian of E: Exact, or GaussNewton throughout.
  curvature::SecondDerivatives hessian = curvature::SecondDerivatives::Exact;
  // With chordSteps, a Newton step first solves H δ = −∇f by conjugate gradients preconditioned
  // by the kept factor F (preconditionedStep), and factors H only when that fails; the chord
  // steps that follow solve with that H the same way.
  bool preconditionedSteps = false;
  // Accepted when the residual r = −∇f − H δ has rᵀF⁻¹r ≤ pcgTolerance² ∇fᵀF⁻¹∇f, within
  // pcgMaxIterations products with H (each one solve with F). Measured on the drape benchmark
  // (hinge, 2 500 vertices; η, cap → steps/s): 1e-3, 12 → 1.83; 1e-2, 6 → 2.08; 1e-1, 4 → 2.60;
  // 1e-1, 8 → 2.12; 0.3, 4 → 2.09 (more Hessians: the inexact steps contract less).
  double pcgTolerance = 0.1;
  int pcgMaxIterations = 4;
  // With chordSteps, m > 0: each chord step is the L-BFGS step δ = −H_k∇f on H₀ = F⁻¹ with the
  // last m pairs of accepted steps since F was factored in this run (lbfgs_update.h), under the
  // chord step's tests; 0: δ = −F⁻¹∇f.
  int quasiNewtonPairs = 0;
};

struct NewtonResult {
  NewtonStop stop = NewtonStop::Running;
  std::string convergedBy;  // static rule: the test that held, with its numbers
  int iterations = 0;       // static: accepted steps; time step: iterations made
  int newtonSteps = 0, chordSteps = 0;
  int factorizations = 0;
  int gaussNewtonSteps = 0, shiftedFactorizations = 0;  // the indefinite-Hessian rule's
  // Newton steps solved by preconditioned conjugate gradients instead of a factorization, and the
  // conjugate-gradient iterations made (those of attempts that fell back to factoring included).
  int pcgSolves = 0, pcgIterations = 0;
  double initialValue = 0.0, finalValue = 0.0;
  Eigen::VectorXd gradient;  // ∇f at the last iterate
  double evaluationSeconds = 0.0, linearSolverSeconds = 0.0;
};

class NewtonLoop {
 public:
  // `factorization` is of `assembly`'s pattern (the objectives'); the loop keeps its last factor
  // between runs.
  NewtonLoop(const HessianAssembly& assembly, HessianFactorization& factorization)
      : assembly_(assembly), factorization_(factorization) {}

  // Minimizes from y (updated to the last iterate, or the converged point).
  NewtonResult run(Objective& objective, Eigen::VectorXd& y, const StaticStopRule& rule);
  NewtonResult run(Objective& objective, Eigen::VectorXd& y, const StepStopRule& rule);

  // Whether a factor from an earlier run (or `factor` below) is at hand; forget() drops it,
  // adoptFactor() says the factorization holds one from elsewhere (KeptFactorization), and
  // factorAdopted() whether that one is still the factor at hand.
  bool haveFactor() const { return haveFactor_; }
  void adoptFactor() { haveFactor_ = adopted_ = true; }
  bool factorAdopted() const { return haveFactor_ && adopted_; }
  void forget() {
    haveFactor_ = adopted_ = false;
    chordHessian_.clear();
  }
  // Factors h's values, shifted by μI where singular (the static rule's); counts into `result`.
  // `tryUnshifted` false: h is known not to factor unshifted.
  bool factorShifted(const std::vector<double>& values, NewtonResult& result,
                     bool tryUnshifted = true);
  Eigen::VectorXd solve(const Eigen::VectorXd& b, NewtonResult& result);

 private:
  // How a run searches along a step (searchStep).
  struct LineSearch {
    int chordTrials = 2;               // trials a chord step gets before a Newton step instead
    double smallestStep = 1e-10;       // α below which a Newton step's search fails
    bool scaleByVertexBounds = false;  // first search δ scaled per vertex by its obstacle bound
    bool acceptBelowRoundoff = false;  // pass a step whose predicted decrease is below roundoff
  };
  // The policies of one run besides its stop rule (StaticStop, StepStop in newton_loop.cpp):
  // the Newton steps' Hessian and what to do where it is indefinite, the linear step (a factor,
  // chord steps on the kept factor, PCG preconditioned by it) and the line search.
  struct Policy {
    curvature::SecondDerivatives hessian = curvature::SecondDerivatives::Exact;
    IndefiniteHessian indefinite = IndefiniteHessian::GaussNewton;
    // Keep the Gauss–Newton matrix after an indefinite Hessian while its steps contract tenfold.
    bool keepGaussNewton = false;
    bool chordSteps = true;
    bool preconditionedSteps = false;  // StepStopRule's
    double pcgTolerance = 0.1;
    int pcgMaxIterations = 4;
    int quasiNewtonPairs = 0;  // StepStopRule's
    LineSearch search;
    bool progress = false;  // one line per accepted step on stderr
  };
  class StaticStop;
  class StepStop;

  template <class Stop>
  NewtonResult iterate(Objective& objective, Eigen::VectorXd& y, const Stop& stop,
                       const Policy& policy);
  HessianEvaluation evaluate(Objective& objective, const Eigen::VectorXd& y,
                             curvature::SecondDerivatives kind, NewtonResult& result);
  bool factorNewton(Objective& objective, const Eigen::VectorXd& y, IndefiniteHessian indefinite,
                    bool fallback, HessianEvaluation& h, NewtonResult& result);
  bool preconditionedStep(const std::vector<double>& hessian, const Eigen::VectorXd& gradient,
                          const Policy& policy, Eigen::VectorXd& delta, NewtonResult& result);
  bool searchStep(Objective& objective, const Eigen::VectorXd& y, const HessianEvaluation& at,
                  const Eigen::VectorXd& delta, double decrement, double bound, bool chord,
                  const LineSearch& search, Eigen::VectorXd& trial, HessianEvaluation& trialAt,
                  bool& shortened);

  const HessianAssembly& assembly_;
  HessianFactorization& factorization_;
  bool haveFactor_ = false;
  bool adopted_ = false;  // the factor is adoptFactor()'s, none of this loop's own
  // The step rule's last Hessian when its Newton step was solved by PCG (preconditionedStep):
  // the chord steps solve with it, F as their preconditioner. Empty when F is of the last Hessian.
  std::vector<double> chordHessian_;
  double lastShift_ = 0.0;
};

}  // namespace flexure::optimize
