// Solve speed of flexure's static minimizers against two linear baselines, on the slides' test
// problem: the flat patch48 (4-8) mesh with n × n cells, the two outer vertex rings lifted onto a
// quadratic z = p(x, y), the interior free in height mode and starting at rest.
//
// Per mesh size n, every case runs in its own forked child process (so that the parent's
// ru_maxrss is not mixed in and wait4() reports that case's peak memory); the child builds the
// mesh, its stencils and rest state itself (mesh_seconds, counted in no ratio: every method
// needs them), runs the case, and sends its JSON record up a pipe. Wall-clock times:
//   floor      the cotangent bi-Laplacian L M⁻¹ L on the free vertices, z only:
//              seconds.total = optimize::solveBiharmonic (assembly + CHOLMOD factor + solve), and
//              the same steps re-run here with the library's cotanLaplacian and the same CHOLMOD
//              class so they can be timed apart: assembly, factor, solve. The floor is
//              "one CHOLMOD factorization + solve": ratio_to_floor divides by factor + solve.
//   cgal_fair  modeling::cgalFair (CGAL's PMP::fair, continuity 1, default sparse LU) on the
//              lifted mesh with the free set = the unfixed vertices; includes building CGAL's
//              Surface_mesh, which is part of what a user of fair pays.
//   <energy>   newton (flexure's Newton on the exact Hessian, the default solver), ceres
//              (Ceres' LM, the reference) and linearized: what `flexure minimize` pays after
//              reading the mesh.
//              seconds.setup = optimize::buildProblem on the compiled mesh (makeBendingEnergy,
//              midedge's ξ̄, surfaceBoundary);
//              seconds.minimize = optimize::minimize (default MinimizeOptions, 2 threads, no
//              progress) with its report's split: evaluation (residuals + Jacobians; linearized:
//              the rest Jacobian), linear_solver, ordering (the METIS order handed to Ceres), and
//              other (= minimize − those: problem assembly, Ceres' preprocessing, step
//              bookkeeping); seconds.total = setup + minimize. A nonlinear minimize (default
//              Start::Linearized) includes the linearized predictor solve.
//              ratio_to_floor = total / floor factor+solve; ratio_to_cgal_fair = total / cgal_fair.
//              factorizations: numerical sparse Cholesky factorizations, the predictor's
//              included. newton's ratio_to_ceres = its total / ceres' total.
//              Mode vibration (issue #16): the 12 smallest vibration modes of the clamped plate
//              (optimize/modes/vibration_modes.h: midedge clamps its normals, the others rings 0
//              and 1) — assembly of K, one CHOLMOD factor of K − σM, shift-invert Lanczos —;
//              seconds.total = setup + modes, split into assembly, factor and eigensolve.
//              With --baselines, mode ceres_amd measures the nested-dissection order in the
//              same run: the Ceres solve on Ceres' AMD order, with ratio_to_ceres = its
//              total / the default Ceres total.
// `--repeat R` runs every case R times (each in a fresh child) and keeps the fastest record (by
// the time its ratios use), with peak_memory_mb the largest over the repeats.
// The summary checks the targets at the largest n run, met or not.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "modeling/cgal_fair.h"
#include "modeling/generators.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/boundary_conditions.h"
#include "optimize/linear/biharmonic.h"
#include "optimize/linear/heap_reuse.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace {

namespace curvature = flexure::curvature;
namespace modeling = flexure::modeling;
namespace optimize = flexure::optimize;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr int kFixedRings = 2;  // clamped: positions and normals held
constexpr int kThreads = 2;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Settings {
  std::vector<int> sizes = {64, 128, 256, 512};
  std::vector<std::string> energies = {"hinge", "triavg", "cotan", "midedge", "quadfit"};
  std::string boundary = "quadratic:0.3,-0.7,0.5";
  int repeat = 1;
  int timeout = 3600;  // seconds per case (child); 0: none
  bool baselines = false;
  bool newton = true, ceres = true, linearized = true, vibration = false;  // --modes
};

// One case: "floor", "cgal_fair", or an energy with mode "newton" | "ceres" | "linearized" |
// "ceres_amd" | "vibration".
struct Case {
  std::string kind;
  std::string energy, mode;
};

json runFloor(const modeling::Stencils& stencils, const modeling::RestState& rest,
              const std::vector<bool>& fixed, const modeling::PolynomialSurface& surface) {
  const optimize::Positions lifted = optimize::boundaryFromSurface(rest.positions, fixed, surface);
  const Eigen::VectorXd z = lifted.col(2);

  // The library's floor in one figure.
  auto start = Clock::now();
  const Eigen::VectorXd solved = optimize::solveBiharmonic(stencils, rest, fixed, z);
  const double total = secondsSince(start);

  // The same steps as solveBiharmonic, timed apart.
  start = Clock::now();
  const optimize::BiharmonicSystem floor = optimize::assembleBiharmonic(stencils, rest, fixed, z);
  const Eigen::SparseMatrix<double>& system = floor.matrix;
  const Eigen::VectorXd& rhs = floor.rhs;
  const std::vector<int>& index = floor.freeIndex;
  const int vertexCount = stencils.vertexCount();
  const int freeCount = static_cast<int>(rhs.size());
  const double assembly = secondsSince(start);
  start = Clock::now();
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky(system);
  const double factor = secondsSince(start);
  start = Clock::now();
  const Eigen::VectorXd freeZ = cholesky.solve(rhs);
  const double solve = secondsSince(start);
  if (cholesky.info() != Eigen::Success) throw std::runtime_error("floor: CHOLMOD failed");

  // The split must reproduce the library's answer, else it timed something else.
  double difference = 0.0;
  for (int v = 0; v < vertexCount; ++v)
    if (index[v] >= 0) difference = std::max(difference, std::abs(freeZ[index[v]] - solved[v]));
  optimize::Positions result = lifted;
  result.col(2) = solved;
  return {
      {"seconds",
       {{"total", total},
        {"assembly", assembly},
        {"factor", factor},
        {"solve", solve},
        {"factor_solve", factor + solve}}},
      {"split_max_difference", difference},
      {"unknowns", freeCount},
      {"nonzeros", system.nonZeros()},
      {"reproduction_error", optimize::reproductionError(rest.positions, result, fixed, surface)}};
}

json runCgalFair(const modeling::Mesh& mesh, const std::vector<bool>& fixed,
                 const modeling::PolynomialSurface& surface) {
  modeling::Mesh lifted = mesh;
  lifted.positions = optimize::boundaryFromSurface(mesh.positions, fixed, surface);
  std::vector<bool> freeVertex(fixed.size());
  for (size_t v = 0; v < fixed.size(); ++v) freeVertex[v] = !fixed[v];
  const auto start = Clock::now();
  const optimize::Positions result = modeling::cgalFair(lifted, freeVertex);
  const double total = secondsSince(start);
  return {
      {"seconds", {{"total", total}}},
      {"reproduction_error", optimize::reproductionError(mesh.positions, result, fixed, surface)}};
}

json runEnergy(modeling::Stencils stencils, modeling::RestState rest,
               const std::vector<bool>& fixed, const modeling::PolynomialSurface& surface,
               const Case& c) {
  optimize::MinimizeOptions options;
  options.linearized = c.mode == "linearized";
  options.solver = c.mode == "newton" ? optimize::Solver::Newton : optimize::Solver::Ceres;
  options.nestedDissection = c.mode != "ceres_amd";
  options.threads = kThreads;
  options.progress = false;

  optimize::ProblemOptions problemOptions;
  problemOptions.bending.discretization = curvature::parseDiscretization(c.energy);
  problemOptions.fixedVertex = fixed;
  problemOptions.boundarySurface = surface;
  problemOptions.boundaryNormals = optimize::BoundaryNormals::Clamped;
  problemOptions.linearizedClamp = options.linearized;

  const auto start = Clock::now();
  const optimize::Problem problem =
      optimize::buildProblem(std::move(stencils), std::move(rest), problemOptions);
  const double setup = secondsSince(start);
  const optimize::MinimizeResult result = optimize::minimize(problem, options);
  const optimize::MinimizeReport& r = result.report;
  const double minimizeSeconds = secondsSince(start) - setup;
  return {{"seconds",
           {{"total", setup + minimizeSeconds},
            {"setup", setup},
            {"minimize", minimizeSeconds},
            {"evaluation", r.evaluationSeconds},
            {"linear_solver", r.linearSolverSeconds},
            {"ordering", r.orderingSeconds},
            {"other",
             minimizeSeconds - r.evaluationSeconds - r.linearSolverSeconds - r.orderingSeconds}}},
          {"iterations", r.iterations},
          {"factorizations", r.factorizations},
          {"converged", r.converged},
          {"termination", r.termination},
          {"initial_energy", r.initialEnergy},
          {"final_energy", r.finalEnergy},
          {"gradient_norm", r.gradientNorm},
          {"unknowns", r.unknowns},
          {"residuals", r.residuals},
          {"reproduction_error",
           optimize::reproductionError(problem.rest.positions, result.positions, fixed, surface)}};
}

constexpr int kVibrationModes = 12;

// The problem holds nothing: the support is ModesOptions'.
json runVibration(modeling::Stencils stencils, modeling::RestState rest, const Case& c) {
  optimize::ProblemOptions problemOptions;
  problemOptions.bending.discretization = curvature::parseDiscretization(c.energy);
  problemOptions.fixedRings = 0;
  problemOptions.boundaryNormals = optimize::BoundaryNormals::Free;
  const auto start = Clock::now();
  const optimize::Problem problem =
      optimize::buildProblem(std::move(stencils), std::move(rest), problemOptions);
  const double setup = secondsSince(start);
  optimize::ModesOptions options;
  options.count = kVibrationModes;
  options.support = optimize::Support::Clamped;
  options.clamp = problem.usesEdgeUnknowns() ? optimize::Clamp::Normals : optimize::Clamp::Rings;
  const optimize::ModesResult r = optimize::vibrationModes(problem.termPointers(), problem.stencils,
                                                           problem.rest, problem.restXi, options);
  double worstResidual = 0.0;
  for (const auto& mode : r.modes) worstResidual = std::max(worstResidual, mode.residual);
  return {{"seconds",
           {{"total", setup + r.totalSeconds},
            {"setup", setup},
            {"assembly", r.assemblySeconds},
            {"factor", r.factorSeconds},
            {"eigensolve", r.eigenSeconds}}},
          {"clamp", optimize::clampName(options.clamp)},
          {"modes", r.flexibleModes},
          {"lambda_1", r.modes.empty() ? json(nullptr) : json(r.modes.front().lambda)},
          {"lanczos_solves", r.operations},
          {"lanczos_restarts", r.restarts},
          {"worst_residual", worstResidual},
          {"unknowns", r.unknowns}};
}

// Runs in the child: the whole case, mesh included, as one JSON record. mesh_seconds: the mesh
// generated and compiled (stencils, rest state) and its fixed rings found.
json runCase(int n, const Case& c, const std::string& boundary) {
  const modeling::PolynomialSurface surface = modeling::PolynomialSurface::parse(boundary);
  const auto start = Clock::now();
  const modeling::Mesh mesh = modeling::generateMesh({modeling::MeshFamily::Patch48, n, 1, {}});
  modeling::Stencils stencils = modeling::compileStencils(mesh);
  modeling::RestState rest = modeling::precomputeRestState(stencils, mesh.positions);
  const std::vector<bool> fixed = optimize::fixedRings(stencils, kFixedRings);
  const double meshSeconds = secondsSince(start);
  const int vertexCount = stencils.vertexCount();
  json record = c.kind == "floor"       ? runFloor(stencils, rest, fixed, surface)
                : c.kind == "cgal_fair" ? runCgalFair(mesh, fixed, surface)
                : c.mode == "vibration"
                    ? runVibration(std::move(stencils), std::move(rest), c)
                    : runEnergy(std::move(stencils), std::move(rest), fixed, surface, c);
  record["mesh_seconds"] = meshSeconds;
  record["vertices"] = vertexCount;
  record["free_vertices"] = std::count(fixed.begin(), fixed.end(), false);
  return record;
}

bool writeAll(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t k = write(fd, text.data() + done, text.size() - done);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    done += static_cast<size_t>(k);
  }
  return true;
}

// Forks, runs the case in the child and returns its record with peak_memory_mb (the child's
// ru_maxrss) or, when the child failed, an "error".
json runInChild(int n, const Case& c, const Settings& s) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    close(fds[0]);
    if (s.timeout > 0) alarm(static_cast<unsigned>(s.timeout));  // SIGALRM ends a runaway case
    json record;
    int status = 0;
    try {
      record = runCase(n, c, s.boundary);
    } catch (const std::exception& e) {
      record = {{"error", e.what()}};
      status = 1;
    }
    const bool written = writeAll(fds[1], record.dump());
    close(fds[1]);
    _exit(written ? status : 2);  // no static destructors, no parent buffers flushed twice
  }
  close(fds[1]);
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t k = read(fds[0], buffer, sizeof buffer);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) break;
    text.append(buffer, static_cast<size_t>(k));
  }
  close(fds[0]);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  json record = json::object();
  if (!text.empty()) record = json::parse(text, nullptr, false);
  if (record.is_discarded()) record = {{"error", "unreadable record from the child"}};
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    record["error"] = signal == SIGALRM ? "timed out after " + std::to_string(s.timeout) + " s"
                                        : "killed by signal " + std::to_string(signal) + " (" +
                                              strsignal(signal) + ")";
  }
  record["peak_memory_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB → MiB
  return record;
}

// The time a record's ratios use: the floor's factor + solve, everyone else's total.
double primarySeconds(const json& record) {
  if (!record.contains("seconds")) return std::numeric_limits<double>::infinity();
  const json& seconds = record["seconds"];
  return seconds.value("factor_solve", seconds.value("total", 0.0));
}

json runRepeated(int n, const Case& c, const Settings& s) {
  json best;
  double peak = 0.0;
  for (int k = 0; k < s.repeat; ++k) {
    json record = runInChild(n, c, s);
    peak = std::max(peak, record["peak_memory_mb"].get<double>());
    if (best.is_null() || primarySeconds(record) < primarySeconds(best)) best = std::move(record);
  }
  best["peak_memory_mb"] = peak;
  best["repeats"] = s.repeat;
  json out = {{"n", n}, {"case", c.kind}};
  if (c.kind == "energy") {
    out["energy"] = c.energy;
    out["mode"] = c.mode;
  }
  out.update(best);
  return out;
}

std::string formatSeconds(const json& record) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f s", primarySeconds(record));
  return text;
}

json ratio(double numerator, double denominator) {
  if (!(numerator < std::numeric_limits<double>::infinity()) || !(denominator > 0.0) ||
      !(denominator < std::numeric_limits<double>::infinity()))
    return nullptr;
  return numerator / denominator;
}

// The targets at one n.
json summarize(const json& records, int n, const std::vector<std::string>& energies) {
  const json* floor = nullptr;
  const json* fair = nullptr;
  std::vector<const json*> cases;
  for (const json& r : records) {
    if (r["n"] != n) continue;
    if (r["case"] == "floor") floor = &r;
    if (r["case"] == "cgal_fair") fair = &r;
    if (r["case"] == "energy") cases.push_back(&r);
  }
  const auto find = [&](const std::string& energy, const std::string& mode) -> const json* {
    for (const json* r : cases)
      if ((*r)["energy"] == energy && (*r)["mode"] == mode) return r;
    return nullptr;
  };
  // A failed or unconverged solve meets no target.
  const auto ok = [](const json* r) {
    return r && !r->contains("error") && r->value("converged", true);
  };
  json targets = json::array();
  // "what": `r`'s ratio (its `key`, against a baseline that ran) at most `bound` (below it when
  // `strict`); a case that did not run (--modes) has no target.
  const auto target = [&](const json* r, bool baselineRan, const char* key, const std::string& what,
                          double bound, bool strict) {
    if (r == nullptr) return;
    const json value = ok(r) && baselineRan ? (*r)[key] : json(nullptr);
    const bool met =
        value.is_number() && (strict ? value.get<double>() < bound : value.get<double>() <= bound);
    targets.push_back({{"what", what}, {"ratio", value}, {"met", met}});
  };
  char what[96];
  // Issue #13: Newton ≤ 2.5× the floor (midedge ≤ 6×); issue #4's Ceres targets (3×, 10×).
  for (const char* mode : {"newton", "ceres"}) {
    for (const std::string& e : energies) {
      const bool newton = std::string(mode) == "newton";
      const double bound = e == "midedge" ? (newton ? 6.0 : 10.0) : (newton ? 2.5 : 3.0);
      std::snprintf(what, sizeof what, "%s %s <= %gx floor", mode, e.c_str(), bound);
      target(find(e, mode), floor != nullptr, "ratio_to_floor", what, bound, false);
    }
  }
  for (const std::string& e : energies)
    target(find(e, "newton"), find(e, "ceres") != nullptr, "ratio_to_ceres",
           "newton " + e + " faster than ceres", 1.0, true);
  for (const std::string& e : energies)
    target(find(e, "linearized"), floor != nullptr, "ratio_to_floor",
           "linearized " + e + " <= 1.5x floor", 1.5, false);
  for (const char* mode : {"newton", "ceres", "linearized"})
    for (const std::string& e : energies)
      target(find(e, mode), fair != nullptr, "ratio_to_cgal_fair",
             std::string(mode) + " " + e + " faster than cgal_fair", 1.0, true);
  // Issue #16: 12 vibration modes ≤ 4× the floor.
  for (const std::string& e : energies)
    target(find(e, "vibration"), floor != nullptr, "ratio_to_floor",
           "vibration " + e + " (12 modes) <= 4x floor", 4.0, false);
  double peak = 0.0;
  std::string worst;
  for (const json* r : cases) {
    const double mb = (*r)["peak_memory_mb"].get<double>();
    if (mb > peak) {
      peak = mb;
      worst = (*r)["mode"].get<std::string>() + " " + (*r)["energy"].get<std::string>();
    }
  }
  targets.push_back({{"what", "peak memory of every energy solve < 3 GB (3072 MB)"},
                     {"peak_memory_mb", peak},
                     {"worst", worst},
                     {"met", !cases.empty() && peak < 3072.0}});
  return {{"n", n},
          {"floor_used_by_ratios", "floor seconds.factor_solve (CHOLMOD factor + solve)"},
          {"targets", targets}};
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) items.push_back(item);
  return items;
}

std::vector<int> parseSizes(const std::string& text) {
  std::vector<int> sizes;
  for (const std::string& item : splitList(text)) {
    std::size_t used = 0;
    const int n = std::stoi(item, &used);
    if (used != item.size() || n < 4) throw CLI::ValidationError("--sizes", "bad size " + item);
    sizes.push_back(n);
  }
  return sizes;
}

std::vector<std::string> parseEnergies(const std::string& text) {
  std::vector<std::string> energies;
  for (const std::string& item : splitList(text)) {
    curvature::parseDiscretization(item);  // throws InputError listing the names
    energies.push_back(item);
  }
  return energies;
}

// A table on stderr for people: the primary time (floor: factor + solve), the report's split,
// ratios and peak memory; "-" where a column does not apply.
void printTable(const json& records) {
  std::fprintf(stderr, "\n%5s %8s %-10s %-12s %9s %9s %9s %5s %5s %5s %8s %8s %8s %8s\n", "n",
               "free", "case", "mode", "seconds", "eval_s", "linsol_s", "iter", "fact", "conv",
               "x_floor", "x_fair", "x_ceres", "peak_MB");
  const auto cell = [](const json& j, const char* key, const char* format) {
    if (!j.contains(key) || !j[key].is_number()) return std::string("-");
    char text[32];
    std::snprintf(text, sizeof text, format, j[key].get<double>());
    return std::string(text);
  };
  for (const json& r : records) {
    const json seconds = r.value("seconds", json::object());
    const std::string name = r[r["case"] == "energy" ? "energy" : "case"].get<std::string>();
    const std::string mode = r.value("mode", r["case"] == "floor" ? "f+s" : "-");
    const std::string converged = !r.contains("converged") ? "-" : r["converged"] ? "yes" : "NO";
    std::fprintf(stderr, "%5d %8d %-10s %-12s %9.3f %9s %9s %5s %5s %5s %8s %8s %8s %8.0f%s\n",
                 r["n"].get<int>(), r.value("free_vertices", 0), name.c_str(), mode.c_str(),
                 primarySeconds(r), cell(seconds, "evaluation", "%.3f").c_str(),
                 cell(seconds, "linear_solver", "%.3f").c_str(),
                 cell(r, "iterations", "%.0f").c_str(), cell(r, "factorizations", "%.0f").c_str(),
                 converged.c_str(), cell(r, "ratio_to_floor", "%.2f").c_str(),
                 cell(r, "ratio_to_cgal_fair", "%.3f").c_str(),
                 cell(r, "ratio_to_ceres", "%.3f").c_str(), r["peak_memory_mb"].get<double>(),
                 r.contains("error") ? ("  ERROR: " + r["error"].get<std::string>()).c_str() : "");
  }
}

// The command line into `s` and `output`; the exit code when it asks for help or is refused.
std::optional<int> parseArguments(int argc, char** argv, Settings& s, std::string& output) {
  std::string sizes = "64,128,256,512", energies = "hinge,triavg,cotan,midedge,quadfit";
  bool quick = false;
  CLI::App app(
      "flexure solve benchmark: each energy's Newton, Ceres and linearized solve vs one "
      "CHOLMOD bi-Laplacian solve (the floor) and CGAL's PMP::fair, on patch48");
  app.add_option("--sizes", sizes, "Mesh sizes n (cells per side)")->capture_default_str();
  app.add_option("--energies", energies)->capture_default_str();
  app.add_option("--boundary", s.boundary, "Fixed rings lifted onto z = p(x, y)")
      ->capture_default_str();
  app.add_option("--repeat", s.repeat, "Runs per case; the fastest is kept")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--timeout", s.timeout, "Seconds per case before it is killed (0: none)")
      ->capture_default_str();
  app.add_option("-o,--output", output, "Also write the JSON here");
  app.add_flag("--quick", quick, "Smoke run: sizes 32,64");
  std::string modes = "newton,ceres,linearized";
  app.add_option("--modes", modes,
                 "Which solves of each energy: newton, ceres (nonlinear; 'nonlinear' = both), "
                 "linearized, vibration (12 vibration modes; not in the default)")
      ->capture_default_str();
  app.add_flag("--baselines", s.baselines,
               "Also each energy's Ceres solve on Ceres' AMD order (mode ceres_amd)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    s.sizes = quick ? std::vector<int>{32, 64} : parseSizes(sizes);
    s.energies = parseEnergies(energies);
    s.newton = s.ceres = s.linearized = false;
    for (const std::string& mode : splitList(modes)) {
      if (mode == "newton" || mode == "nonlinear") s.newton = true;
      if (mode == "ceres" || mode == "nonlinear") s.ceres = true;
      if (mode == "linearized") s.linearized = true;
      if (mode == "vibration") s.vibration = true;
      if (mode != "newton" && mode != "ceres" && mode != "nonlinear" && mode != "linearized" &&
          mode != "vibration")
        throw std::runtime_error("--modes " + modes +
                                 ": expected newton, ceres, linearized, vibration");
    }
    if (!s.newton && !s.ceres && !s.linearized && !s.vibration)
      throw std::runtime_error(
          "--modes is empty: expected newton, ceres, linearized and/or vibration");
    modeling::PolynomialSurface::parse(s.boundary);  // fail before any case runs
  } catch (const std::exception& e) {
    std::cerr << "solve_bench: " << e.what() << "\n";
    return 1;
  }
  return std::nullopt;
}

// The cases of one size: the floor, CGAL's fair, then each energy's solves.
std::vector<Case> casesOfSize(const Settings& s) {
  std::vector<Case> cases = {{"floor", "", ""}};
  // CGAL's fair is the baseline of the static solves only.
  if (s.newton || s.ceres || s.linearized) cases.push_back({"cgal_fair", "", ""});
  for (const std::string& e : s.energies) {
    if (s.vibration) cases.push_back({"energy", e, "vibration"});
    if (s.newton) cases.push_back({"energy", e, "newton"});
    if (s.ceres) cases.push_back({"energy", e, "ceres"});
    if (s.linearized) cases.push_back({"energy", e, "linearized"});
    if (s.ceres && s.baselines) cases.push_back({"energy", e, "ceres_amd"});
  }
  return cases;
}

// Ratios of the records from `first` on (one size), once that size's baselines are known.
void addRatios(json& records, size_t first) {
  double floorSeconds = std::numeric_limits<double>::infinity();
  double fairSeconds = floorSeconds;
  for (size_t k = first; k < records.size(); ++k) {
    if (records[k].contains("error")) continue;
    if (records[k]["case"] == "floor") floorSeconds = primarySeconds(records[k]);
    if (records[k]["case"] == "cgal_fair") fairSeconds = primarySeconds(records[k]);
  }
  for (size_t k = first; k < records.size(); ++k) {
    json& r = records[k];
    const double seconds =
        r.contains("error") ? std::numeric_limits<double>::infinity() : primarySeconds(r);
    r["ratio_to_floor"] = ratio(seconds, floorSeconds);
    r["ratio_to_cgal_fair"] = ratio(seconds, fairSeconds);
    // Newton and Ceres' AMD-order solve against Ceres' default one, same run.
    const std::string mode = r.value("mode", "");
    if (mode != "newton" && mode != "ceres_amd") continue;
    for (size_t j = first; j < records.size(); ++j) {
      const json& ceres = records[j];
      if (ceres["case"] == "energy" && ceres["energy"] == r["energy"] && ceres["mode"] == "ceres" &&
          !ceres.contains("error"))
        r["ratio_to_ceres"] = ratio(seconds, primarySeconds(ceres));
    }
  }
}

// Every case of every size, each with its ratios.
json runAll(const Settings& s) {
  json records = json::array();
  for (int n : s.sizes) {
    const size_t first = records.size();
    for (const Case& c : casesOfSize(s)) {
      json record = runRepeated(n, c, s);
      std::fprintf(stderr, "n=%d %s %s %s: %s, %.0f MB%s\n", n, c.kind.c_str(), c.energy.c_str(),
                   c.mode.c_str(), formatSeconds(record).c_str(),
                   record["peak_memory_mb"].get<double>(),
                   record.contains("error") ? (" ERROR " + record["error"].dump()).c_str() : "");
      records.push_back(std::move(record));
    }
    addRatios(records, first);
  }
  return records;
}

// The table on stderr, the JSON on stdout and in `output` (when given); the exit code.
int report(const Settings& s, const json& records, const std::string& output) {
  const json result = {
      {"machine", {{"cores", sysconf(_SC_NPROCESSORS_ONLN)}}},
      {"boundary", s.boundary},
      {"mesh", "patch48, " + std::to_string(kFixedRings) + " fixed rings, height mode"},
      {"threads", kThreads},
      {"repeat", s.repeat},
      {"records", records},
      {"summary",
       summarize(records, *std::max_element(s.sizes.begin(), s.sizes.end()), s.energies)},
  };
  printTable(records);
  const std::string text = result.dump(2);
  std::cout << text << "\n";
  if (!output.empty()) {
    std::ofstream file(output);
    file << text << "\n";
    if (!file) {
      std::cerr << "solve_bench: could not write " << output << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  flexure::optimize::reuseFreedMemory();  // as the flexure executable does
  Settings s;
  std::string output;
  if (const std::optional<int> exitCode = parseArguments(argc, argv, s, output)) return *exitCode;
  return report(s, runAll(s), output);
}
