#include "reports/viewer_modes.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "optimize/modes/vibration_modes.h"

namespace flexure::reports {
namespace {

std::string modeLabel(const nlohmann::json& m) {
  char text[160];
  std::snprintf(text, sizeof text, "mode %d: λ = %.4g, ω = %.4g", m.value("index", 0),
                m.value("lambda", 0.0), m.value("omega", 0.0));
  std::string label = text;
  const int multiplicity = m.value("multiplicity", 1);
  if (multiplicity > 1) label += " (×" + std::to_string(multiplicity) + ")";
  return label;
}

// One energy's rest mesh and modes; `rest` read once for every energy.
render::ViewerMesh energyMesh(const std::filesystem::path& dir, const nlohmann::json& energy,
                              const modeling::Mesh& rest, const modeling::Stencils& stencils,
                              const modeling::RestState& restState) {
  const std::string report = (dir / "modes.json").string();
  render::ViewerMesh mesh;
  mesh.name = energy.value("energy", std::string("modes"));
  mesh.triangles = rest.triangles;
  mesh.frames.push_back(rest.positions);
  for (const nlohmann::json& m : energy.value("modes", nlohmann::json::array())) {
    if (m.value("kind", std::string()) != "flexible") continue;
    if (!m.contains("shape") || !m["shape"].is_string())
      throw InputError(report + ": " + mesh.name + " mode " + std::to_string(m.value("index", 0)) +
                       " has no shape file (the folder was written without its mode shapes)");
    const std::filesystem::path path = dir / m["shape"].get<std::string>();
    const modeling::Mesh shaped = modeling::readMesh(path.string());
    if (shaped.vertexCount() != rest.vertexCount() || shaped.triangles != rest.triangles)
      throw InputError(path.string() + ": " + std::to_string(shaped.vertexCount()) +
                       " vertices, but the rest mesh " + (dir / "rest.obj").string() + " has " +
                       std::to_string(rest.vertexCount()) + " (or other faces)");
    mesh.modes.push_back(
        viewerMode(stencils, restState, shaped.positions - rest.positions, modeLabel(m)));
  }
  if (mesh.modes.empty())
    throw InputError(report + ": " + mesh.name + " has no flexible mode to show");
  return mesh;
}

}  // namespace

render::ViewerMode viewerMode(const modeling::Stencils& stencils, const modeling::RestState& rest,
                              const modeling::Positions& shape, const std::string& label) {
  render::ViewerMode mode;
  mode.label = label;
  mode.shape = shape;
  for (const auto& [p, q] : optimize::nodalEdgeSegments(stencils, rest, shape))
    mode.nodalLines.emplace_back(render::ViewerLinePoint{p.a, p.b, p.t},
                                 render::ViewerLinePoint{q.a, q.b, q.t});
  return mode;
}

bool isModesFolder(const std::string& dir) {
  return std::filesystem::is_directory(dir) &&
         std::filesystem::is_regular_file(std::filesystem::path(dir) / "modes.json");
}

std::vector<render::ViewerMesh> readModesFolder(const std::string& folder,
                                                render::ViewerStyle style) {
  if (style == render::ViewerStyle::Field)
    throw InputError(folder +
                     ": a modes folder is drawn in the reflection, isophote or shaded style, not "
                     "with a field (curvature, displacement)");
  const std::filesystem::path dir(folder);
  const std::string report = (dir / "modes.json").string();
  std::ifstream file(report);
  if (!file) throw InputError(report + ": cannot be read");
  const nlohmann::json json = nlohmann::json::parse(file, nullptr, false);
  if (json.is_discarded() || !json.is_object() || !json.contains("energies") ||
      !json["energies"].is_array())
    throw InputError(report + ": not a flexure modes report (no \"energies\" list)");
  const std::filesystem::path restPath = dir / json.value("rest", std::string("rest.obj"));
  if (!std::filesystem::is_regular_file(restPath))
    throw InputError(restPath.string() +
                     ": missing: the modes folder holds no rest mesh and mode shapes (it was "
                     "written without them)");
  const modeling::Mesh rest = modeling::readMesh(restPath.string());
  const modeling::Stencils stencils = modeling::compileStencils(rest);
  const modeling::RestState restState = modeling::precomputeRestState(stencils, rest.positions);
  std::vector<render::ViewerMesh> meshes;
  for (const nlohmann::json& energy : json["energies"])
    meshes.push_back(energyMesh(dir, energy, rest, stencils, restState));
  if (meshes.empty()) throw InputError(report + ": no energies");
  return meshes;
}

}  // namespace flexure::reports
