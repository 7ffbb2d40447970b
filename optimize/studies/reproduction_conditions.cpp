// The flat plate test problem and the two necessary conditions: C1 (the linearized energy per
// covered area of a quadratic against the continuum density) and C2 (the linearized minimizer
// with a quadratic's boundary data reproduces it), linearized and nonlinear, with the factored
// solves shared by a case's boundary data.
#include "optimize/studies/reproduction_conditions.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "optimize/linear/least_squares.h"
#include "optimize/studies/convergence_study.h"
#include "optimize/studies/plate_polynomials.h"

namespace flexure::optimize {
using modeling::PolynomialSurface;

namespace {

// A relative reproduction error at or below this is round-off: the point says nothing about an
// order (nonlinear C2 fits leave it out).
constexpr double kRoundOff = 1e-12;

ProblemOptions flatPlateOptions(const curvature::BendingOptions& bending, int fixedRingCount) {
  ProblemOptions options;
  options.bending = bending;
  options.fixedRings = fixedRingCount;
  options.boundaryNormals = BoundaryNormals::Free;  // no surface yet to clamp to
  return options;
}

}  // namespace

double c1Measure(double energyPerArea, const PolynomialSurface& p, double poisson) {
  return std::abs(energyPerArea - plateDensity(p, poisson, 0.0, 0.0)) /
         hessianSquaredNorm(p, 0.0, 0.0);
}

FlatPlateProblem::FlatPlateProblem(const modeling::Mesh& flat,
                                   const curvature::BendingOptions& options, int fixedRingCount)
    : Problem(buildProblem(flat, flatPlateOptions(options, fixedRingCount))),
      restJacobian(residualJacobian(termPointers(), rest.positions, restXi)) {}

double linearizedEnergyPerArea(const FlatPlateProblem& problem, const PolynomialSurface& p) {
  const modeling::Positions& rest = problem.rest.positions;
  modeling::Positions delta = modeling::Positions::Zero(rest.rows(), 3);
  for (int v = 0; v < delta.rows(); ++v) delta(v, 2) = p.height(rest(v, 0), rest(v, 1));
  // Midedge: the boundary ξ clamped to p (linearized), the interior ξ free.
  Eigen::VectorXd deltaXi;
  std::vector<bool> freeEdge;
  if (problem.bending().usesEdgeUnknowns()) {
    deltaXi = curvature::linearizedClampedBoundaryXi(problem.stencils, rest, delta, p);
    freeEdge = curvature::boundaryEdges(problem.stencils);
    freeEdge.flip();
  }
  return linearizedEnergyOfDisplacement(problem.restJacobian, rest, delta, deltaXi, freeEdge) /
         problem.bending().coveredArea();
}

double c1Error(const FlatPlateProblem& problem, const PolynomialSurface& p, double poisson) {
  return c1Measure(linearizedEnergyPerArea(problem, p), p, poisson);
}

MinimizeResult solveWithSurfaceBoundary(const FlatPlateProblem& problem, const PolynomialSurface& u,
                                        BoundaryNormals normals, bool linearized,
                                        MinimizeOptions options) {
  options.linearized = linearized;
  const BoundaryConditions bc =
      surfaceBoundary(problem.stencils, problem.rest.positions, problem.restXi,
                      problem.boundary.fixedVertex, u, normals, linearized);
  return minimize(problem, bc, options);
}

double c2Error(const FlatPlateProblem& problem, const PolynomialSurface& p,
               BoundaryNormals normals) {
  MinimizeOptions options;
  options.threads = 1;
  const MinimizeResult result = solveWithSurfaceBoundary(problem, p, normals, true, options);
  return reproductionError(problem.rest.positions, result.positions, problem.boundary.fixedVertex,
                           p);
}

namespace {

// The unknowns of solveWithSurfaceBoundary's linearized solve: interior z; midedge ξ free but on
// the boundary when clamped (surfaceBoundary). The data move the fixed vertices in z only.
LinearizedUnknowns surfaceUnknowns(const FlatPlateProblem& problem, BoundaryNormals normals) {
  LinearizedUnknowns unknowns;
  unknowns.fixedVertex = problem.boundary.fixedVertex;
  unknowns.fixedEdge.assign(problem.restXi.size(), false);
  if (problem.restXi.size() > 0 && normals == BoundaryNormals::Clamped)
    unknowns.fixedEdge = curvature::boundaryEdges(problem.stencils);
  unknowns.heightOnly = true;
  return unknowns;
}

}  // namespace

FlatPlateSolves::FlatPlateSolves(const FlatPlateProblem& problem, BoundaryNormals normals)
    : problem_(problem), normals_(normals) {
  std::vector<bool> touched(problem.boundary.fixedVertex.size(), false);
  problem.bending().markTouchedVertices(touched);
  for (size_t v = 0; v < touched.size(); ++v) {
    if (!problem.boundary.fixedVertex[v] && !touched[v])
      throw InputError("free vertex " + std::to_string(v) +
                       " is touched by no element of the energy, so nothing determines it");
  }
  // J at rest with all derivatives: its z and ξ columns are those of the height-mode J that
  // minimize() evaluates, and the x, y columns meet only zero moves, so the solves are the same.
  solver_ = std::make_unique<LinearizedSolver>(
      problem.restJacobian,
      freeUnknownMask(surfaceUnknowns(problem, normals), static_cast<int>(problem.restXi.size())),
      problem.rest.positions, problem.restXi);
}

FlatPlateSolves::~FlatPlateSolves() = default;

LinearizedSolution FlatPlateSolves::surface(const PolynomialSurface& u) const {
  return solver_->solve(surfaceBoundary(problem_.stencils, problem_.rest.positions, problem_.restXi,
                                        problem_.boundary.fixedVertex, u, normals_, true));
}

int FlatPlateSolves::factorizations() const {
  return solver_->factorizations();
}

FlatPlateEnergyPerArea::FlatPlateEnergyPerArea(const FlatPlateProblem& problem)
    : problem_(problem) {
  if (!problem.bending().usesEdgeUnknowns()) return;
  // linearizedEnergyOfDisplacement: positions given, the interior ξ free.
  const int positionCount = static_cast<int>(problem.rest.positions.size());
  std::vector<bool> free(problem.restJacobian.cols(), false);
  const std::vector<bool> onBoundary = curvature::boundaryEdges(problem.stencils);
  for (size_t e = 0; e < onBoundary.size(); ++e) free[positionCount + e] = !onBoundary[e];
  interiorXi_ =
      std::make_unique<LinearizedSolver>(problem.restJacobian, free, problem.rest.positions);
}

FlatPlateEnergyPerArea::~FlatPlateEnergyPerArea() = default;

double FlatPlateEnergyPerArea::operator()(const PolynomialSurface& p) const {
  if (!interiorXi_) return linearizedEnergyPerArea(problem_, p);
  const modeling::Positions& rest = problem_.rest.positions;
  const int positionCount = static_cast<int>(rest.size());
  Eigen::VectorXd u = Eigen::VectorXd::Zero(problem_.restJacobian.cols());
  for (int v = 0; v < rest.rows(); ++v) u[3 * v + 2] = p.height(rest(v, 0), rest(v, 1));
  modeling::Positions delta = Eigen::Map<const modeling::Positions>(u.data(), rest.rows(), 3);
  u.tail(u.size() - positionCount) =
      curvature::linearizedClampedBoundaryXi(problem_.stencils, rest, delta, p);
  return interiorXi_->energy(interiorXi_->solve(u)) / problem_.bending().coveredArea();
}

int FlatPlateEnergyPerArea::factorizations() const {
  return interiorXi_ ? interiorXi_->factorizations() : 0;
}

NonlinearC2Series nonlinearC2(const FlatPlateProblem& problem, const PolynomialSurface& p,
                              BoundaryNormals normals, int amplitudeCount,
                              MinimizeOptions options) {
  NonlinearC2Series series;
  std::vector<double> fitAmplitudes, fitErrors;
  for (int k = 1; k <= amplitudeCount; ++k) {
    const double eps = std::ldexp(1.0, -k);
    const PolynomialSurface data = scaledSurface(p, eps);
    const MinimizeResult result = solveWithSurfaceBoundary(problem, data, normals, false, options);
    series.converged = series.converged && result.report.converged;
    series.factorizations += result.report.factorizations;
    const double error = reproductionError(problem.rest.positions, result.positions,
                                           problem.boundary.fixedVertex, data);
    series.amplitudes.push_back(eps);
    series.errors.push_back(error);
    if (error > kRoundOff) {
      fitAmplitudes.push_back(eps);
      fitErrors.push_back(eps * error);  // ∝ the absolute error max |z − εp|
    }
  }
  if (fitAmplitudes.size() >= 2) series.order = logLogSlope(fitAmplitudes, fitErrors);
  return series;
}

}  // namespace flexure::optimize
