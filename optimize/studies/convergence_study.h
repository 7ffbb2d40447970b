// Convergence studies: "with sufficient refinement, does the discrete energy agree with the
// continuous energy?" (slides, seed 000_…), answered through the two necessary conditions of
// docs/energies.md and a refinement study against an exact plate solution.
//
//   C1            |E_lin(p)/A_cov − Ψ_ν(∇²p)| / |∇²p|²  for a sampled quadratic p (the spec's
//                 energy per covered area against the continuum density; |M|² = tr M² makes the
//                 error relative and defined when Ψ_ν(∇²p) = 0, e.g. a saddle under a ν = 1 model)
//   C2            max_interior |z − p| / max |p|  of the linearized minimizer with rings 0 and 1
//                 fixed at p (midedge: boundary ξ clamped, linearized clamp, or free)
//   nonlinear C2  the same for the full energy at boundary amplitude ε = 2⁻ᵏ: the minimizer with
//                 data εp misses εp by ~ε^order in absolute terms (order 1 when linearized C2
//                 fails; for a flat rest the minimizer is odd in ε, so a pass gives order ≥ 3)
//   refinement    a polynomial plate solution u (Δ²u = 0, e.g. x⁴ − 3x²y²) as data on rings 0
//                 and 1 of meshes with n, 2n, 4n, … cells per side; errors of the linearized
//                 minimizer and of its energy, and their least-squares log-log slopes in h = 1/n
//
// The exact energy is ∫ Ψ_ν(∇²u) over the whole square, not over the area A_cov the discrete
// energy's elements cover: an energy that leaves out elements at the boundary (hinge, triavg,
// cotan, quadfit: A_cov falls short of 1 by O(h)) carries that deficit in its energy error;
// midedge covers every face.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "curvature/bending_energy.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/boundary_conditions.h"
#include "optimize/linear/linearized_solver.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace flexure::optimize {

// ---------------------------------------------------------------------------------------------
// The test problem and the conditions, one function each

// The slides' test problem: a flat mesh (z = 0) built by buildProblem with one bending energy
// bound to its rest state, the vertices of rings 0 .. fixedRingCount − 1 held at rest (every
// ξ free: each case sets its own boundary through surfaceBoundary), and the residual Jacobian at
// rest (E_lin), which only the study needs.
struct FlatPlateProblem : Problem {
  SparseMatrix restJacobian;  // J at rest: columns 3 #V positions (+ #E ξ for midedge)

  // Throws InputError (naming the element) for a rest element the energy cannot use.
  FlatPlateProblem(const modeling::Mesh& flat, const curvature::BendingOptions& options,
                   int fixedRingCount = 2);
};

// C1's energy per covered area E_lin(p) / A_cov of the displacement z = p(x̄, ȳ), with midedge
// boundary ξ clamped to p (linearized clamp) and interior ξ minimized.
double linearizedEnergyPerArea(const FlatPlateProblem& problem,
                               const modeling::PolynomialSurface& p);

// The continuum density ρ = Ψ_ν(∇²p) and the scale |∇²p|² = tr (∇²p)² at (x, y) (constant for a
// quadratic).
double plateDensity(const modeling::PolynomialSurface& p, double poisson, double x = 0.0,
                    double y = 0.0);
double hessianSquaredNorm(const modeling::PolynomialSurface& p, double x = 0.0, double y = 0.0);

// C1: |E_lin(p)/A_cov − Ψ_ν(∇²p)| / |∇²p|² for a quadratic p, ν the energy's effective ν.
double c1Error(const FlatPlateProblem& problem, const modeling::PolynomialSurface& p,
               double poisson);

// The minimizer with the fixed vertices lifted onto z = u(x̄, ȳ) (surfaceBoundary), the interior
// free (in height mode unless `options` say xyz); midedge boundary ξ clamped to u's normals or
// free.
MinimizeResult solveWithSurfaceBoundary(const FlatPlateProblem& problem,
                                        const modeling::PolynomialSurface& u,
                                        BoundaryNormals normals, bool linearized,
                                        MinimizeOptions options = {});

// The linearized solves of one FlatPlateProblem, each ordered and factored once
// (linear/linearized_solver.h) and reused for every boundary datum; results equal the one-off
// functions' bit for bit. Both keep a reference to the problem.
//
// C2's and the refinement's: interior z and the free ξ, with boundary normals `normals`.
class FlatPlateSolves {
 public:
  FlatPlateSolves(const FlatPlateProblem& problem, BoundaryNormals normals);
  ~FlatPlateSolves();
  // solveWithSurfaceBoundary(problem, u, normals, linearized = true): the minimizer with the
  // fixed vertices on z = u.
  LinearizedSolution surface(const modeling::PolynomialSurface& u) const;
  int factorizations() const;  // numerical factorizations made (1 without a ridge retry)

 private:
  const FlatPlateProblem& problem_;
  BoundaryNormals normals_;
  std::unique_ptr<LinearizedSolver> solver_;
};

// C1's: linearizedEnergyPerArea(problem, p) for many p; for midedge the interior ξ solve at a
// given displacement is factored once (other energies need no solve).
class FlatPlateEnergyPerArea {
 public:
  explicit FlatPlateEnergyPerArea(const FlatPlateProblem& problem);
  ~FlatPlateEnergyPerArea();
  double operator()(const modeling::PolynomialSurface& p) const;
  int factorizations() const;

 private:
  const FlatPlateProblem& problem_;
  std::unique_ptr<LinearizedSolver> interiorXi_;
};

// C2: reproductionError of the linearized minimizer with boundary data p.
double c2Error(const FlatPlateProblem& problem, const modeling::PolynomialSurface& p,
               BoundaryNormals normals);

// Nonlinear C2 at the amplitudes ε_k = 2⁻ᵏ, k = 1 .. amplitudeCount.
struct NonlinearC2Series {
  std::vector<double> amplitudes;  // ε_k
  std::vector<double> errors;      // reproductionError with data ε_k p (relative to max |ε_k p|)
  std::optional<double> order;     // slope of log(ε_k · error_k) vs log ε_k; empty when exact
  bool converged = true;           // every nonlinear solve converged
  int factorizations = 0;          // of all the nonlinear solves
};
NonlinearC2Series nonlinearC2(const FlatPlateProblem& problem, const modeling::PolynomialSurface& p,
                              BoundaryNormals normals, int amplitudeCount,
                              MinimizeOptions options = {});

// ∫ Ψ_ν(∇²u) dA over the square [−½, ½]² of the generated meshes, by tensor Gauss–Legendre
// quadrature with enough points to be exact for the polynomial u.
double squarePlateEnergy(const modeling::PolynomialSurface& u, double poisson);

// Least-squares slope of log y against log x (x, y > 0; at least two points).
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y);

// ---------------------------------------------------------------------------------------------
// Verdicts

// The spec's thresholds for C1 and C2 (worst error over the quadratics): pass below 1e-9, fail
// above 1e-4, anything between is inconclusive.
enum class Reproduction { Pass, Fail, Inconclusive };
inline constexpr double kReproductionPass = 1e-9;
inline constexpr double kReproductionFail = 1e-4;
Reproduction classifyReproduction(double worstError);
std::string_view reproductionName(Reproduction r);  // "pass" | "fail" | "inconclusive"

// A refinement series (errors from coarsest to finest): Exact when the coarsest error is below
// kReproductionPass (the discretization reproduces the data on that kind of mesh; the finer
// levels then only show round-off, which grows with the n⁴ conditioning of the bending operator:
// ≈ 1e-14 at n = 8, 1e-10 at n = 64); DoesNotConverge when the finest error is not below
// kStallRatio × the one before (doubling n bought less than 30 %); otherwise Converges. A single
// level that is not exact is Unmeasured.
enum class Refinement { Converges, DoesNotConverge, Exact, Unmeasured };
inline constexpr double kStallRatio = 0.7;
Refinement classifyRefinement(const std::vector<double>& errors);
std::string_view refinementName(Refinement r);  // "converges" | "does not converge" | …
// The least-squares slope of log error against log h over the positive errors of a series that
// converges or stalls (an exact or unmeasured series has no order).
std::optional<double> seriesOrder(const std::vector<double>& h, const std::vector<double>& errors,
                                  Refinement verdict);

// ---------------------------------------------------------------------------------------------
// The study

// One energy of a study: a discretization with its options and, for midedge, how the boundary ξ
// are held. `label` names it in tables: "hinge", "hinge(tan)", "triavg", "cotan(voronoi)",
// "cotan(barycentric)", "midedge(clamped)", "midedge(free)", "quadfit".
struct EnergyVariant {
  std::string label;
  curvature::BendingOptions bending;
  BoundaryNormals normals = BoundaryNormals::Clamped;
};

// "hinge", "hinge:tan", "triavg", "cotan" (= "cotan:voronoi"), "cotan:barycentric", "midedge"
// (= "midedge:clamped"), "midedge:free", "quadfit". `poisson` goes to the energies that take a ν
// (triavg, midedge, quadfit; hinge and cotan are ν = 1 models). Throws InputError listing the
// names.
EnergyVariant parseEnergyVariant(std::string_view spec, std::optional<double> poisson = {});
// The study's energies and families by name, for every front end: InputError naming the field
// ("StudyOptions.energies: unknown energy 'x' (expected …)", "StudyOptions.families: …").
std::vector<EnergyVariant> parseEnergyVariants(const std::vector<std::string>& specs,
                                               std::optional<double> poisson = {});
std::vector<modeling::MeshFamily> parseStudyFamilies(const std::vector<std::string>& names);
// The spec parseEnergyVariant reads back into `v`: its label with "(option)" as ":option"
// ("hinge(tan)" → "hinge:tan", "midedge(free)" → "midedge:free").
std::string energyVariantSpec(const EnergyVariant& v);
// The spellings parseEnergyVariant takes, in registry order: each energy's name, and name:option
// for each option it reads (hinge:tan, cotan:barycentric and, withBoundaryNormals, midedge:free);
// the last two joined by `lastSeparator`.
std::string energyVariantSpecs(bool withBoundaryNormals, std::string_view lastSeparator);
// The seven rows of the spec's table, in its order (the registry entries' studyVariants).
std::vector<EnergyVariant> defaultEnergyVariants(std::optional<double> poisson = {});

// p = a x² + b xy + c y².
struct Quadratic {
  double a = 0.0, b = 0.0, c = 0.0;
  modeling::PolynomialSurface surface(double scale = 1.0) const {
    return modeling::PolynomialSurface::quadratic(scale * a, scale * b, scale * c);
  }
};
// (1,0,0), (0,1,0), (1,0,1), (1,0,−1), (0.3,−0.7,0.5).
std::vector<Quadratic> defaultQuadratics();

// A flat mesh of the user's (z ≡ 0; x, y are used): C1, C2 and nonlinear C2, no refinement.
struct UserMesh {
  std::string name;  // file name, used in errors and tables
  modeling::Mesh mesh;
};

// The default refinement data u = x⁴ − 3x²y²: biharmonic (Δ²u = 24 − 24 = 0), so it is the
// clamped plate's solution for every ν; not harmonic (Δu = 6x² − 6y²), so the ν = 1 energies see
// it; and u_xxyy ≠ 0. A cubic such as x³ − 3xy² is a poor default: every fourth derivative of a
// cubic vanishes, so any fourth-order limit equation, right or wrong, accepts it, and on the 4-8
// patch even hinge reproduces it to round-off (measured), hiding the stall this study exists to
// show.
inline constexpr const char* kDefaultSolution = "polynomial:x^4-3*x^2*y^2";

struct StudyOptions {
  std::vector<EnergyVariant> energies = defaultEnergyVariants();
  std::vector<modeling::MeshFamily> families = {
      modeling::MeshFamily::Patch48, modeling::MeshFamily::Stripe, modeling::MeshFamily::Criss,
      modeling::MeshFamily::Delaunay};
  std::vector<std::uint64_t> seeds = {1};  // delaunay: one mesh sequence per seed
  std::vector<UserMesh> userMeshes;
  int baseN = 8;   // cells per side of the coarsest level
  int levels = 3;  // n, 2n, …, 2^(levels−1) n
  std::vector<Quadratic> quadratics = defaultQuadratics();
  int amplitudes = 4;  // nonlinear C2 at ε = 2⁻¹ … 2⁻ᴷ on the coarsest level; 0: none
  std::string solution = kDefaultSolution;  // refinement data; empty: no refinement
  int threads = 2;                          // independent cases run on this many threads
  Solver solver = Solver::Newton;           // the nonlinear C2 solves
  HessianMode hessian = HessianMode::Exact;

  // Throws InputError naming the field ("StudyOptions.levels 9: expected 1 to 8") for an unusable
  // study: no energies, no meshes, baseN < 4, levels outside 1..8, amplitudes other than 0 or
  // 2..12, threads < 1, a zero quadratic, a solution that does not parse, is zero or is not
  // biharmonic (Δ²u ≠ 0: no plate's solution), a user mesh that is not flat (z ≢ 0).
  void validate() const;
};

enum class RecordKind { Quadratic, NonlinearC2, Refinement };
std::string_view recordKindName(RecordKind kind);  // "quadratic" | "nonlinear_c2" | "refinement"

// One run: an energy on one mesh with one boundary datum.
struct StudyRecord {
  RecordKind kind = RecordKind::Quadratic;
  int energy = 0;                     // index into StudyOptions::energies
  std::string family;                 // "patch48", "stripe", "criss", "delaunay" or a user mesh
  std::optional<std::uint64_t> seed;  // delaunay
  std::optional<int> n;               // generated meshes: cells per side
  int level = 0;                      // 0 = coarsest
  double h = 0.0;                     // 1/n (user meshes: the mean rest edge length)
  int vertices = 0, freeVertices = 0;
  std::string data;  // the quadratic ("quadratic:a,b,c") or the solution's spec

  // Quadratic: C1 (not for free midedge normals: the spec's "—") and linearized C2.
  std::optional<double> energyPerArea, density, c1Error;
  double c2Error = 0.0;
  // Numerical sparse Cholesky factorizations made for this record: the case's linearized solves
  // share their factors (FlatPlateSolves, FlatPlateEnergyPerArea), counted on its first record;
  // nonlinear C2 counts its Newton (or Ceres) factorizations.
  int factorizations = 0;
  // NonlinearC2
  NonlinearC2Series nonlinear;
  // Refinement (order, energyOrder and verdict: the series' fit, on each of its records)
  double solutionError = 0.0;  // max interior |z − u| / max |u|
  double discreteEnergy = 0.0, exactEnergy = 0.0;
  double energyError = 0.0;  // |E_lin(z) − ∫Ψ_ν(∇²u)| / ∫|∇²u|²
  std::optional<double> order, energyOrder;
  Refinement verdict = Refinement::Unmeasured, energyVerdict = Refinement::Unmeasured;
};

// One refinement series: an energy on one family (and seed) over the levels.
struct RefinementFit {
  int energy = 0;
  std::string family;
  std::optional<std::uint64_t> seed;
  std::vector<int> n;
  std::vector<double> h, solutionErrors, energyErrors;
  std::optional<double> order, energyOrder;  // slopes in log h; empty when Exact or Unmeasured
  Refinement verdict = Refinement::Unmeasured, energyVerdict = Refinement::Unmeasured;
};

struct StudyResults {
  std::vector<StudyRecord> records;        // energy-major, then mesh (families, seeds, levels, user
                                           // meshes), then quadratic records, nonlinear, refinement
  std::vector<RefinementFit> refinements;  // energy-major, then family, seed
};

struct StudyProgress {
  int done = 0, total = 0;
  std::string finished;  // the case just finished, e.g. "midedge(free) on delaunay seed 1 n=16"
  // Or a step inside a long case (a mesh of at least kStepProgressVertices vertices) about to run:
  // `running` names the case, `step` the solve ("solve 3 of 6: C2, quadratic:1,0,1"); `finished`
  // is empty and `done` counts the cases finished so far.
  std::string running, step;
};

// From this many vertices a case reports its steps (measured: a linearized solve on the 66 049
// vertices of patch48 at n = 256 takes about a second, 11 with midedge).
inline constexpr int kStepProgressVertices = 50000;

// The peak memory a study needs, estimated before any mesh is made: each case (an energy on a
// mesh) needs kStudyCaseBaseBytes plus, per vertex, studyBytesPerVertex(its discretization); up
// to `threads` cases run at once, so the peak is the sum of the `threads` largest cases.
inline constexpr double kStudyCaseBaseBytes = 50e6;
double studyBytesPerVertex(curvature::Discretization discretization);

struct StudyMemoryEstimate {
  double peakBytes = 0.0;  // the `concurrent` largest cases together
  double largestCaseBytes = 0.0;
  double largestCaseVertices = 0.0;
  std::string largestCase;  // e.g. "midedge(clamped) on delaunay n=1024"
  int concurrent = 1;
};
// Generated meshes count (n + 1)² vertices (delaunay 1.25 (n + 1)², measured 1.21 at n = 128);
// user meshes their own. Throws what StudyOptions::validate throws.
StudyMemoryEstimate estimateStudyMemory(const StudyOptions& options);

// Runs every case (an energy on a mesh) on `options.threads` threads; the results do not depend
// on the thread count. `progress` (may be empty) is called after each case, from one thread at a
// time. Throws what StudyOptions::validate throws, and the first error of a case (in case order).
StudyResults runConvergenceStudy(const StudyOptions& options,
                                 const std::function<void(const StudyProgress&)>& progress = {});

// ---------------------------------------------------------------------------------------------
// The summary: the spec's table computed live

// C1 and C2 are judged on the coarsest level (the spec's table is the n = 8 test problem; the
// finer levels' errors are in the records: a pass grows with the conditioning, ≈ 5e-9 at n = 64).
struct SummaryCell {
  std::optional<double> worstC1;  // empty for midedge(free)
  double worstC2 = 0.0;
  std::optional<Reproduction> c1;
  Reproduction c2 = Reproduction::Pass;
  // Smallest nonlinear-C2 order over the quadratics and seeds (empty: none measured or exact).
  std::optional<double> nonlinearOrder;
  bool nonlinearConverged = true;
  // Refinement, generated families: the smallest order over the seeds, and DoesNotConverge when
  // any seed's series stalls.
  std::optional<double> refinementOrder, energyOrder;
  Refinement refinement = Refinement::Unmeasured, energyRefinement = Refinement::Unmeasured;
  std::optional<double> finestError, finestEnergyError;  // largest over the seeds, finest level
};

struct StudySummary {
  std::vector<std::string> energies;  // row labels
  std::vector<std::string> families;  // column labels: generated families, then user meshes
  std::vector<std::vector<SummaryCell>> cells;  // [energy][family]
};

StudySummary summarizeStudy(const StudyOptions& options, const StudyResults& results);

}  // namespace flexure::optimize
