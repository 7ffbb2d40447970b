// flexure info: what a mesh file holds and whether flexure can use it.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "modeling/errors.h"
#include "modeling/mesh_check.h"
#include "modeling/mesh_info.h"
#include "modeling/mesh_io.h"

namespace flexure::cli {
namespace {

struct InfoCommandOptions {
  std::string file;
  bool json = false;
};

std::string histogramText(const std::map<int, int>& valences) {
  std::ostringstream out;
  for (const auto& [valence, count] : valences) out << ' ' << valence << "×" << count;
  return valences.empty() ? " none" : out.str();
}

void printText(const std::string& file, const modeling::Mesh& mesh, int split,
               const modeling::MeshCheck& check, const modeling::MeshInfo* info) {
  std::ostringstream out;
  const auto row = [&](const char* key, const auto& value) {
    out << "  " << key << std::string(22 - std::string(key).size(), ' ') << value << '\n';
  };
  out << file << '\n';
  row("vertices", mesh.vertexCount());
  row("faces", mesh.faceCount());
  if (split > 0) row("polygons split", split);
  if (info) {
    row("edges", info->edges);
    row("components", info->components);
    row("euler characteristic", info->eulerCharacteristic);
    std::ostringstream loops;
    loops << info->boundaryLoopLengths.size();
    if (!info->boundaryLoopLengths.empty()) {
      loops << " (vertices:";
      for (int n : info->boundaryLoopLengths) loops << ' ' << n;
      loops << ')';
    }
    row("boundary loops", loops.str());
    row("valence, interior", histogramText(info->interiorValences).substr(1));
    row("valence, boundary", histogramText(info->boundaryValences).substr(1));
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "min %.6g  mean %.6g  max %.6g", info->minEdgeLength,
                  info->meanEdgeLength, info->maxEdgeLength);
    row("edge length", buffer);
    row("area", info->area);
    std::snprintf(buffer, sizeof buffer, "[%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g]",
                  info->boxMin.x(), info->boxMax.x(), info->boxMin.y(), info->boxMax.y(),
                  info->boxMin.z(), info->boxMax.z());
    row("bounding box", buffer);
  }
  row("valid", check.valid() ? "yes" : "no (" + std::to_string(check.totalProblems()) + " found)");
  for (const auto& p : check.problems)
    out << "    " << modeling::meshProblemName(p.kind) << ": " << p.element << ": " << p.reason
        << '\n';
  std::cout << out.str();
}

void runInfoCommand(const InfoCommandOptions& o) {
  const modeling::PolygonSoup soup = modeling::readPolygonSoup(o.file);
  int split = 0;
  const modeling::Mesh mesh = modeling::triangulatePolygons(soup, &split);
  const modeling::MeshCheck check = modeling::checkMesh(mesh, 10);
  std::optional<modeling::MeshInfo> info;
  if (check.valid()) info = modeling::describeMesh(mesh);

  if (o.json) {
    nlohmann::json report = {{"file", o.file},
                             {"vertices", mesh.vertexCount()},
                             {"faces", mesh.faceCount()},
                             {"polygons_split", split}};
    if (info) report.update(meshInfoJson(*info));
    report["validation"] = meshCheckJson(check);
    std::cout << report.dump(2) << '\n';
  } else {
    printText(o.file, mesh, split, check, info ? &*info : nullptr);
  }
  std::cout.flush();
  if (!check.valid()) {
    const int n = check.totalProblems();
    throw InputError(o.file + ": not usable by flexure: " + std::to_string(n) +
                     (n == 1 ? " problem" : " problems") + " (listed above)");
  }
}

}  // namespace

void registerInfoCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<InfoCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "info", "Describe a mesh file: counts, boundary loops, valences, sizes, validation verdict");
  sub->add_option("file", options->file, "Mesh file (.obj, .off, .ply, .stl)")->required();
  sub->add_flag("--json", options->json, "Print the description as JSON");
  sub->footer("Exits 2 when the mesh is not usable (the problems are listed).");
  sub->callback([options, &global] {
    if (!global.checkOnly) runInfoCommand(*options);  // flexure run's check: the parse alone
  });
}

}  // namespace flexure::cli
