// Fairing accuracy on surfaces with a known fair answer (issue #15): a region of an irregular
// sphere (jittered icosphere or CGAL-remeshed) or of the Clifford torus
// (modeling/willmore_surfaces.h) is spoiled — radial noise, or pressed flat — and faired back by
// CGAL's linear fair and by flexure with each energy. Each result's distance from the exact surface
// over the region, max and RMS of |dist| / scale, at several resolutions, and the order of the
// error under refinement (log2 of successive ratios: each level halves the edge length). Smallest
// angle, seconds and checkFairing's verdict (faces turned over or degenerate, and for flexure the
// gradient check: a row marked FAILS CHECKS is a result `flexure fair` would not write) beside.
// JSON on stdout, a table on stderr.
//
// Cases (--cases): noise<D> — a geodesic cap of D degrees (sphere) or D/180·π tube radii (torus),
// 5 % radial noise (--noise); flat<D> — the cap pressed flat onto the plane through its rim.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "modeling/fairing_region.h"
#include "modeling/mesh_io.h"
#include "modeling/stencils.h"
#include "modeling/vertex_sets.h"
#include "modeling/willmore_surfaces.h"
#include "optimize/fairing/fairing.h"

namespace {

namespace modeling = flexure::modeling;
namespace optimize = flexure::optimize;
namespace curvature = flexure::curvature;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;

struct Distance {
  double max = 0.0, rms = 0.0;
};

Distance regionDistance(modeling::WillmoreSurface surface, const modeling::FairingPatch& patch,
                        const modeling::Positions& x) {
  Distance d;
  int count = 0;
  for (int v = 0; v < x.rows(); ++v) {
    if (!patch.moves[v]) continue;
    const double e = modeling::relativeDistance(surface, x.row(v).transpose());
    d.max = std::max(d.max, e);
    d.rms += e * e;
    ++count;
  }
  d.rms = std::sqrt(d.rms / std::max(count, 1));
  return d;
}

// The bench's options, as the flags give them.
struct BenchOptions {
  std::vector<int> levels = {3, 4, 5};
  std::vector<std::string> surfaces = {"sphere", "remeshed", "torus"};
  std::vector<std::string> cases = {"noise40", "flat60"};
  std::vector<std::string> energies = {"hinge", "triavg", "cotan", "midedge", "quadfit"};
  double noise = 0.05, jitter = 0.3;
  std::optional<double> weight;   // empty: the metric's default (optimize::defaultFairingOptions)
  std::optional<int> fadeStages;  // likewise
  std::string metric = "current", shape = "start", vertexArea;  // vertexArea likewise
  std::string start = "best";
  int threads = 2;
  bool progress = false;
  std::string writeDirectory;
};

void addOptions(CLI::App& app, BenchOptions& o) {
  app.add_option("--levels", o.levels, "Sphere levels (torus n = 20 · 2^(level − 3))");
  app.add_option("--surfaces", o.surfaces,
                 "sphere (a jittered icosphere), remeshed (CGAL's isotropic remeshing of the "
                 "sphere) and/or torus");
  app.add_option("--cases", o.cases, "noise<degrees> | flat<degrees>");
  app.add_option("--energies", o.energies, "Bending energies of flexure's fairing");
  app.add_option("--noise", o.noise, "Radial noise amplitude / radius");
  app.add_option("--jitter", o.jitter, "Vertex jitter / edge length");
  app.add_option("--metric", o.metric, "current | current-exact | input")
      ->check(CLI::IsMember({"current", "current-exact", "input"}));
  app.add_option("--shape", o.shape, "Membrane rest shape: start | input")
      ->check(CLI::IsMember({"start", "input"}));
  app.add_option("--membrane-weight", o.weight,
                 "Membrane weight w (default: the metric's, 0.1 on the current metric)");
  app.add_option("--membrane-fade", o.fadeStages,
                 "Membrane fade stages, each lowering w tenfold (default: the metric's, 2 on the "
                 "current metric)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--vertex-area", o.vertexArea,
                 "cotan's vertex area: barycentric | voronoi (default: the metric's, barycentric "
                 "on the current metric)")
      ->check(CLI::IsMember({"barycentric", "voronoi"}));
  app.add_option("--start", o.start, "Start of the nonlinear solve: best | biharmonic | input")
      ->check(CLI::IsMember({"best", "biharmonic", "input"}));
  app.add_option("--threads", o.threads);
  app.add_flag("--progress", o.progress);
  app.add_option("--write", o.writeDirectory,
                 "Also write each spoiled mesh and its region, DIR/SURFACE-CASE-LEVEL.off and "
                 ".txt (for flexure fair --region vertices:FILE), and each result, "
                 "DIR/SURFACE-CASE-LEVEL-METHOD.off")
      ->check(CLI::ExistingDirectory);
}

// The cap's angle in degrees of a case noise<D> or flat<D>; empty when `spec` is neither or D is
// not in (0, 180).
std::optional<double> caseDegrees(const std::string& spec) {
  const bool flat = spec.rfind("flat", 0) == 0;
  std::size_t used = 0;
  double degrees = 0.0;
  const std::string number = spec.substr(flat ? 4 : std::min<std::size_t>(5, spec.size()));
  try {
    degrees = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if ((!flat && spec.rfind("noise", 0) != 0) || used == 0 || used != number.size() ||
      !(degrees > 0.0 && degrees < 180.0))
    return std::nullopt;
  return degrees;
}

// The exact mesh of a surface at `level`: the icosphere's edge at `level` is the remeshed
// sphere's target edge.
modeling::Mesh exactMesh(const std::string& surfaceName, int level, double jitter) {
  return surfaceName == "torus"      ? modeling::cliffordTorus(20 << (level - 3), jitter, 7)
         : surfaceName == "remeshed" ? modeling::remeshedSphere(1.1071 / std::pow(2.0, level))
                                     : modeling::irregularSphere(level, jitter, 7);
}

// The spoiled mesh as STEM.off and its region's vertex indices, one a line, as STEM.txt.
void writeSpoiled(const std::string& stem, const modeling::Mesh& spoiled,
                  const std::vector<bool>& region) {
  modeling::writeMesh(stem + ".off", spoiled);
  std::ofstream indices(stem + ".txt");
  for (int v = 0; v < spoiled.vertexCount(); ++v)
    if (region[v]) indices << v << '\n';
}

// flexure's fairing with `energy`, as the options ask.
optimize::FairingOptions fairingOptions(const BenchOptions& o, const std::string& energy) {
  optimize::FairingOptions options =
      optimize::defaultFairingOptions(optimize::parseFairingMetric(o.metric));
  options.bending.discretization = curvature::parseDiscretization(energy);
  options.bending.restCurvature = curvature::RestCurvature::Flat;
  if (!o.vertexArea.empty()) {
    options.bending.vertexArea = o.vertexArea == "barycentric" ? curvature::VertexArea::Barycentric
                                                               : curvature::VertexArea::Voronoi;
  }
  options.membraneShape =
      o.shape == "input" ? optimize::FairingShape::Input : optimize::FairingShape::Start;
  options.start = o.start == "input"        ? optimize::FairingStart::Input
                  : o.start == "biharmonic" ? optimize::FairingStart::Biharmonic
                                            : optimize::FairingStart::Best;
  if (o.weight) options.membraneWeight = *o.weight;
  if (o.fadeStages) options.membraneFadeStages = *o.fadeStages;
  options.solver.threads = o.threads;
  options.solver.progress = o.progress;
  return options;
}

// One row: the surface at `level` with the case's cap spoiled, faired by CGAL and by each energy.
json benchLevel(const BenchOptions& o, const std::string& surfaceName, const std::string& spec,
                double degrees, int level) {
  const bool flat = spec.rfind("flat", 0) == 0;
  const auto surface = surfaceName == "torus" ? modeling::WillmoreSurface::CliffordTorus
                                              : modeling::WillmoreSurface::Sphere;
  const modeling::Mesh exact = exactMesh(surfaceName, level, o.jitter);
  const Eigen::Vector3d centre = surface == modeling::WillmoreSurface::Sphere
                                     ? Eigen::Vector3d(0.0, 0.0, 1.0)
                                     : Eigen::Vector3d(std::sqrt(2.0) + 1.0, 0.0, 0.0);
  const std::vector<bool> region =
      modeling::capRegion(surface, exact, centre, degrees * kPi / 180.0);
  modeling::Mesh spoiled = exact;
  spoiled.positions = modeling::perturbRegion(
      surface, exact, region, centre,
      flat ? modeling::Perturbation::Flatten : modeling::Perturbation::Noise, o.noise, 11);
  const std::string stem =
      o.writeDirectory + "/" + surfaceName + "-" + spec + "-" + std::to_string(level);
  if (!o.writeDirectory.empty()) writeSpoiled(stem, spoiled, region);
  const modeling::Stencils stencils = modeling::compileStencils(spoiled);
  const modeling::FairingPatch patch = modeling::extractFairingPatch(spoiled, stencils, region);
  json row = {{"surface", surfaceName},
              {"case", spec},
              {"level", level},
              {"vertices", exact.vertexCount()},
              {"region_vertices", modeling::countVertices(region)}};
  // A result is recorded with checkFairing's checks (`solve`: flexure's, for the gradient
  // check); a solve that stopped at a result with an inverted or degenerate face is no
  // fairing `flexure fair` would write, so its row says so beside the distances.
  const auto record = [&](const std::string& name, const modeling::Positions& x, double seconds,
                          json extra, const optimize::FairingResult* solve = nullptr) {
    const Distance d = regionDistance(surface, patch, x);
    const optimize::FairingChecks checks = optimize::checkFairing(patch, x, solve);
    extra["max"] = d.max;
    extra["rms"] = d.rms;
    extra["seconds"] = seconds;
    extra["min_angle"] = checks.resultMinAngleDegrees;
    extra["inverted_faces"] = checks.invertedFaces.size();
    extra["degenerate_faces"] = checks.degenerateFaces.size();
    extra["checks_passed"] = checks.passed();
    row[name] = extra;
    if (!o.writeDirectory.empty() && name != "input") {
      modeling::Mesh result = spoiled;
      result.positions = modeling::scatterPatchPositions(spoiled.positions, patch, x);
      modeling::writeMesh(stem + "-" + name + ".off", result);
    }
    std::fprintf(stderr, "%-6s %-8s L%d %-8s max %.2e rms %.2e  angle %5.2f  %6.2f s%s %s\n",
                 surfaceName.c_str(), spec.c_str(), level, name.c_str(), d.max, d.rms,
                 checks.resultMinAngleDegrees, seconds, checks.passed() ? "" : "  FAILS CHECKS",
                 extra.dump().c_str());
  };
  record("input", patch.mesh.positions, 0.0, json::object());
  auto t0 = Clock::now();
  const modeling::Positions cgal = optimize::fairCgal(patch);
  record("cgal", cgal, std::chrono::duration<double>(Clock::now() - t0).count(), json::object());
  for (const std::string& energy : o.energies) {
    const optimize::FairingOptions options = fairingOptions(o, energy);
    t0 = Clock::now();
    try {
      const optimize::FairingResult r = optimize::fairNonlinear(patch, options);
      const char* startName = r.start == optimize::FairingStart::Input ? "input" : "biharmonic";
      record(energy, r.positions, std::chrono::duration<double>(Clock::now() - t0).count(),
             {{"converged", r.report.converged},
              {"iterations", r.report.iterations},
              {"start", startName},
              {"membrane_weight", r.membraneWeight},
              {"gradient_ratio", r.finalGradientNorm / r.startGradientNorm}},
             &r);
    } catch (const std::exception& e) {
      row[energy] = {{"error", e.what()}};
      std::fprintf(stderr, "%s: %s\n", energy.c_str(), e.what());
    }
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("fair_sphere_bench: fairing accuracy on spheres and Clifford tori");
  BenchOptions o;
  addOptions(app, o);
  CLI11_PARSE(app, argc, argv);

  json out = json::array();
  for (const std::string& surfaceName : o.surfaces) {
    if (surfaceName != "sphere" && surfaceName != "remeshed" && surfaceName != "torus") {
      std::cerr << "fair_sphere_bench: --surfaces " << surfaceName
                << ": expected sphere, remeshed or torus\n";
      return 2;
    }
    for (const std::string& spec : o.cases) {
      const std::optional<double> degrees = caseDegrees(spec);
      if (!degrees) {
        std::cerr << "fair_sphere_bench: --cases " << spec
                  << ": expected noise<degrees> or flat<degrees>, degrees in (0, 180)\n";
        return 2;
      }
      for (int level : o.levels) out.push_back(benchLevel(o, surfaceName, spec, *degrees, level));
    }
  }
  std::cout << out.dump(2) << '\n';
}
