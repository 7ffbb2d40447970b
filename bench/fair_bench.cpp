// Fairing speed on a real mesh: flexure's nonlinear fairing against CGAL's linear fair (and
// flexure's own linear fair, its default start) on one large region.
//
// The input: a mesh (default: CGAL's bunny00, 37 706 vertices, extracted by scripts/bench fair),
// refined `--refine` times by midpoint subdivision (each triangle into four coplanar ones: a
// faceted surface with 4× the vertices, the kind of mesh fairing smooths), and the region: the
// `--region-vertices` vertices nearest (in space) to vertex `--seed-vertex`. Each case runs in
// turn in this process on the same FairingPatch; peak memory is the process's resident high-water
// mark over the case (reset before it through /proc/self/clear_refs). Wall-clock seconds:
//   cgal_fair     optimize::fairCgal (CGAL's PMP::fair, continuity 1, on the patch; includes
//                 building CGAL's Surface_mesh);
//   linear_fair   optimize::fairBiharmonic (the same system with CHOLMOD, x, y, z);
//   <energy>/<solver>[/current]  optimize::fairNonlinear with the metric's default options
//                 (defaultFairingOptions: mips membrane, w = 1 on the input's metric, 0.1 faded to
//                 0.01 on the current one, quasi-Newton chord steps there; start = the better
//                 of input and linear fair), 2 threads, on each solver of --solvers (newton:
//                 flexure's Newton, the default; ceres: Ceres' LM) and metric of --metrics
//                 (input, the default, and current), with its iterations, factorizations and
//                 linear-solver seconds. --membrane-fade-stages N replaces the metric's fade
//                 (0: the solve at the first w alone); --progress prints each iteration.
//                 bending_energy_after: all five energies of the result (flat rest, the input's
//                 metric), so solvers compare in each.
// Every case carries checkFairing's verdict (checks_passed, failed_check; for flexure's the
// gradient check too), beside the solver's own `converged`. ratio_to_cgal_fair = seconds /
// cgal_fair seconds. The bending energy of the default energy (midedge) and the smallest angle
// after each case are reported too.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "modeling/fairing_region.h"
#include "modeling/mesh_io.h"
#include "modeling/stencils.h"
#include "optimize/fairing/fairing.h"
#include "optimize/linear/heap_reuse.h"

namespace {

namespace modeling = flexure::modeling;
namespace optimize = flexure::optimize;
namespace curvature = flexure::curvature;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

// Each triangle into four: the edge midpoints become vertices (shared between the two faces of an
// edge), positions unchanged.
modeling::Mesh midpointSubdivision(const modeling::Mesh& mesh) {
  std::map<std::pair<int, int>, int> midpoint;
  std::vector<Eigen::RowVector3d> added;
  const auto middle = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    const auto [it, inserted] =
        midpoint.emplace(key, mesh.vertexCount() + static_cast<int>(added.size()));
    if (inserted) added.push_back(0.5 * (mesh.positions.row(a) + mesh.positions.row(b)));
    return it->second;
  };
  modeling::Mesh out;
  out.triangles.resize(4 * mesh.faceCount(), 3);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    const int a = mesh.triangles(f, 0), b = mesh.triangles(f, 1), c = mesh.triangles(f, 2);
    const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
    out.triangles.row(4 * f) << a, ab, ca;
    out.triangles.row(4 * f + 1) << ab, b, bc;
    out.triangles.row(4 * f + 2) << ca, bc, c;
    out.triangles.row(4 * f + 3) << ab, bc, ca;
  }
  out.positions.resize(mesh.vertexCount() + static_cast<Eigen::Index>(added.size()), 3);
  out.positions.topRows(mesh.vertexCount()) = mesh.positions;
  for (std::size_t i = 0; i < added.size(); ++i)
    out.positions.row(mesh.vertexCount() + static_cast<Eigen::Index>(i)) = added[i];
  return out;
}

// The `count` vertices nearest to vertex `seed`.
std::vector<bool> nearestVertices(const modeling::Mesh& mesh, int seed, int count) {
  std::vector<double> distance(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v)
    distance[v] = (mesh.positions.row(v) - mesh.positions.row(seed)).norm();
  std::vector<int> order(mesh.vertexCount());
  std::iota(order.begin(), order.end(), 0);
  std::nth_element(order.begin(), order.begin() + count, order.end(),
                   [&](int a, int b) { return distance[a] < distance[b]; });
  std::vector<bool> region(mesh.vertexCount(), false);
  for (int i = 0; i < count; ++i) region[order[i]] = true;
  return region;
}

void resetPeakMemory() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

double peakMemoryMb() {  // VmHWM of /proc/self/status, in MB
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kb = 0.0;
      status >> kb;
      return kb / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0.0;
}

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The bench's options, as the flags give them.
struct BenchOptions {
  std::string meshPath;
  int refine = 1, regionVertices = 50000, seedVertex = 0;
  std::vector<std::string> energies = {"midedge"}, solvers = {"newton", "ceres"};
  std::vector<std::string> metrics = {"input"};
  bool progress = false;
  std::optional<int> fadeStages;  // the metric's default when not given
};

// The command line into `o`; the exit code when it asks for help or is refused.
std::optional<int> parseArguments(int argc, char** argv, BenchOptions& o) {
  CLI::App app("flexure fairing benchmark: nonlinear fairing vs CGAL's fair on a large region");
  app.add_option("--mesh", o.meshPath, "Input mesh")->required();
  app.add_option("--refine", o.refine, "Midpoint subdivisions")->capture_default_str();
  app.add_option("--region-vertices", o.regionVertices, "Region size")->capture_default_str();
  app.add_option("--seed-vertex", o.seedVertex, "The region is nearest this vertex")
      ->capture_default_str();
  app.add_option("--energies", o.energies, "flexure energies to run")->delimiter(',');
  app.add_option("--solvers", o.solvers, "newton, ceres")->delimiter(',');
  app.add_option("--metrics", o.metrics,
                 "input, current, current-exact: whose metric the bending energy reads")
      ->delimiter(',');
  app.add_flag("--progress", o.progress, "One line per solver iteration on stderr");
  app.add_option("--membrane-fade-stages", o.fadeStages,
                 "Stages of the membrane's fade (default: the metric's)")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (const std::string& metric : o.metrics) optimize::parseFairingMetric(metric);
  } catch (const std::exception& e) {
    std::cerr << "fair_bench: --metrics: " << e.what() << "\n";
    return 2;
  }
  return std::nullopt;
}

// The fairing patch of the region of `regionVertices` vertices nearest `seedVertex`, described on
// stderr.
modeling::FairingPatch regionPatch(const modeling::Mesh& mesh, const BenchOptions& o) {
  const modeling::Stencils stencils = modeling::compileStencils(mesh);
  const std::vector<bool> region = nearestVertices(mesh, o.seedVertex, o.regionVertices);
  modeling::requireFairableRegion(stencils, region, "nearest vertices");
  modeling::FairingPatch patch = modeling::extractFairingPatch(mesh, stencils, region);
  std::cerr << "fair_bench: " << mesh.vertexCount() << " vertices, region " << o.regionVertices
            << ", patch " << patch.mesh.vertexCount() << " vertices / " << patch.mesh.faceCount()
            << " faces\n";
  return patch;
}

// The cases measured on one patch: each result's seconds, peak memory, bending energies after
// (by every energy, midedge's apart), smallest angle and checkFairing's verdict.
struct CaseTable {
  const modeling::FairingPatch& patch;
  curvature::BendingOptions material;
  json cases = json::array();
  double cgalSeconds = 0.0;  // the ratio's denominator, once CGAL's fair has run

  explicit CaseTable(const modeling::FairingPatch& fairingPatch) : patch(fairingPatch) {
    material.discretization = curvature::Discretization::Midedge;
  }

  // Each result with checkFairing's verdict (`solve`: flexure's, for the gradient check too): a
  // solver that stopped is not a fairing `flexure fair` would write unless it passes them.
  void record(const std::string& name, double seconds, const modeling::Positions& result,
              json extra, const optimize::FairingResult* solve = nullptr) {
    const double memory = peakMemoryMb();
    const optimize::FairingMeasures m = optimize::measureFairing(patch, result, material);
    const optimize::FairingChecks checks = optimize::checkFairing(patch, result, solve);
    extra["checks_passed"] = checks.passed();
    if (!checks.passed()) extra["failed_check"] = checks.failure();
    double midedge = 0.0;
    json after = json::object();
    for (const auto& e : m.bending) {
      if (e.energy == "midedge") midedge = e.value;
      after[e.energy] = e.value;
    }
    json c = {{"case", name},
              {"seconds", seconds},
              {"peak_memory_mb", memory},
              {"midedge_energy_after", midedge},
              {"bending_energy_after", after},
              {"min_angle_degrees", m.quality.minAngleDegrees}};
    c.update(extra);
    if (cgalSeconds > 0.0) c["ratio_to_cgal_fair"] = seconds / cgalSeconds;
    std::cerr << "  " << name << ": " << seconds << " s, " << memory << " MB, E_midedge " << midedge
              << (checks.passed() ? "" : "  FAILS CHECKS: " + checks.failure()) << "\n";
    cases.push_back(c);
  }
};

// CGAL's fair and flexure's linear (biharmonic) fair.
void runBaselines(CaseTable& table) {
  resetPeakMemory();
  auto start = Clock::now();
  const modeling::Positions cgal = optimize::fairCgal(table.patch);
  table.cgalSeconds = secondsSince(start);
  table.record("cgal_fair", table.cgalSeconds, cgal, json::object());

  resetPeakMemory();
  start = Clock::now();
  const modeling::Positions linear = optimize::fairBiharmonic(table.patch);
  table.record("linear_fair", secondsSince(start), linear, json::object());
}

// flexure's nonlinear fairing with each energy, solver and metric.
void runNonlinear(const BenchOptions& o, CaseTable& table) {
  for (const std::string& energy : o.energies) {
    for (const std::string& solver : o.solvers) {
      for (const std::string& metric : o.metrics) {
        optimize::FairingOptions options =
            optimize::defaultFairingOptions(optimize::parseFairingMetric(metric));
        options.bending.discretization = curvature::parseDiscretization(energy);
        options.solver.solver =
            solver == "ceres" ? optimize::Solver::Ceres : optimize::Solver::Newton;
        options.solver.progress = o.progress;
        options.membraneFadeStages = o.fadeStages.value_or(options.membraneFadeStages);
        resetPeakMemory();
        const auto start = Clock::now();
        const optimize::FairingResult r = optimize::fairNonlinear(table.patch, options);
        table.record(energy + "/" + solver + (metric == "input" ? "" : "/" + metric),
                     secondsSince(start), r.positions,
                     {{"solver", r.report.solver},
                      {"iterations", r.report.iterations},
                      {"factorizations", r.report.factorizations},
                      {"converged", r.report.converged},
                      {"start", r.start == optimize::FairingStart::Input ? "input" : "biharmonic"},
                      {"linear_solver_seconds", r.report.linearSolverSeconds},
                      {"evaluation_seconds", r.report.evaluationSeconds},
                      {"ordering_seconds", r.report.orderingSeconds},
                      {"solver_seconds", r.report.totalSeconds},
                      {"metric", metric},
                      {"membrane_weight", r.membraneWeight}},
                     &r);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  flexure::optimize::reuseFreedMemory();  // as the flexure executable does
  BenchOptions o;
  if (const std::optional<int> exitCode = parseArguments(argc, argv, o)) return *exitCode;

  modeling::Mesh mesh = modeling::readMesh(o.meshPath);
  for (int k = 0; k < o.refine; ++k) mesh = midpointSubdivision(mesh);
  if (o.regionVertices >= mesh.vertexCount()) {
    std::cerr << "fair_bench: --region-vertices must be below the mesh's " << mesh.vertexCount()
              << " vertices\n";
    return 2;
  }
  const modeling::FairingPatch patch = regionPatch(mesh, o);
  CaseTable table(patch);
  runBaselines(table);
  runNonlinear(o, table);
  const json out = {{"mesh", o.meshPath},
                    {"refine", o.refine},
                    {"vertices", mesh.vertexCount()},
                    {"region_vertices", o.regionVertices},
                    {"patch_vertices", patch.mesh.vertexCount()},
                    {"patch_faces", patch.mesh.faceCount()},
                    {"cases", table.cases}};
  std::cout << out.dump(2) << '\n';
  return 0;
}
