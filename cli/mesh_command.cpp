// flexure mesh: one generated test-problem mesh, written to a file.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/available_memory.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "modeling/errors.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"

namespace flexure::cli {
namespace {

// Up to 20 000 cells per side: 2n² faces and 3n² edges stay far inside an int index.
constexpr int kMaxCellsPerSide = 20000;

// Peak resident memory of `flexure mesh` per (n + 1)² (the vertex count of a square grid), in
// bytes: the generation, the checks and the text of the output file. Measured with /usr/bin/time -v
// (maximum resident set size), one run each: patch48 n = 1000 and 2000, 257 MB and 1.01 GB for
// 1.0e6 and 4.0e6 vertices (260 B each; 290 B with --height); criss n = 1000, 280 B; delaunay
// n = 500 and 1000, 126 MB and 472 MB for 0.31e6 and 1.23e6 vertices (395 B a vertex, 482 B per
// (n + 1)²). 500 B covers every family.
constexpr double kMeshBytesPerVertex = 500.0;

// Refuses a mesh whose generation would not fit in the available memory, before any allocation.
// The estimate scales (n + 1)² by the rows an --aspect below 1 adds (stripe has half as many
// vertices: its estimate is high).
void requireMemoryFor(int n, double aspect) {
  const double cells = static_cast<double>(n) + 1.0;
  const double vertices = cells * cells * (aspect > 1.0 ? 1.0 : 1.0 / std::max(aspect, 1e-3));
  const double needed = vertices * kMeshBytesPerVertex;
  const double available = availableMemoryBytes();
  if (available > 0.0 && needed > available) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "--n %d: the mesh needs about %.1f GB of memory (%.3g vertices), more than the "
                  "%.1f GB available; give a smaller --n",
                  n, needed / 1e9, vertices, available / 1e9);
    throw InputError(text);
  }
}

struct MeshCommandOptions {
  std::string family = "patch48";
  int n = 8;
  std::uint64_t seed = 1;
  double aspect = 0.0;  // 0: the family's default
  std::string height;   // empty: flat
  std::string output;
};

void runMeshCommand(const MeshCommandOptions& o, const GlobalOptions& global) {
  modeling::writableMeshFormatOf(o.output);  // an unusable output name fails before any work
  // A tube's vertex count grows with its length as a square's with rows: 1/aspect.
  const double aspect = o.aspect == 0.0 ? 1.0 : o.aspect;
  requireMemoryFor(o.n, o.family == "cylinder" ? 1.0 / aspect : aspect);
  modeling::GeneratorOptions generator;
  generator.family = modeling::parseMeshFamily(o.family);
  generator.n = o.n;
  generator.seed = o.seed;
  if (o.aspect != 0.0) generator.aspect = o.aspect;
  if (modeling::isShellFamily(generator.family) && !o.height.empty()) {
    throw InputError("--height lifts the flat families only; a " + o.family + " is not a graph");
  }
  const std::optional<modeling::PolynomialSurface> surface =
      o.height.empty() ? std::nullopt : std::optional(modeling::PolynomialSurface::parse(o.height));

  modeling::Mesh mesh = modeling::generateMesh(generator);
  if (surface) modeling::applyHeightField(*surface, mesh.positions);
  modeling::writeMesh(o.output, mesh);
  if (!global.quiet) {
    std::cerr << "flexure mesh: wrote " << o.output << " (" << o.family << ", n = " << o.n << ", "
              << counted(mesh.vertexCount(), "vertex") << ", " << counted(mesh.faceCount(), "face")
              << ")\n";
  }
}

}  // namespace

void registerMeshCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<MeshCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "mesh",
      "Generate a test-problem mesh of the square [-1/2, 1/2]^2 (flat, or a height field) or a "
      "shell (cylinder, sphere, hemisphere of radius 1/2)");
  sub->add_option("--family", options->family,
                  "patch48 | stripe | criss | delaunay | cylinder | sphere | hemisphere")
      ->capture_default_str();
  auto files = CommandFiles::of(*sub);
  sub->add_option(
         "-n,--n", options->n,
         "Cells per side (delaunay: boundary edges per side; shells: edges around, sphere and "
         "hemisphere a multiple of 4)")
      ->capture_default_str()
      ->check(inRange(1, kMaxCellsPerSide));
  sub->add_option("--seed", options->seed, "Random seed of the delaunay sampling")
      ->capture_default_str()
      ->check(seedValue());
  sub->add_option("--aspect", options->aspect,
                  "Cell height / width (patch48, criss: default 1; stripe: 2); cylinder: length / "
                  "diameter (default 1)")
      ->check(positive());
  sub->add_option("--height", options->height,
                  "Height field z = p(x, y): quadratic:a,b,c or polynomial:EXPR")
      ->check(surfaceSpec());
  files->output("-o,--output", options->output, "Output mesh (.obj, .off or .ply)")->required();
  sub->footer(
      "Example: flexure mesh --family delaunay --n 32 --seed 7 --height quadratic:1,0,1 -o d.obj");
  files->onRun(global, [options, &global] { runMeshCommand(*options, global); });
}

}  // namespace flexure::cli
