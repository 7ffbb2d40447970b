#include "optimize/studies/convergence_study.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

#include "curvature/bending_spec.h"
#include "curvature/energy_registry.h"
#include "curvature/koiter_density.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "modeling/mesh_info.h"

namespace flexure::optimize {
namespace {

using modeling::PolynomialSurface;

// A relative reproduction error at or below this is round-off: the point says nothing about an
// order (nonlinear C2 fits leave it out).
constexpr double kRoundOff = 1e-12;

// Ψ_ν of the Hessian of u at (x, y).
double hessianDensity(const PolynomialSurface& u, double poisson, double x, double y) {
  const Eigen::Matrix2d h = u.hessian(x, y);
  return curvature::koiterDensity({h(0, 0), h(0, 1), h(1, 1)}, poisson);
}

PolynomialSurface scaledSurface(const PolynomialSurface& p, double scale) {
  std::vector<modeling::Monomial> terms = p.terms();
  for (modeling::Monomial& term : terms) term.coefficient *= scale;
  return PolynomialSurface(std::move(terms));
}

bool isZero(const PolynomialSurface& p) {
  return std::all_of(p.terms().begin(), p.terms().end(),
                     [](const modeling::Monomial& m) { return m.coefficient == 0.0; });
}

// The largest coefficient of Δ²u, relative to the largest |c| (i + j)⁴ of u's terms c xⁱ yʲ:
// Δ²(xⁱ yʲ) = i(i−1)(i−2)(i−3) xⁱ⁻⁴ yʲ + 2 i(i−1) j(j−1) xⁱ⁻² yʲ⁻² + j(j−1)(j−2)(j−3) xⁱ yʲ⁻⁴.
double relativeBilaplacian(const PolynomialSurface& u) {
  std::map<std::pair<int, int>, double> bilaplacian;
  double scale = 0.0;
  for (const modeling::Monomial& m : u.terms()) {
    const double i = m.xPower, j = m.yPower, c = m.coefficient;
    scale = std::max(scale, std::abs(c) * std::pow(i + j, 4));
    if (m.xPower >= 4) bilaplacian[{m.xPower - 4, m.yPower}] += c * i * (i - 1) * (i - 2) * (i - 3);
    if (m.xPower >= 2 && m.yPower >= 2)
      bilaplacian[{m.xPower - 2, m.yPower - 2}] += 2 * c * i * (i - 1) * j * (j - 1);
    if (m.yPower >= 4) bilaplacian[{m.xPower, m.yPower - 4}] += c * j * (j - 1) * (j - 2) * (j - 3);
  }
  double largest = 0.0;
  for (const auto& [powers, coefficient] : bilaplacian)
    largest = std::max(largest, std::abs(coefficient));
  return scale > 0.0 ? largest / scale : 0.0;
}

// C1's measure of an energy per area against the continuum density, relative to
// |∇²p|² = tr (∇²p)², which is positive for any non-zero quadratic even where Ψ_ν(∇²p) = 0.
double c1Measure(double energyPerArea, const PolynomialSurface& p, double poisson) {
  return std::abs(energyPerArea - hessianDensity(p, poisson, 0.0, 0.0)) /
         hessianDensity(p, 0.0, 0.0, 0.0);
}

// Gauss–Legendre nodes and weights on [−1, 1] (m points, exact for degree 2m − 1): the roots of
// P_m by Newton's method from Tricomi's initial guesses, w = 2 / ((1 − x²) P_m'(x)²).
void gaussLegendre(int m, std::vector<double>& nodes, std::vector<double>& weights) {
  const double pi = std::acos(-1.0);
  nodes.assign(m, 0.0);
  weights.assign(m, 0.0);
  for (int i = 0; i < m; ++i) {
    double x = std::cos(pi * (i + 0.75) / (m + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      // P_m(x) and P_{m−1}(x) by the three-term recurrence, then
      // P_m'(x) = m (x P_m − P_{m−1}) / (x² − 1).
      double previous = 1.0, value = x;
      for (int k = 2; k <= m; ++k) {
        const double nextValue = ((2 * k - 1) * x * value - (k - 1) * previous) / k;
        previous = value;
        value = nextValue;
      }
      derivative = m * (x * value - previous) / (x * x - 1.0);
      const double step = value / derivative;
      x -= step;
      if (std::abs(step) < 1e-15) break;
    }
    nodes[i] = x;
    weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
  }
}

// One mesh of a study: a level of a generated family (and seed) or a user mesh.
struct StudyMesh {
  std::string family;
  std::optional<std::uint64_t> seed;
  std::optional<int> n;
  int level = 0;
  double h = 0.0;
  modeling::Mesh mesh;

  std::string describe() const {
    std::string s = family;
    if (seed) s += " seed " + std::to_string(*seed);
    if (n) s += " n=" + std::to_string(*n);
    return s;
  }
};

std::vector<StudyMesh> studyMeshes(const StudyOptions& options) {
  std::vector<StudyMesh> meshes;
  for (const modeling::MeshFamily family : options.families) {
    std::vector<std::optional<std::uint64_t>> seeds = {std::nullopt};
    if (family == modeling::MeshFamily::Delaunay)
      seeds.assign(options.seeds.begin(), options.seeds.end());
    for (const auto& seed : seeds) {
      const std::vector<modeling::Mesh> sequence = modeling::refinementSequence(
          {family, options.baseN, seed.value_or(1), {}}, options.levels);
      for (int level = 0; level < options.levels; ++level) {
        StudyMesh m;
        m.family = std::string(modeling::meshFamilyName(family));
        m.seed = seed;
        m.n = options.baseN << level;
        m.level = level;
        m.h = 1.0 / *m.n;
        m.mesh = sequence[level];
        meshes.push_back(std::move(m));
      }
    }
  }
  for (const UserMesh& user : options.userMeshes) {
    StudyMesh m;
    m.family = user.name;
    m.h = modeling::describeMesh(user.mesh).meanEdgeLength;
    m.mesh = user.mesh;
    meshes.push_back(std::move(m));
  }
  return meshes;
}

// Everything the study computes for one energy on one mesh. `step` (may be empty) is told each
// solve before it runs, on meshes of at least kStepProgressVertices vertices.
std::vector<StudyRecord> runCase(const StudyOptions& options, int energyIndex,
                                 const StudyMesh& studyMesh,
                                 const std::function<void(const std::string&)>& step) {
  const EnergyVariant& variant = options.energies[energyIndex];
  const FlatPlateProblem problem(studyMesh.mesh, variant.bending);
  const double poisson = curvature::effectivePoisson(variant.bending);
  const bool freeNormals =
      problem.bending().usesEdgeUnknowns() && variant.normals == BoundaryNormals::Free;
  MinimizeOptions solver;
  solver.threads = 1;  // cases run in parallel; one thread each keeps every sum in one order
  solver.solver = options.solver;
  solver.hessian = options.hessian;

  StudyRecord base;
  base.energy = energyIndex;
  base.family = studyMesh.family;
  base.seed = studyMesh.seed;
  base.n = studyMesh.n;
  base.level = studyMesh.level;
  base.h = studyMesh.h;
  base.vertices = studyMesh.mesh.vertexCount();
  base.freeVertices = static_cast<int>(
      std::count(problem.boundary.fixedVertex.begin(), problem.boundary.fixedVertex.end(), false));

  const bool refinement = studyMesh.n && !options.solution.empty();
  const bool nonlinear = studyMesh.level == 0 && options.amplitudes > 0;
  const int solves =
      static_cast<int>(options.quadratics.size()) * (nonlinear ? 2 : 1) + (refinement ? 1 : 0);
  int solve = 0;
  const auto announce = [&](const std::string& what) {
    ++solve;
    if (step && studyMesh.mesh.vertexCount() >= kStepProgressVertices) {
      step("solve " + std::to_string(solve) + " of " + std::to_string(solves) + ": " + what + " (" +
           std::to_string(studyMesh.mesh.vertexCount()) + " vertices)");
    }
  };
  // C1 first, its factor (midedge's interior ξ) freed before C2's is made: one factor alive at a
  // time, as when every solve factored its own.
  std::vector<StudyRecord> records;
  for (const Quadratic& q : options.quadratics) {
    StudyRecord r = base;
    r.kind = RecordKind::Quadratic;
    r.data = q.surface().spec();
    records.push_back(std::move(r));
  }
  if (!freeNormals) {
    const FlatPlateEnergyPerArea energyPerArea(problem);
    for (size_t k = 0; k < options.quadratics.size(); ++k) {
      const PolynomialSurface p = options.quadratics[k].surface();
      StudyRecord& r = records[k];
      r.energyPerArea = energyPerArea(p);
      r.density = plateDensity(p, poisson);
      r.c1Error = c1Measure(*r.energyPerArea, p, poisson);
    }
    records.front().factorizations += energyPerArea.factorizations();
  }
  // Every other linearized solve of the case shares one factor.
  const FlatPlateSolves linear(problem, variant.normals);
  for (size_t k = 0; k < options.quadratics.size(); ++k) {
    const PolynomialSurface p = options.quadratics[k].surface();
    announce("C1 and C2, " + p.spec());
    records[k].c2Error = reproductionError(problem.rest.positions, linear.surface(p).positions,
                                           problem.boundary.fixedVertex, p);
  }
  records.front().factorizations += linear.factorizations();
  if (nonlinear) {
    for (const Quadratic& q : options.quadratics) {
      announce("nonlinear C2, " + q.surface().spec() + " at " + std::to_string(options.amplitudes) +
               " amplitudes");
      StudyRecord r = base;
      r.kind = RecordKind::NonlinearC2;
      r.data = q.surface().spec();
      r.nonlinear = nonlinearC2(problem, q.surface(), variant.normals, options.amplitudes, solver);
      r.factorizations = r.nonlinear.factorizations;
      records.push_back(std::move(r));
    }
  }
  if (refinement) {
    const PolynomialSurface u = PolynomialSurface::parse(options.solution);
    announce("refinement, " + u.spec());
    StudyRecord r = base;
    r.kind = RecordKind::Refinement;
    r.data = u.spec();
    const LinearizedSolution result = linear.surface(u);
    r.solutionError = reproductionError(problem.rest.positions, result.positions,
                                        problem.boundary.fixedVertex, u);
    r.discreteEnergy = result.energy;
    r.exactEnergy = squarePlateEnergy(u, poisson);
    r.energyError = std::abs(r.discreteEnergy - r.exactEnergy) / squarePlateEnergy(u, 0.0);
    records.push_back(std::move(r));
  }
  return records;
}

void fitRefinements(StudyResults& results) {
  std::vector<std::vector<size_t>> series;  // record indices of each series, in level order
  for (size_t i = 0; i < results.records.size(); ++i) {
    const StudyRecord& r = results.records[i];
    if (r.kind != RecordKind::Refinement) continue;
    if (r.level > 0 && !series.empty()) {
      const StudyRecord& previous = results.records[series.back().back()];
      if (previous.energy == r.energy && previous.family == r.family && previous.seed == r.seed &&
          previous.level == r.level - 1) {
        series.back().push_back(i);
        continue;
      }
    }
    series.push_back({i});
  }
  for (const std::vector<size_t>& indices : series) {
    RefinementFit fit;
    const StudyRecord& first = results.records[indices.front()];
    fit.energy = first.energy;
    fit.family = first.family;
    fit.seed = first.seed;
    for (size_t i : indices) {
      const StudyRecord& r = results.records[i];
      fit.n.push_back(r.n.value_or(0));
      fit.h.push_back(r.h);
      fit.solutionErrors.push_back(r.solutionError);
      fit.energyErrors.push_back(r.energyError);
    }
    fit.verdict = classifyRefinement(fit.solutionErrors);
    fit.energyVerdict = classifyRefinement(fit.energyErrors);
    fit.order = seriesOrder(fit.h, fit.solutionErrors, fit.verdict);
    fit.energyOrder = seriesOrder(fit.h, fit.energyErrors, fit.energyVerdict);
    for (size_t i : indices) {
      StudyRecord& r = results.records[i];
      r.order = fit.order;
      r.energyOrder = fit.energyOrder;
      r.verdict = fit.verdict;
      r.energyVerdict = fit.energyVerdict;
    }
    results.refinements.push_back(std::move(fit));
  }
}

}  // namespace

std::optional<double> seriesOrder(const std::vector<double>& h, const std::vector<double>& errors,
                                  Refinement verdict) {
  if (verdict != Refinement::Converges && verdict != Refinement::DoesNotConverge) return {};
  std::vector<double> x, y;
  for (size_t k = 0; k < errors.size(); ++k) {
    if (errors[k] > 0.0) {
      x.push_back(h[k]);
      y.push_back(errors[k]);
    }
  }
  if (x.size() < 2) return {};
  return logLogSlope(x, y);
}

// ---------------------------------------------------------------------------------------------

namespace {

ProblemOptions flatPlateOptions(const curvature::BendingOptions& bending, int fixedRingCount) {
  ProblemOptions options;
  options.bending = bending;
  options.fixedRings = fixedRingCount;
  options.boundaryNormals = BoundaryNormals::Free;  // no surface yet to clamp to
  return options;
}

}  // namespace

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

double plateDensity(const PolynomialSurface& p, double poisson, double x, double y) {
  return hessianDensity(p, poisson, x, y);
}

double hessianSquaredNorm(const PolynomialSurface& p, double x, double y) {
  return hessianDensity(p, 0.0, x, y);  // Ψ_0(M) = tr M²
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

double squarePlateEnergy(const PolynomialSurface& u, double poisson) {
  // Ψ_ν(∇²u) has degree ≤ 2 d in each variable (d the largest power of u): d + 1 points suffice.
  int degree = 0;
  for (const modeling::Monomial& m : u.terms()) degree = std::max({degree, m.xPower, m.yPower});
  std::vector<double> nodes, weights;
  gaussLegendre(degree + 1, nodes, weights);
  // [−1, 1] → [−½, ½]: x = t / 2, dx = dt / 2.
  double sum = 0.0;
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t j = 0; j < nodes.size(); ++j)
      sum += weights[i] * weights[j] * hessianDensity(u, poisson, nodes[i] / 2, nodes[j] / 2);
  return sum / 4.0;
}

double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t count = x.size();
  double meanX = 0.0, meanY = 0.0;
  for (size_t k = 0; k < count; ++k) {
    meanX += std::log(x[k]) / count;
    meanY += std::log(y[k]) / count;
  }
  double sxy = 0.0, sxx = 0.0;
  for (size_t k = 0; k < count; ++k) {
    const double dx = std::log(x[k]) - meanX;
    sxy += dx * (std::log(y[k]) - meanY);
    sxx += dx * dx;
  }
  return sxy / sxx;
}

// ---------------------------------------------------------------------------------------------

Reproduction classifyReproduction(double worstError) {
  if (worstError < kReproductionPass) return Reproduction::Pass;
  if (worstError > kReproductionFail) return Reproduction::Fail;
  return Reproduction::Inconclusive;
}

std::string_view reproductionName(Reproduction r) {
  switch (r) {
    case Reproduction::Pass:
      return "pass";
    case Reproduction::Fail:
      return "fail";
    case Reproduction::Inconclusive:
      return "inconclusive";
  }
  return "unknown";
}

Refinement classifyRefinement(const std::vector<double>& errors) {
  if (!errors.empty() && errors.front() < kReproductionPass) return Refinement::Exact;
  if (errors.size() < 2) return Refinement::Unmeasured;
  if (errors.back() >= kStallRatio * errors[errors.size() - 2]) return Refinement::DoesNotConverge;
  return Refinement::Converges;
}

std::string_view refinementName(Refinement r) {
  switch (r) {
    case Refinement::Converges:
      return "converges";
    case Refinement::DoesNotConverge:
      return "does not converge";
    case Refinement::Exact:
      return "exact";
    case Refinement::Unmeasured:
      return "unmeasured";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------------------------

std::string energyVariantSpecs(bool withBoundaryNormals, std::string_view lastSeparator) {
  std::vector<std::string> specs;
  for (const curvature::EnergyEntry& e : curvature::registeredEnergies()) {
    specs.push_back(e.name);
    if (e.readsHingeAngle) specs.push_back(e.name + ":tan");
    if (e.readsVertexArea) specs.push_back(e.name + ":barycentric");
    if (e.restEdgeUnknowns && withBoundaryNormals) specs.push_back(e.name + ":free");
  }
  std::string joined;
  for (size_t k = 0; k < specs.size(); ++k)
    joined += std::string(k == 0 ? "" : k + 1 == specs.size() ? lastSeparator : ", ") + specs[k];
  return joined;
}

EnergyVariant parseEnergyVariant(std::string_view spec, std::optional<double> poisson) {
  const std::string text(spec);
  const auto colon = text.find(':');
  const std::string name = text.substr(0, colon);
  const std::string option = colon == std::string::npos ? "" : text.substr(colon + 1);
  const auto unknown = [&]() -> InputError {
    return InputError("unknown energy '" + text + "' (expected " +
                      energyVariantSpecs(true, " or ") + ")");
  };
  const auto& energies = curvature::registeredEnergies();
  const auto found = std::find_if(energies.begin(), energies.end(),
                                  [&](const curvature::EnergyEntry& e) { return e.name == name; });
  if (found == energies.end()) throw unknown();
  const curvature::EnergyEntry& e = *found;
  EnergyVariant v;
  v.bending.discretization = curvature::Discretization(static_cast<int>(found - energies.begin()));
  v.label = e.name;
  const auto either = [&](const char* first, const char* second) {
    return option.empty() || option == first || option == second;
  };
  if (e.readsHingeAngle && either("theta", "tan")) {
    if (!option.empty()) v.bending.hingeAngle = curvature::parseHingeAngle(option);
    if (option == "tan") v.label += "(tan)";
  } else if (e.readsVertexArea && either("voronoi", "barycentric")) {
    if (!option.empty()) v.bending.vertexArea = curvature::parseVertexArea(option);
    v.label += std::string("(") + curvature::vertexAreaName(v.bending.vertexArea) + ")";
  } else if (e.restEdgeUnknowns && either("clamped", "free")) {
    v.normals = option == "free" ? BoundaryNormals::Free : BoundaryNormals::Clamped;
    v.label += option == "free" ? "(free)" : "(clamped)";
  } else if (!option.empty()) {
    throw unknown();
  }
  if (e.poissonRule == curvature::PoissonRule::Koiter) v.bending.poisson = poisson;
  curvature::effectivePoisson(v.bending);  // rejects a ν outside [−1, 1]
  return v;
}

std::vector<EnergyVariant> defaultEnergyVariants(std::optional<double> poisson) {
  std::vector<const curvature::EnergyEntry*> entries;
  for (const curvature::EnergyEntry& e : curvature::registeredEnergies()) entries.push_back(&e);
  std::stable_sort(entries.begin(), entries.end(),
                   [](const auto* a, const auto* b) { return a->studyRank < b->studyRank; });
  std::vector<EnergyVariant> variants;
  for (const curvature::EnergyEntry* e : entries)
    for (const std::string& spec : e->studyVariants)
      variants.push_back(parseEnergyVariant(spec, poisson));
  return variants;
}

std::vector<Quadratic> defaultQuadratics() {
  return {{1, 0, 0}, {0, 1, 0}, {1, 0, 1}, {1, 0, -1}, {0.3, -0.7, 0.5}};
}

std::string_view recordKindName(RecordKind kind) {
  switch (kind) {
    case RecordKind::Quadratic:
      return "quadratic";
    case RecordKind::NonlinearC2:
      return "nonlinear_c2";
    case RecordKind::Refinement:
      return "refinement";
  }
  return "unknown";
}

void StudyOptions::validate() const {
  const StudyOptions& o = *this;
  if (o.energies.empty()) throw InputError("StudyOptions.energies: no energy to study");
  for (const EnergyVariant& v : o.energies) curvature::effectivePoisson(v.bending);
  if (o.families.empty() && o.userMeshes.empty())
    throw InputError(
        "StudyOptions.families, StudyOptions.userMeshes: no mesh to study (give a family or a mesh "
        "file)");
  const bool delaunay = std::find(o.families.begin(), o.families.end(),
                                  modeling::MeshFamily::Delaunay) != o.families.end();
  if (delaunay && o.seeds.empty())
    throw InputError("StudyOptions.seeds: the delaunay family needs a seed");
  if (o.baseN < 4) {
    throw InputError("StudyOptions.baseN " + std::to_string(o.baseN) +
                     ": at least 4 cells per side (rings 0 and 1 are fixed; the interior must "
                     "keep free vertices)");
  }
  if (o.levels < 1 || o.levels > 8)
    throw InputError("StudyOptions.levels " + std::to_string(o.levels) + ": expected 1 to 8");
  if (o.amplitudes < 0 || o.amplitudes == 1 || o.amplitudes > 12) {
    throw InputError(
        "StudyOptions.amplitudes " + std::to_string(o.amplitudes) +
        ": expected 2 to 12 (an order needs two amplitudes), or 0 for no nonlinear C2");
  }
  if (o.threads < 1)
    throw InputError("StudyOptions.threads " + std::to_string(o.threads) + ": at least 1");
  if (o.quadratics.empty()) throw InputError("StudyOptions.quadratics: no quadratic to reproduce");
  for (const Quadratic& q : o.quadratics) {
    if (!std::isfinite(q.a) || !std::isfinite(q.b) || !std::isfinite(q.c) ||
        (q.a == 0.0 && q.b == 0.0 && q.c == 0.0)) {
      throw InputError("StudyOptions.quadratics: " + q.surface().spec() +
                       " has nothing to reproduce (zero or not finite)");
    }
  }
  if (!o.solution.empty()) {
    const PolynomialSurface u = PolynomialSurface::parse(o.solution);
    if (isZero(u))
      throw InputError("StudyOptions.solution " + o.solution +
                       ": the zero solution has nothing to converge to");
    if (relativeBilaplacian(u) > 1e-12) {
      throw InputError("StudyOptions.solution " + o.solution +
                       ": is not biharmonic (Δ²u ≠ 0), so it solves no clamped plate problem; "
                       "e.g. polynomial:x^4-3*x^2*y^2 or polynomial:x^3+x*y^2");
    }
  }
  for (const UserMesh& user : o.userMeshes) {
    for (int v = 0; v < user.mesh.vertexCount(); ++v) {
      if (user.mesh.positions(v, 2) != 0.0) {
        throw InputError(user.name + ": vertex " + std::to_string(v) +
                         " has z = " + std::to_string(user.mesh.positions(v, 2)) +
                         ": a study mesh must be flat (z = 0 everywhere); its x and y are used");
      }
    }
  }
}

double studyBytesPerVertex(curvature::Discretization discretization) {
  return curvature::energyEntry(discretization).studyBytesPerVertex;
}

StudyMemoryEstimate estimateStudyMemory(const StudyOptions& options) {
  options.validate();
  struct Case {
    double bytes, vertices;
    std::string name;
  };
  std::vector<Case> cases;
  for (const EnergyVariant& v : options.energies) {
    const double perVertex = studyBytesPerVertex(v.bending.discretization);
    const auto add = [&](double vertices, const std::string& mesh) {
      cases.push_back(
          {kStudyCaseBaseBytes + perVertex * vertices, vertices, v.label + " on " + mesh});
    };
    for (const modeling::MeshFamily family : options.families) {
      const double delaunay = family == modeling::MeshFamily::Delaunay ? 1.25 : 1.0;
      const int seeds =
          family == modeling::MeshFamily::Delaunay ? static_cast<int>(options.seeds.size()) : 1;
      for (int level = 0; level < options.levels; ++level) {
        const double n = std::ldexp(static_cast<double>(options.baseN), level);
        for (int s = 0; s < seeds; ++s) {
          char name[96];
          std::snprintf(name, sizeof name, "%s n=%.0f",
                        std::string(modeling::meshFamilyName(family)).c_str(), n);
          add(delaunay * (n + 1.0) * (n + 1.0), name);
        }
      }
    }
    for (const UserMesh& user : options.userMeshes) add(user.mesh.vertexCount(), user.name);
  }
  std::sort(cases.begin(), cases.end(),
            [](const Case& a, const Case& b) { return a.bytes > b.bytes; });
  StudyMemoryEstimate estimate;
  estimate.concurrent = std::max(1, std::min(options.threads, static_cast<int>(cases.size())));
  for (int k = 0; k < estimate.concurrent; ++k) estimate.peakBytes += cases[k].bytes;
  estimate.largestCaseBytes = cases.front().bytes;
  estimate.largestCaseVertices = cases.front().vertices;
  estimate.largestCase = cases.front().name;
  return estimate;
}

StudyResults runConvergenceStudy(const StudyOptions& options,
                                 const std::function<void(const StudyProgress&)>& progress) {
  options.validate();
  const std::vector<StudyMesh> meshes = studyMeshes(options);
  const int energies = static_cast<int>(options.energies.size());
  const int cases = energies * static_cast<int>(meshes.size());
  const auto caseName = [&](int c) {
    return options.energies[c / meshes.size()].label + " on " +
           meshes[c % meshes.size()].describe();
  };

  std::vector<std::vector<StudyRecord>> caseRecords(cases);
  std::vector<std::exception_ptr> failures(cases);
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex progressMutex;
  int done = 0;
  // Cases are taken in index order, so when one fails every case before it has started: stopping
  // there still reports the first failure in case order.
  const auto worker = [&] {
    for (int c; !failed && (c = next++) < cases;) {
      try {
        const auto step = [&](const std::string& what) {
          if (!progress) return;
          std::lock_guard<std::mutex> lock(progressMutex);
          progress({done, cases, "", caseName(c), what});
        };
        caseRecords[c] =
            runCase(options, c / static_cast<int>(meshes.size()), meshes[c % meshes.size()], step);
      } catch (const InputError& e) {
        failures[c] = std::make_exception_ptr(InputError(caseName(c) + ": " + e.what()));
        failed = true;
      } catch (const NumericalError& e) {
        failures[c] = std::make_exception_ptr(NumericalError(caseName(c) + ": " + e.what()));
        failed = true;
      } catch (...) {
        failures[c] = std::current_exception();
        failed = true;
      }
      std::lock_guard<std::mutex> lock(progressMutex);
      ++done;
      if (progress) progress({done, cases, caseName(c), "", ""});
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min(options.threads, cases); ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);

  StudyResults results;
  for (std::vector<StudyRecord>& records : caseRecords)
    for (StudyRecord& r : records) results.records.push_back(std::move(r));
  fitRefinements(results);
  return results;
}

// ---------------------------------------------------------------------------------------------

StudySummary summarizeStudy(const StudyOptions& options, const StudyResults& results) {
  StudySummary summary;
  for (const EnergyVariant& v : options.energies) summary.energies.push_back(v.label);
  for (const modeling::MeshFamily f : options.families)
    summary.families.emplace_back(modeling::meshFamilyName(f));
  for (const UserMesh& user : options.userMeshes) summary.families.push_back(user.name);
  const auto column = [&](const std::string& family) {
    return static_cast<size_t>(std::find(summary.families.begin(), summary.families.end(), family) -
                               summary.families.begin());
  };

  summary.cells.assign(summary.energies.size(), std::vector<SummaryCell>(summary.families.size()));
  for (const StudyRecord& r : results.records) {
    SummaryCell& cell = summary.cells[r.energy][column(r.family)];
    if (r.kind == RecordKind::Quadratic && r.level == 0) {
      if (r.c1Error) cell.worstC1 = std::max(cell.worstC1.value_or(0.0), *r.c1Error);
      cell.worstC2 = std::max(cell.worstC2, r.c2Error);
    } else if (r.kind == RecordKind::NonlinearC2) {
      if (r.nonlinear.order) {
        cell.nonlinearOrder =
            std::min(cell.nonlinearOrder.value_or(*r.nonlinear.order), *r.nonlinear.order);
      }
      cell.nonlinearConverged = cell.nonlinearConverged && r.nonlinear.converged;
    }
  }
  for (size_t e = 0; e < summary.energies.size(); ++e) {
    for (SummaryCell& cell : summary.cells[e]) {
      if (cell.worstC1) cell.c1 = classifyReproduction(*cell.worstC1);
      cell.c2 = classifyReproduction(cell.worstC2);
    }
  }
  // Refinement over seeds: the smallest order; DoesNotConverge if any series stalls, then
  // Converges if any converges, Exact if all are exact.
  const auto combine = [](Refinement a, Refinement b) {
    for (Refinement r : {Refinement::DoesNotConverge, Refinement::Converges, Refinement::Exact})
      if (a == r || b == r) return r;
    return Refinement::Unmeasured;
  };
  const auto smaller = [](std::optional<double> a, std::optional<double> b) {
    if (!a) return b;
    if (!b) return a;
    return std::optional<double>(std::min(*a, *b));
  };
  for (const RefinementFit& fit : results.refinements) {
    SummaryCell& cell = summary.cells[fit.energy][column(fit.family)];
    cell.refinement = combine(cell.refinement, fit.verdict);
    cell.energyRefinement = combine(cell.energyRefinement, fit.energyVerdict);
    cell.refinementOrder = smaller(cell.refinementOrder, fit.order);
    cell.energyOrder = smaller(cell.energyOrder, fit.energyOrder);
    cell.finestError = std::max(cell.finestError.value_or(0.0), fit.solutionErrors.back());
    cell.finestEnergyError =
        std::max(cell.finestEnergyError.value_or(0.0), fit.energyErrors.back());
  }
  return summary;
}

}  // namespace flexure::optimize
