// A convergence study's runs: its options checked, every case (an energy on a mesh) run on a pool
// of threads — C1 and C2 for each quadratic, nonlinear C2 on the coarsest level, the refinement
// solve — and the refinement series fitted.
#include "optimize/studies/convergence_study.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "curvature/bending_spec.h"
#include "modeling/errors.h"
#include "optimize/studies/plate_polynomials.h"
#include "optimize/studies/reproduction_conditions.h"
#include "optimize/studies/study_meshes.h"

namespace flexure::optimize {
using modeling::PolynomialSurface;

namespace {

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

}  // namespace flexure::optimize
