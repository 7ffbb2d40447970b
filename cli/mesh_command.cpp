// flexure mesh: one generated test-problem mesh, written to a file.
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"

namespace flexure::cli {
namespace {

struct MeshCommandOptions {
  std::string family = "patch48";
  int n = 8;
  std::uint64_t seed = 1;
  double aspect = 0.0;  // 0: the family's default
  std::string height;   // empty: flat
  std::string output;
};

void runMeshCommand(const MeshCommandOptions& o, const GlobalOptions& global) {
  modeling::meshFormatOf(o.output);  // an unusable output name fails before any work
  modeling::GeneratorOptions generator;
  generator.family = modeling::parseMeshFamily(o.family);
  generator.n = o.n;
  generator.seed = o.seed;
  if (o.aspect != 0.0) generator.aspect = o.aspect;
  const std::optional<modeling::PolynomialSurface> surface =
      o.height.empty() ? std::nullopt : std::optional(modeling::PolynomialSurface::parse(o.height));

  modeling::Mesh mesh = modeling::generateMesh(generator);
  if (surface) modeling::applyHeightField(*surface, mesh.positions);
  modeling::writeMesh(o.output, mesh);
  if (!global.quiet) {
    std::cerr << "flexure mesh: wrote " << o.output << " (" << o.family << ", n = " << o.n << ", "
              << mesh.vertexCount() << " vertices, " << mesh.faceCount() << " faces)\n";
  }
}

}  // namespace

void registerMeshCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<MeshCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "mesh", "Generate a test-problem mesh of the square [-1/2, 1/2]^2 (flat, or a height field)");
  sub->add_option("--family", options->family, "patch48 | stripe | criss | delaunay")
      ->capture_default_str();
  sub->add_option("-n,--n", options->n, "Cells per side (delaunay: boundary edges per side)")
      ->capture_default_str();
  sub->add_option("--seed", options->seed, "Random seed of the delaunay sampling")
      ->capture_default_str();
  sub->add_option("--aspect", options->aspect,
                  "Cell height / width (patch48, criss: default 1; stripe: 2)");
  sub->add_option("--height", options->height,
                  "Height field z = p(x, y): quadratic:a,b,c or polynomial:EXPR");
  sub->add_option("-o,--output", options->output, "Output mesh (.obj, .off or .ply)")->required();
  sub->footer(
      "Example: flexure mesh --family delaunay --n 32 --seed 7 --height quadratic:1,0,1 -o d.obj");
  sub->callback([options, &global] { runMeshCommand(*options, global); });
}

}  // namespace flexure::cli
