// flexure demo: the main job. It generates and describes the test-problem meshes of every family
// at three refinement levels, runs a small convergence study (seconds) into convergence/ and a
// small `flexure compare` (every energy's minimizer on three families, rendered) into compare/ and
// the clamped square's vibration modes (`flexure modes`, the Chladni figure) into modes/.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/compare_command.h"
#include "cli/mesh_json.h"
#include "cli/modes_command.h"
#include "cli/study_outputs.h"
#include "curvature/energy_registry.h"
#include "modeling/atomic_write.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_info.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "optimize/studies/spectrum_study.h"

namespace flexure::cli {
namespace {

struct DemoCommandOptions {
  std::string outputDir = "demo-output";
};

// The energies of the demo's Chladni figure: one per element kind (an edge, a face, a vertex
// energy), each the first of its kind among the spectrum study's default energies.
std::vector<std::string> oneEnergyPerElementKind() {
  std::vector<std::string> names;
  std::vector<curvature::ElementKind> kinds;
  for (const optimize::EnergyVariant& v : optimize::defaultSpectrumEnergies()) {
    const curvature::EnergyEntry& entry = curvature::energyEntry(v.bending.discretization);
    if (std::find(kinds.begin(), kinds.end(), entry.elementKind) != kinds.end()) continue;
    kinds.push_back(entry.elementKind);
    names.push_back(entry.name);
  }
  return names;
}

// The general quadratic of the convergence study's default set: boundary data of the test problem.
constexpr const char* kDemoSurface = "quadratic:0.3,-0.7,0.5";

void runDemoCommand(const DemoCommandOptions& o, const GlobalOptions& global) {
  namespace fs = std::filesystem;
  const fs::path dir(o.outputDir), meshDir = dir / "meshes";
  modeling::createOutputDirectory(meshDir.string());
  const modeling::PolynomialSurface surface = modeling::PolynomialSurface::parse(kDemoSurface);

  nlohmann::json records = nlohmann::json::array();
  std::printf("%-9s %4s %9s %9s  %-34s %s\n", "family", "n", "vertices", "faces",
              "interior valences", "mean edge x n");
  for (const auto family : {modeling::MeshFamily::Patch48, modeling::MeshFamily::Stripe,
                            modeling::MeshFamily::Criss, modeling::MeshFamily::Delaunay}) {
    for (const modeling::Mesh& flat : modeling::refinementSequence({family, 8, 1, {}}, 3)) {
      const std::string name = std::string(modeling::meshFamilyName(family));
      const modeling::MeshInfo info = modeling::describeMesh(flat);
      const int n = 8 << records.size() % 3;
      const std::string stem = name + "-n" + std::to_string(n);
      modeling::Mesh curved = flat;
      modeling::applyHeightField(surface, curved.positions);
      modeling::writeMesh((meshDir / (stem + ".obj")).string(), flat);
      modeling::writeMesh((meshDir / (stem + "-quadratic.obj")).string(), curved);

      std::string valences;
      for (const auto& [valence, count] : info.interiorValences)
        valences += std::to_string(valence) + "x" + std::to_string(count) + " ";
      std::printf("%-9s %4d %9d %9d  %-34s %.3f\n", name.c_str(), n, info.vertices, info.faces,
                  valences.c_str(), info.meanEdgeLength * n);
      records.push_back(
          {{"family", name},
           {"n", n},
           {"mesh", "meshes/" + stem + ".obj"},
           {"height_field",
            {{"surface", kDemoSurface}, {"mesh", "meshes/" + stem + "-quadratic.obj"}}},
           {"info", meshInfoJson(info)}});
    }
  }
  writeJsonFile((dir / "meshes.json").string(), {{"meshes", records}});
  if (!global.quiet) {
    std::cerr << "flexure demo: wrote " << records.size() * 2 << " meshes to " << meshDir.string()
              << " and their descriptions to " << (dir / "meshes.json").string() << '\n';
  }

  // A small convergence study: every energy of the spec's table on the 4-8 patch and a Delaunay
  // mesh, n = 8 and 16, the default quadratics, nonlinear C2 at ε = 1/2, 1/4, 1/8.
  optimize::StudyOptions study;
  study.families = {modeling::MeshFamily::Patch48, modeling::MeshFamily::Delaunay};
  study.baseN = 8;
  study.levels = 2;
  study.amplitudes = 3;
  const fs::path studyDir = dir / "convergence";
  std::printf("\n");
  std::fputs(runStudyInto(study, studyDir.string(), global, "flexure demo").c_str(), stdout);
  if (!global.quiet) {
    std::cerr << "flexure demo: wrote the convergence study (summary.md, results.json, "
                 "results.csv, plots) to "
              << studyDir.string() << '\n';
  }

  // The slides' figure, small: every default energy's nonlinear minimizer on patch48, stripe and
  // delaunay at n = 12, reflection lines at 240 pixels a panel (about a second).
  CompareOptions compare;
  compare.outputDir = (dir / "compare").string();
  compare.n = 12;
  compare.size = 240;
  compare.stripes = 10;
  runCompare(compare, global, "flexure demo");

  // Chladni's plates: the first six vibration modes of the clamped square for one energy of each
  // element kind (midedge, cotan, hinge) against Leissa's frequencies, with their nodal lines (a
  // second).
  ModesOptions modes;
  modes.outputDir = (dir / "modes").string();
  modes.family = "patch48";
  modes.n = 24;
  modes.energies = oneEnergyPerElementKind();
  modes.count = 6;
  modes.reference = "square-clamped";
  std::printf("\nVibration modes of the clamped square (λ = ω L² √(ρh/D)):\n");
  runModes(modes, global, "flexure demo");
}

}  // namespace

void registerDemoCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<DemoCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "demo",
      "The main job: the test-problem meshes of every family, a small convergence study, a "
      "small comparison figure and the clamped square's vibration modes");
  auto files = CommandFiles::of(*sub);
  files
      ->output("-o,--output", options->outputDir, "Output directory (created if missing)",
               OutputKind::Directory)
      ->capture_default_str();
  files->onRun(global, [options, &global] { runDemoCommand(*options, global); });
}

}  // namespace flexure::cli
