// flexure convert: read a mesh, check it, write it in another format at full precision.
#include <iostream>
#include <memory>

#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "modeling/mesh_io.h"

namespace flexure::cli {
namespace {

struct ConvertCommandOptions {
  std::string input;
  std::string output;
};

void runConvertCommand(const ConvertCommandOptions& o, const GlobalOptions& global) {
  modeling::writableMeshFormatOf(o.output);  // an unusable output name fails before any work
  std::vector<std::string> notices;
  const modeling::Mesh mesh = modeling::readMesh(o.input, &notices);
  if (!global.quiet)
    for (const std::string& notice : notices) std::cerr << "flexure convert: " << notice << '\n';
  modeling::writeMesh(o.output, mesh);
  if (!global.quiet) {
    std::cerr << "flexure convert: wrote " << o.output << " ("
              << counted(mesh.vertexCount(), "vertex") << ", " << counted(mesh.faceCount(), "face")
              << ")\n";
  }
}

}  // namespace

void registerConvertCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<ConvertCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "convert", "Check a mesh and write it as .obj, .off or .ply (polygons split into triangles)");
  auto files = CommandFiles::of(*sub);
  files->input("input", options->input, "Mesh file (.obj, .off, .ply, .stl)")->required();
  files->output("-o,--output", options->output, "Output mesh (.obj, .off or .ply)")->required();
  sub->footer("Example: flexure convert scan.stl -o scan.ply");
  files->onRun(global, [options, &global] { runConvertCommand(*options, global); });
}

}  // namespace flexure::cli
