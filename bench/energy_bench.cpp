// Throughput of the five bending energies of docs/energies.md on a 4-8 patch with about one
// million elements each, and a floor to compare them with.
//
// Per energy, in this order:
//   BM_Setup/<energy>           the one-time cost a solve pays before its first evaluation:
//                               makeBendingEnergy (rest data per element; counter term_ms) plus
//                               the assembly of the ceres::Problem (problem_ms). The mesh, its
//                               stencils and rest state are shared by all energies and not counted.
//   BM_Energy/<energy>          E alone: EnergyTerm::energy(x, ξ), the plain-double kernels
//                               (single-threaded, one element after another).
//   BM_EnergyCeres/<energy>     E alone through Problem::Evaluate (cost only): the same double
//                               kernels behind Ceres' per-call bookkeeping. A diagnostic that
//                               splits the gradient's cost into bookkeeping and autodiff.
//   BM_EnergyGradient/<energy>  E and ∇E through Ceres autodiff: Problem::Evaluate on the problem
//                               BM_Setup assembled (outside the timed loop), with 2 threads and
//                               explicit parameter blocks — what optimize::energyGradient runs per
//                               call, minus the assembly.
// and after them
//   BM_HingeRestTensors         the hinge's face and rest tensors (curvature/hinge_face_tensors.h),
//                               which its term builds on the first read of its rest curvature (a
//                               plastic update's), not in makeBendingEnergy: per iteration a fresh
//                               hinge term (untimed; its build time is the counter term_ms, for
//                               the ratio in the same run) and its first restCurvatures().
//                               Counter geometry_ms: the copy of the rest geometry the term keeps
//                               for that build (HingeRestGeometry::of, part of term_ms).
// and, first, per mesh size one floor:
//   BM_LaplacianFloor/n:<n>     y = L X for the cotangent Laplacian L of the rest mesh and the
//                               #V × 3 current positions X: one sparse matrix-vector product per
//                               coordinate, about the least any gradient of a mesh energy costs.
//
// Second derivatives, on a 100 × 100 patch48 (10 201 vertices, as the simulate bench's scenes):
//   BM_HingeElementHessian/<path> the hinge's exact element Hessians (all elements, one thread):
//                               `jets` the second-order jets of the templated kernel, `closed` the
//                               closed form (curvature/hinge_angle_derivatives.h) element_term.h
//                               uses; the same configuration, so their ratio is the speed-up.
//   BM_CotanElementHessian/<path>, BM_MidedgeElementHessian/<path> the same for cotan and
//                               midedge: `jets` against `separable`, the chain rule through the
//                               elements' sums (curvature/*_element_hessian.cpp) element_term.h
//                               uses.
//   BM_HessianAssembly/<energy> HessianAssembly::evaluate, exact, all unknowns free: E, ∇E and the
//                               assembled sparse ∇²E, as each Newton iteration pays it.
//
// Each mesh size n is chosen so that its energy has about 10^6 elements: n = 578 for hinge
// (3n² − 2n interior edges), n = 708 for triavg, quadfit (≈ 2n² − 4n interior faces) and midedge
// (2n² faces), n = 1001 for cotan ((n − 1)² interior vertices). Counters: `elements/s` (elements
// per second of wall time) and `floor_ratio` (time per evaluation / time of the floor on the same
// mesh; present when that floor ran earlier in the same process, as it does by default).
//
// The configuration: rest flat (patch48 at z = 0), current = rest lifted onto a smooth,
// non-quadratic height field, so every element is bent and no kernel takes a flat short cut;
// midedge ξ = rest ξ̄ = 0. Times are wall-clock (UseRealTime), since Ceres evaluates on a
// worker thread as well; the CPU column is the whole process's CPU time.
#include <benchmark/benchmark.h>
#include <ceres/problem.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "curvature/element_term.h"
#include "curvature/hinge_face_tensors.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/hessian_assembly.h"
#include "optimize/linear/biharmonic.h"

namespace {

using flexure::curvature::BendingOptions;
using flexure::curvature::Discretization;
using flexure::curvature::EnergyTerm;
using flexure::modeling::Positions;
using flexure::modeling::RestState;
using flexure::modeling::Stencils;
using Clock = std::chrono::steady_clock;

constexpr const char* kHeightField = "polynomial:0.3*x^2-0.7*x*y+0.5*y^2+0.2*x^3";
constexpr int kEvaluationThreads = 2;  // as optimize::energyGradient

struct EnergyCase {
  Discretization discretization;
  int n;  // patch48 cells per side
};

const std::vector<EnergyCase>& energyCases() {
  static const std::vector<EnergyCase> cases = {
      {Discretization::Hinge, 578},        {Discretization::TriangleAveraged, 708},
      {Discretization::Cotan, 1001},       {Discretization::Midedge, 708},
      {Discretization::QuadraticFit, 708},
  };
  return cases;
}

// A flat patch48 mesh compiled once per size and shared by every benchmark on it.
struct MeshData {
  Stencils stencils;
  RestState rest;
  Positions current;  // rest lifted onto kHeightField
};

const MeshData& meshData(int n) {
  static std::map<int, std::unique_ptr<MeshData>> cache;
  std::unique_ptr<MeshData>& slot = cache[n];
  if (!slot) {
    const auto start = Clock::now();
    namespace modeling = flexure::modeling;
    const modeling::Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Patch48, n, 1, {}});
    slot = std::make_unique<MeshData>();
    slot->stencils = modeling::compileStencils(mesh);
    slot->rest = modeling::precomputeRestState(slot->stencils, mesh.positions);
    slot->current = mesh.positions;
    modeling::applyHeightField(modeling::PolynomialSurface::parse(kHeightField), slot->current);
    const std::chrono::duration<double> seconds = Clock::now() - start;
    std::fprintf(stderr, "mesh patch48 n=%d: %d vertices, %d faces, %d edges (built in %.1f s)\n",
                 n, slot->stencils.vertexCount(), slot->stencils.faceCount(),
                 slot->stencils.edgeCount(), seconds.count());
  }
  return *slot;
}

BendingOptions optionsFor(Discretization d) {
  BendingOptions options;
  options.discretization = d;
  return options;  // defaults: ν = 0.3 (1 for hinge, cotan), k_B = 1, Voronoi areas, θ
}

// One energy bound to the current state, with its Ceres problem. The problem points into x and
// ξ, so an Evaluation never moves (it lives behind a unique_ptr).
struct Evaluation {
  std::unique_ptr<EnergyTerm> term;
  Positions x;
  Eigen::VectorXd xi;
  ceres::Problem problem;
  ceres::Problem::EvaluateOptions options;
};

// Parameter blocks as optimize's AssembledProblem adds them: one per vertex (3 doubles), then,
// for a term that reads them, one per edge unknown ξ; then the term's residual blocks.
void assemble(Evaluation& e) {
  std::vector<double*>& blocks = e.options.parameter_blocks;
  blocks.clear();
  for (int v = 0; v < e.x.rows(); ++v) {
    blocks.push_back(e.x.data() + 3 * v);
    e.problem.AddParameterBlock(blocks.back(), 3);
  }
  if (e.term->usesEdgeUnknowns()) {
    for (int k = 0; k < e.xi.size(); ++k) {
      blocks.push_back(e.xi.data() + k);
      e.problem.AddParameterBlock(blocks.back(), 1);
    }
  }
  e.term->addResidualBlocks(e.problem, e.x.data(), e.xi.data(),
                            flexure::curvature::Derivatives::All);
  e.options.apply_loss_function = false;
  e.options.num_threads = kEvaluationThreads;
}

// The energy of one case at the current state; `termSeconds` and `problemSeconds` receive the
// wall time of makeBendingEnergy and of the problem assembly.
std::unique_ptr<Evaluation> makeEvaluation(const EnergyCase& c, double& termSeconds,
                                           double& problemSeconds) {
  const MeshData& mesh = meshData(c.n);
  auto e = std::make_unique<Evaluation>();
  e->x = mesh.current;
  // ξ̄ = 0 on the flat rest mesh (docs/energies.md); the current ξ is the rest ξ.
  e->xi = Eigen::VectorXd::Zero(mesh.stencils.edgeCount());
  const auto start = Clock::now();
  e->term =
      flexure::curvature::makeBendingEnergy(mesh.stencils, mesh.rest, optionsFor(c.discretization));
  const auto built = Clock::now();
  assemble(*e);
  termSeconds = std::chrono::duration<double>(built - start).count();
  problemSeconds = std::chrono::duration<double>(Clock::now() - built).count();
  return e;
}

// The Evaluation of one energy, kept while that energy's benchmarks run (Google Benchmark calls
// a benchmark function several times while it settles the iteration count) and replaced for the
// next energy, so that only one million-element problem is alive at a time.
struct EvaluationCache {
  Discretization discretization{};
  std::unique_ptr<Evaluation> evaluation;
};

EvaluationCache& evaluationCache() {
  static EvaluationCache cache;
  return cache;
}

Evaluation& evaluation(const EnergyCase& c) {
  EvaluationCache& cache = evaluationCache();
  if (!cache.evaluation || cache.discretization != c.discretization) {
    cache.evaluation.reset();
    double termSeconds = 0.0, problemSeconds = 0.0;
    cache.evaluation = makeEvaluation(c, termSeconds, problemSeconds);
    cache.discretization = c.discretization;
  }
  return *cache.evaluation;
}

// Seconds per floor evaluation on each mesh size, for the floor_ratio counters.
std::map<int, double>& floorSeconds() {
  static std::map<int, double> seconds;
  return seconds;
}

void setCounters(benchmark::State& state, const EnergyCase& c, int elements, double loopSeconds) {
  state.counters["n"] = c.n;
  state.counters["elements"] = elements;
  state.counters["elements/s"] =
      benchmark::Counter(elements, benchmark::Counter::kIsIterationInvariantRate);
  const auto floor = floorSeconds().find(c.n);
  if (floor != floorSeconds().end() && state.iterations() > 0) {
    state.counters["floor_ratio"] =
        loopSeconds / static_cast<double>(state.iterations()) / floor->second;
  }
}

// BM_Setup: makeBendingEnergy + problem assembly, what a solve pays once before evaluating. The
// Evaluation built last is handed to the cache, so the benchmarks after it reuse it instead of
// building their own.
void setup(benchmark::State& state, EnergyCase c) {
  evaluationCache().evaluation.reset();  // free the previous energy's problem first
  std::unique_ptr<Evaluation> e;
  double termSeconds = 0.0, problemSeconds = 0.0;
  for (auto _ : state) {
    if (e) {
      // Tearing a million-block problem down is not part of the setup.
      state.PauseTiming();
      e.reset();
      state.ResumeTiming();
    }
    double term = 0.0, problem = 0.0;
    e = makeEvaluation(c, term, problem);
    benchmark::DoNotOptimize(e.get());
    termSeconds += term;
    problemSeconds += problem;
  }
  if (!e) return;
  state.counters["n"] = c.n;
  state.counters["elements"] = e->term->elementCount();
  state.counters["elements/s"] =
      benchmark::Counter(e->term->elementCount(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["term_ms"] =
      benchmark::Counter(1e3 * termSeconds, benchmark::Counter::kAvgIterations);
  state.counters["problem_ms"] =
      benchmark::Counter(1e3 * problemSeconds, benchmark::Counter::kAvgIterations);
  evaluationCache().evaluation = std::move(e);
  evaluationCache().discretization = c.discretization;
}

// BM_HingeRestTensors: the hinge term's tensors, built on its first restCurvatures().
void hingeRestTensors(benchmark::State& state) {
  const EnergyCase& c = energyCases().front();  // the hinge's
  const MeshData& mesh = meshData(c.n);
  double termSeconds = 0.0, geometrySeconds = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    auto start = Clock::now();
    const auto geometry = flexure::curvature::HingeRestGeometry::of(mesh.stencils, mesh.rest);
    benchmark::DoNotOptimize(geometry.positions.data());
    geometrySeconds += std::chrono::duration<double>(Clock::now() - start).count();
    start = Clock::now();
    std::unique_ptr<EnergyTerm> term = flexure::curvature::makeBendingEnergy(
        mesh.stencils, mesh.rest, optionsFor(c.discretization));
    termSeconds += std::chrono::duration<double>(Clock::now() - start).count();
    state.ResumeTiming();
    const Eigen::MatrixXd rest = term->restCurvatureState()->restCurvatures();
    benchmark::DoNotOptimize(rest.data());
    state.PauseTiming();
    term.reset();
    state.ResumeTiming();
  }
  state.counters["n"] = c.n;
  state.counters["term_ms"] =
      benchmark::Counter(1e3 * termSeconds, benchmark::Counter::kAvgIterations);
  state.counters["geometry_ms"] =
      benchmark::Counter(1e3 * geometrySeconds, benchmark::Counter::kAvgIterations);
}

// BM_Energy: E from the plain-double element kernels.
void energyOnly(benchmark::State& state, EnergyCase c) {
  const Evaluation& e = evaluation(c);
  const auto start = Clock::now();
  for (auto _ : state) {
    double energy = e.term->energy(e.x, e.xi);
    benchmark::DoNotOptimize(energy);
  }
  const std::chrono::duration<double> loop = Clock::now() - start;
  setCounters(state, c, e.term->elementCount(), loop.count());
}

// BM_EnergyCeres (cost only) and BM_EnergyGradient (cost and gradient): Problem::Evaluate on the
// assembled problem. The cost-only variant runs the same double kernels as BM_Energy behind
// Ceres' per-call bookkeeping, so EnergyCeres − Energy is that bookkeeping and
// EnergyGradient − EnergyCeres the autodiff (Jet) evaluation and gradient accumulation.
void ceresEvaluate(benchmark::State& state, EnergyCase c, bool withGradient) {
  Evaluation& e = evaluation(c);
  // Evaluate's cost is ½ Σ r² = E (docs/energies.md): check once, outside the timing, that the
  // Ceres path computes the same energy as the plain kernels.
  double cost = 0.0;
  std::vector<double> gradient;
  std::vector<double>* gradientOut = withGradient ? &gradient : nullptr;
  if (!e.problem.Evaluate(e.options, &cost, nullptr, gradientOut, nullptr)) {
    state.SkipWithError("Problem::Evaluate failed");
    return;
  }
  const double energy = e.term->energy(e.x, e.xi);
  if (!(std::abs(cost - energy) <= 1e-9 * std::abs(energy))) {
    state.SkipWithError(
        ("Ceres cost " + std::to_string(cost) + " != energy " + std::to_string(energy)).c_str());
    return;
  }
  const auto start = Clock::now();
  for (auto _ : state) {
    e.problem.Evaluate(e.options, &cost, nullptr, gradientOut, nullptr);
    benchmark::DoNotOptimize(cost);
    benchmark::DoNotOptimize(gradient.data());
    benchmark::ClobberMemory();
  }
  const std::chrono::duration<double> loop = Clock::now() - start;
  setCounters(state, c, e.term->elementCount(), loop.count());
}

void laplacianFloor(benchmark::State& state, int n) {
  const MeshData& mesh = meshData(n);
  // The library's cotangent Laplacian (optimize/linear/biharmonic.h), row-major for the product.
  const Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian =
      flexure::optimize::cotanLaplacian(mesh.stencils, mesh.rest);
  const Eigen::MatrixXd x = mesh.current;  // #V × 3, one column per coordinate
  Eigen::MatrixXd y(x.rows(), 3);
  const auto start = Clock::now();
  for (auto _ : state) {
    y.noalias() = laplacian * x;
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  const std::chrono::duration<double> loop = Clock::now() - start;
  if (state.iterations() > 0) floorSeconds()[n] = loop.count() / state.iterations();
  state.counters["n"] = n;
  state.counters["vertices"] = static_cast<double>(x.rows());
  state.counters["nnz"] = static_cast<double>(laplacian.nonZeros());
}

// ---------------------------------------------------------------------------------------------
// Second derivatives on the n = 100 patch.

constexpr int kHessianPatch = 100;

// The energy `d` on the n = 100 patch, at its current (lifted) state.
struct HessianCase {
  std::unique_ptr<EnergyTerm> term;
  Eigen::VectorXd xi;
};
HessianCase hessianCase(Discretization d) {
  const MeshData& mesh = meshData(kHessianPatch);
  return {flexure::curvature::makeBendingEnergy(mesh.stencils, mesh.rest, optionsFor(d)),
          Eigen::VectorXd::Zero(mesh.stencils.edgeCount())};
}

// Sums what it receives, so no element's work can be skipped.
class SummingSink : public flexure::curvature::ElementHessianSink {
 public:
  void add(const flexure::curvature::ElementHessian& element) override {
    sum += element.energy + element.hessian(0, 0);
  }
  double sum = 0.0;
};

void hingeElementHessian(benchmark::State& state, bool closedForm) {
  using flexure::curvature::HingeBendingResidual;
  const HessianCase c = hessianCase(Discretization::Hinge);
  const Positions& x = meshData(kHessianPatch).current;
  const auto& term =
      dynamic_cast<const flexure::curvature::ElementTerm<HingeBendingResidual>&>(*c.term);
  const std::vector<int> sizes = {3, 3, 3, 3};
  std::vector<long> firstUnknown(4);
  std::vector<const double*> blocks(4);
  flexure::curvature::ElementHessian out;
  SummingSink sink;
  for (auto _ : state) {
    for (const HingeBendingResidual& element : term.elements()) {
      for (int k = 0; k < 4; ++k) {
        blocks[k] = x.data() + 3 * element.vertices[k];
        firstUnknown[k] = 3L * element.vertices[k];
      }
      const bool ok =
          closedForm ? flexure::curvature::elementHessian(element, blocks, sizes, firstUnknown,
                                                          flexure::curvature::Derivatives::All, out)
                     : flexure::curvature::elementHessian<HingeBendingResidual>(
                           element, blocks, sizes, firstUnknown,
                           flexure::curvature::Derivatives::All, out);
      if (!ok) state.SkipWithError("degenerate hinge");
      sink.add(out);
    }
    benchmark::DoNotOptimize(sink.sum);
  }
  state.counters["elements"] = term.elementCount();
  state.counters["elements/s"] =
      benchmark::Counter(term.elementCount(), benchmark::Counter::kIsIterationInvariantRate);
}

// BM_CotanElementHessian and BM_MidedgeElementHessian: every element's exact Hessian (one thread),
// `jets` the dense second-order jets of the templated kernel, `separable` the chain rule through
// the element's sums (curvature/cotan_element_hessian.cpp, midedge_element_hessian.cpp) that
// element_term.h uses.
template <class Residual>
void separableElementHessian(benchmark::State& state, Discretization d, bool separable) {
  const HessianCase c = hessianCase(d);
  const Positions& x = meshData(kHessianPatch).current;
  const auto& term = dynamic_cast<const flexure::curvature::ElementTerm<Residual>&>(*c.term);
  const long xiColumn = x.size();
  std::vector<const double*> blocks;
  std::vector<long> firstUnknown;
  std::vector<int> sizes;
  flexure::curvature::ElementHessian out;
  SummingSink sink;
  for (auto _ : state) {
    for (const Residual& element : term.elements()) {
      flexure::curvature::parameterBlocks(element, x.data(), c.xi.data(), blocks);
      flexure::curvature::parameterBlocks(element, 0L, xiColumn, firstUnknown);
      sizes.clear();
      for (long first : firstUnknown) sizes.push_back(first >= xiColumn ? 1 : 3);
      const bool ok =
          separable ? flexure::curvature::elementHessian(element, blocks, sizes, firstUnknown,
                                                         flexure::curvature::Derivatives::All, out)
                    : flexure::curvature::elementHessian<Residual>(
                          element, blocks, sizes, firstUnknown,
                          flexure::curvature::Derivatives::All, out);
      if (!ok) state.SkipWithError("degenerate element");
      sink.add(out);
    }
    benchmark::DoNotOptimize(sink.sum);
  }
  state.counters["elements"] = term.elementCount();
  state.counters["elements/s"] =
      benchmark::Counter(term.elementCount(), benchmark::Counter::kIsIterationInvariantRate);
}

void hessianAssembly(benchmark::State& state, Discretization d) {
  const HessianCase c = hessianCase(d);
  const Positions& x = meshData(kHessianPatch).current;
  const long unknowns = x.size() + (c.term->usesEdgeUnknowns() ? c.xi.size() : 0);
  const flexure::optimize::HessianAssembly assembly(
      {c.term.get()}, std::vector<bool>(unknowns, true), static_cast<int>(x.rows()),
      flexure::curvature::Derivatives::All);
  for (auto _ : state) {
    const flexure::optimize::HessianEvaluation h =
        assembly.evaluate(x, c.xi, flexure::optimize::HessianProjection::Exact);
    benchmark::DoNotOptimize(h.values.data());
    benchmark::ClobberMemory();
  }
  state.counters["elements"] = c.term->elementCount();
  state.counters["nnz"] = static_cast<double>(assembly.rowIndex().size());
}

void registerBenchmarks() {
  // Wall time (Ceres evaluates on worker threads); the CPU column is the whole process's CPU
  // time, so CPU / Time shows how many cores were busy.
  const auto configure = [](benchmark::internal::Benchmark* b) {
    return b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
  };
  // Floors first: the energies' floor_ratio counters read them.
  std::vector<int> sizes;
  for (const EnergyCase& c : energyCases()) {
    if (std::find(sizes.begin(), sizes.end(), c.n) == sizes.end()) sizes.push_back(c.n);
  }
  for (int n : sizes) {
    const std::string name = "BM_LaplacianFloor/n:" + std::to_string(n);
    configure(benchmark::RegisterBenchmark(name.c_str(), laplacianFloor, n))->MinTime(0.5);
  }
  for (const EnergyCase& c : energyCases()) {
    const std::string name(flexure::curvature::discretizationName(c.discretization));
    // One setup per energy: it takes seconds, and its result is reused below.
    configure(benchmark::RegisterBenchmark(("BM_Setup/" + name).c_str(), setup, c))->Iterations(1);
    configure(benchmark::RegisterBenchmark(("BM_Energy/" + name).c_str(), energyOnly, c))
        ->MinTime(1.0);
    configure(
        benchmark::RegisterBenchmark(("BM_EnergyCeres/" + name).c_str(), ceresEvaluate, c, false))
        ->MinTime(1.0);
    configure(
        benchmark::RegisterBenchmark(("BM_EnergyGradient/" + name).c_str(), ceresEvaluate, c, true))
        ->MinTime(1.0);
  }
  configure(benchmark::RegisterBenchmark("BM_HingeRestTensors", hingeRestTensors))->Iterations(3);
  for (bool closedForm : {false, true}) {
    const std::string name =
        std::string("BM_HingeElementHessian/") + (closedForm ? "closed" : "jets");
    configure(benchmark::RegisterBenchmark(name.c_str(), hingeElementHessian, closedForm))
        ->MinTime(1.0);
  }
  for (bool separable : {false, true}) {
    const std::string path = separable ? "separable" : "jets";
    configure(benchmark::RegisterBenchmark(
                  ("BM_CotanElementHessian/" + path).c_str(),
                  separableElementHessian<flexure::curvature::CotanMeanCurvatureResidual>,
                  Discretization::Cotan, separable))
        ->MinTime(1.0);
    configure(
        benchmark::RegisterBenchmark(("BM_MidedgeElementHessian/" + path).c_str(),
                                     separableElementHessian<flexure::curvature::MidedgeResidual>,
                                     Discretization::Midedge, separable))
        ->MinTime(1.0);
  }
  for (const EnergyCase& c : energyCases()) {
    const std::string name(flexure::curvature::discretizationName(c.discretization));
    configure(benchmark::RegisterBenchmark(("BM_HessianAssembly/" + name).c_str(), hessianAssembly,
                                           c.discretization))
        ->MinTime(1.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  registerBenchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
