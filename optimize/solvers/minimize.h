// Static minimizers with fixed boundaries: the shape a plate or shell takes when some vertices
// (and, for midedge, some ξ) are held and the rest minimize the energy terms.
//
// Nonlinear: flexure's Newton method on the exact Hessian (newton_solver.h, the default), or
// Ceres' trust-region Levenberg–Marquardt with SPARSE_NORMAL_CHOLESKY on SuiteSparse (the
// reference; one parameter block per vertex, fixed vertices constant, and in height mode a
// SubsetManifold keeps x and y). Linearized: E_lin(u) = ½ |J (u − ū)|² with J the residual Jacobian
// at rest, minimized exactly by one sparse Cholesky solve (CHOLMOD) over the free unknowns.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "curvature/energy_term.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/boundary_conditions.h"
#include "optimize/solvers/newton_stop.h"

namespace flexure::optimize {

using curvature::EnergyTerm;

// Where the free unknowns of a nonlinear solve start. Linearized: at the minimizer of the
// linearized energy (one sparse solve: the Newton step from rest), which leaves Gauss–Newton a
// small correction; AsGiven: at the boundary conditions' `start` (the rest state, or a given
// start).
enum class Start { Linearized, AsGiven };

// The nonlinear solver: flexure's Newton method on the exact Hessian (newton_solver.h), or
// Ceres' Levenberg–Marquardt on the Gauss–Newton matrix JᵀJ, the reference.
enum class Solver { Newton, Ceres };
const char* solverName(Solver solver);  // "newton" | "ceres"

// Which Hessian Newton factors: the exact one, and JᵀJ in an iteration where it is not positive
// definite (Exact), or the sum of the element Hessians projected to positive semidefinite
// (Projected; measured slower: the projection drops curvature a step needs, and near the
// minimizer the convergence is no longer quadratic).
// Shifted and ExactOrProjected: the exact Hessian, and where it is not positive definite H + μI
// (μ grown tenfold until it factors) or the projected sum.
enum class HessianMode { Exact, Projected, Shifted, ExactOrProjected };

// The names users give them, each list in the enum's order: "linearized" | "given"; "newton" |
// "ceres"; "exact" | "projected" | "shifted" | "exact-projected". A parse throws InputError naming
// the field (MinimizeOptions.start, .solver, .hessian) and listing the names.
const char* hessianModeName(HessianMode mode);
Start parseStart(std::string_view name);
Solver parseSolver(std::string_view name);
HessianMode parseHessianMode(std::string_view name);

// The pairs of MinimizeOptions::quasiNewton's L-BFGS steps, as the time steps' default
// (DynamicsOptions::quasiNewtonPairs).
inline constexpr int kQuasiNewtonPairs = 6;

// How a Problem (problem.h: the terms, the unknown layout, the boundary, the load, the
// obstacles) is minimized.
struct MinimizeOptions {
  Solver solver = Solver::Newton;
  HessianMode hessian = HessianMode::Exact;
  bool linearized = false;
  Start start = Start::Linearized;
  int maxIterations = 200;
  // Ceres: |Δcost| / cost. Newton: the predicted decrease ½ gᵀH⁻¹g of a full step / E.
  double functionTolerance = 1e-12;
  double gradientTolerance = 1e-10;   // max-norm of the gradient over the free unknowns
  double parameterTolerance = 1e-12;  // Ceres: |Δx| / |x|
  int threads = 2;
  // Newton: each chord step is the L-BFGS step on the kept factor F with the last
  // kQuasiNewtonPairs accepted steps since F was factored (newton_loop.h: H₀ = F⁻¹, taken while λ²
  // halves per step) instead of −F⁻¹∇E. Fewer factorizations where a Hessian is dear (the fairing
  // on the current metric, fairing.h).
  bool quasiNewton = false;
  // Newton: after an indefinite Hessian, its Newton steps factor JᵀJ for as long as they contract
  // tenfold (newton_loop.h, the time steps' policy), rather than factoring the Hessian first, and
  // JᵀJ after it fails, at every one: such a step factors once, not twice. Worth it where most
  // Hessians are indefinite (the fairing on the current metric, fairing.h); where few are, JᵀJ's
  // linear convergence can cost more Newton steps than it saves.
  bool keepGaussNewton = false;
  bool progress = false;  // one line per iteration on stderr
  // Called at every iteration of the nonlinear solvers (not the linearized solve); true stops the
  // solve, reported as MinimizeReport::stop NewtonStop::Stopped, not converged.
  IterationObserver observer;
  // Hand Ceres a METIS nested-dissection order of the vertices (elimination_order.h). false:
  // Ceres' AMD, the benchmark's baseline.
  bool nestedDissection = true;
  // Benchmarks only: Newton as a plain Newton solver does it (libshell's, say) — Eigen's
  // SimplicialLLT refactored in every iteration, no chord steps. The baseline of scripts/bench
  // shell.
  bool simplicialBaseline = false;

  // InputError naming the field: a limit below 1, a tolerance that is not > 0, a Hessian mode
  // other than exact with Ceres (it factors JᵀJ, not the Hessian).
  void validate() const;
};

struct MinimizeReport {
  bool converged = false;
  std::string solver;                     // "newton", "ceres" or "linearized"
  std::string termination;                // why the solver stopped, for users
  NewtonStop stop = NewtonStop::Running;  // why the solver stopped, for callers
  int iterations = 0;
  int factorizations = 0;  // numerical sparse Cholesky factorizations, the predictor's included
  double initialEnergy = 0.0, finalEnergy = 0.0;
  double gradientNorm = 0.0;  // final |∇E| over the free unknowns (2-norm)
  double totalSeconds = 0.0, evaluationSeconds = 0.0, linearSolverSeconds = 0.0;
  double orderingSeconds = 0.0;  // the fill-reducing order of the Ceres solve (elimination_order.h)
  int vertices = 0, fixedVertices = 0, freeEdgeUnknowns = 0, unknowns = 0, residuals = 0;
};

struct MinimizeResult {
  Positions positions;  // #V by 3
  Eigen::VectorXd xi;   // #E (midedge), else empty
  MinimizeReport report;
};

struct Problem;
class HessianFactorization;

// What a Newton solve keeps for the next solve of the same unknowns with the same Hessian pattern —
// a continuation in a parameter, as the fairing's membrane fade (the same terms, another weight):
// CHOLMOD's symbolic analysis (the fill-reducing order and the factor's structure) and the last
// numerical factor. The next solve checks the pattern (another one is analysed afresh and replaces
// it) and takes its first steps as chord steps on the kept factor, under the chord step's tests
// (newton_loop.h): a Newton step at its own iterate as soon as they no longer contract tenfold, and
// no convergence on the kept factor's decrement until a chord step on it has contracted. Empty
// until a Newton solve fills it; the other solvers neither read nor fill it.
class KeptFactorization {
 public:
  KeptFactorization();
  ~KeptFactorization();
  KeptFactorization(KeptFactorization&&) noexcept;
  KeptFactorization& operator=(KeptFactorization&&) noexcept;

  bool empty() const { return factorization_ == nullptr; }

 private:
  friend MinimizeResult minimizeNewton(const Problem&, const BoundaryConditions&,
                                       const MinimizeOptions&, KeptFactorization*);
  std::unique_ptr<HessianFactorization> factorization_;
  bool haveFactor_ = false;  // it holds a numerical factor (the last solve's last one)
};

// The minimizer of the problem's terms over its free unknowns, with its boundary values — or with
// `conditions` in their place (other held sets and values on the same problem, as the C2 study
// solves one plate for several boundary surfaces). The problem's load (E − Σ_v f_v · x_v, a linear
// term that is no least-squares residual) and obstacles (their barrier joins E, every line-search
// step is capped so that no vertex reaches one; the start — with Start::Linearized the fixed
// vertices at their values, the free ones at rest — must have every vertex outside) need the
// Newton solve: the linearized and Ceres solves refuse them.
//
// Throws InputError for a problem that has no unique minimizer: nothing fixed in height mode,
// everything fixed, a free vertex no element touches; and, for the problem's own boundary, ξ
// clamped for the other kind of solve (MinimizeOptions.linearized against
// ProblemOptions.linearizedClamp). Does not throw on non-convergence: the report says so
// (converged = false).
// `kept` (Newton only): the analysis and factor of the last solve on the same pattern, taken and
// refilled (KeptFactorization).
MinimizeResult minimize(const Problem& problem, const MinimizeOptions& options,
                        KeptFactorization* kept = nullptr);
MinimizeResult minimize(const Problem& problem, const BoundaryConditions& conditions,
                        const MinimizeOptions& options, KeptFactorization* kept = nullptr);

}  // namespace flexure::optimize
