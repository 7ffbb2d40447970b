// flexure repair: mend what info refuses and a program can mend without guessing (unreferenced
// vertices, non-manifold vertices, inconsistent orientation; modeling/mesh_repair.h), check the
// result and write it, saying what changed.
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "modeling/mesh_check.h"
#include "modeling/mesh_io.h"
#include "modeling/mesh_repair.h"

namespace flexure::cli {
namespace {

struct RepairCommandOptions {
  std::string input, output, reportFile;
};

std::string changeText(const modeling::MeshRepairReport& r) {
  if (!r.changed()) return "nothing to repair";
  return "dropped " + counted(r.droppedVertices, "unreferenced vertex", "unreferenced vertices") +
         ", split non-manifold vertices into " +
         counted(r.addedVertices, "new copy", "new copies") + ", flipped " +
         counted(r.flippedFaces, "face") + " to a consistent orientation";
}

void runRepairCommand(const RepairCommandOptions& o, const GlobalOptions& global) {
  modeling::writableMeshFormatOf(o.output);  // an unusable output name fails before any work
  int split = 0;
  const modeling::Mesh input =
      modeling::triangulatePolygons(modeling::readPolygonSoup(o.input), &split);
  const modeling::RepairedMesh repaired = modeling::repairMesh(input);
  // What repair does not mend (zero-area or duplicate faces, non-finite coordinates) is named.
  modeling::requireValidMesh(repaired.mesh,
                             o.input + " (after repair: " + changeText(repaired.report) + ")");
  modeling::writeMesh(o.output, repaired.mesh);
  const modeling::MeshRepairReport& r = repaired.report;
  if (!o.reportFile.empty()) {
    writeJsonFile(o.reportFile, {{"input", o.input},
                                 {"output", o.output},
                                 {"polygons_split_into_triangles", split},
                                 {"dropped_unreferenced_vertices", r.droppedVertices},
                                 {"added_vertex_copies", r.addedVertices},
                                 {"flipped_faces", r.flippedFaces},
                                 {"vertices", repaired.mesh.vertexCount()},
                                 {"faces", repaired.mesh.faceCount()}});
  }
  if (!global.quiet) {
    std::cerr << "flexure repair: " << changeText(r) << "; wrote " << o.output << " ("
              << counted(repaired.mesh.vertexCount(), "vertex", "vertices") << ", "
              << counted(repaired.mesh.faceCount(), "face") << ")\n";
  }
}

}  // namespace

void registerRepairCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<RepairCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "repair",
      "Mend a mesh info refuses: drop unreferenced vertices, split non-manifold vertices, orient "
      "faces consistently");
  auto files = CommandFiles::of(*sub);
  files->input("input", options->input, "Mesh file (.obj, .off, .ply, .stl)")->required();
  files->output("-o,--output", options->output, "Repaired mesh (.obj, .off or .ply)")->required();
  files->output("--report", options->reportFile, "JSON report: what was changed");
  sub->footer(
      "Exit 2 when the input cannot be read, or the repaired mesh still has problems repair does "
      "not mend (zero-area or duplicate faces, non-finite coordinates), each named.\n"
      "Example: flexure repair broken.off -o fixed.off");
  files->onRun(global, [options, &global] { runRepairCommand(*options, global); });
}

}  // namespace flexure::cli
