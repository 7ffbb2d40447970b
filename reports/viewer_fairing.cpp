#include "reports/viewer_fairing.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "modeling/boundary_rings.h"
#include "modeling/errors.h"
#include "modeling/fairing_region.h"
#include "modeling/mesh_io.h"
#include "modeling/stencils.h"

namespace flexure::reports {
namespace {

nlohmann::json readJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) return nlohmann::json();
  nlohmann::json json = nlohmann::json::parse(file, nullptr, false);
  return json.is_discarded() ? nlohmann::json() : json;
}

// A path of the report: as written (relative to the working directory), else relative to the
// report's folder.
std::string reportPath(const std::string& report, const std::string& path) {
  const std::filesystem::path beside = std::filesystem::path(report).parent_path() / path;
  if (std::filesystem::exists(path) || std::filesystem::path(path).is_absolute()) return path;
  return std::filesystem::exists(beside) ? beside.string() : path;
}

// The page framed on `region` of `result` and its rings (addFairingReport), on every mesh of
// `meshes` with the result's vertices.
void frameOnRegion(render::ViewerPageSpec& page, const std::vector<modeling::Mesh>& meshes,
                   const modeling::Mesh& result, const std::vector<bool>& region) {
  const Eigen::VectorXi rings = modeling::ringDistances(
      modeling::compileStencils(result), region, modeling::kHeldRings + modeling::kContextRings);
  std::vector<Eigen::RowVector3d> points;
  for (const modeling::Mesh& m : meshes)
    if (m.vertexCount() == result.vertexCount())
      for (int v = 0; v < m.vertexCount(); ++v)
        if (rings[v] >= 0) points.push_back(m.positions.row(v));
  page.framingPoints.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    page.framingPoints.row(static_cast<Eigen::Index>(i)) = points[i];
  page.viewDirection = modeling::regionNormal(result, region);
}

}  // namespace

render::ViewerSegments regionOutlineSegments(const modeling::Mesh& mesh,
                                             const std::vector<bool>& region) {
  render::ViewerSegments segments;
  for (const auto& [a, b] : modeling::regionOutlineEdges(modeling::compileStencils(mesh), region))
    segments.emplace_back(render::ViewerLinePoint{a, a, 0.0}, render::ViewerLinePoint{b, b, 0.0});
  return segments;
}

bool isFairingReport(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return false;
  const nlohmann::json json = readJson(path);
  return json.is_object() && json.contains("measures") && json.contains("region") &&
         json.contains("input");
}

void addFairingReport(render::ViewerPageSpec& page, const std::string& path) {
  const nlohmann::json report = readJson(path);
  if (!report.is_object() || !report.contains("region") || !report["input"].is_string())
    throw InputError(path + ": not a flexure fair report");
  if (!report["output"].is_string())
    throw InputError(path + ": the fair did not converge; its output was not written");
  const nlohmann::json& indices = report["region"].value("indices", nlohmann::json());
  if (!indices.is_array())
    throw InputError(path + ": the report has no region indices (written by an older flexure)");
  std::vector<std::pair<std::string, std::string>> inputs = {
      {"input", reportPath(path, report["input"].get<std::string>())}};
  if (report.contains("cgal_output") && report["cgal_output"].is_string())
    inputs.emplace_back("CGAL fair", reportPath(path, report["cgal_output"].get<std::string>()));
  inputs.emplace_back("flexure " + report.value("energy_name", std::string("fair")),
                      reportPath(path, report["output"].get<std::string>()));
  if (report.value("result", std::string()) == "cgal") inputs.back().first = "CGAL fair";

  std::vector<modeling::Mesh> meshes;
  for (const auto& [label, file] : inputs) meshes.push_back(modeling::readMesh(file));
  const modeling::Mesh& result = meshes.back();
  std::vector<bool> region(static_cast<std::size_t>(result.vertexCount()), false);
  for (const nlohmann::json& v : indices) {
    if (!v.is_number_integer() || v.get<long>() < 0 || v.get<long>() >= result.vertexCount())
      throw InputError(path + ": region index " + v.dump() + " is not a vertex of " +
                       inputs.back().second);
    region[v.get<std::size_t>()] = true;
  }
  const render::ViewerSegments outline = regionOutlineSegments(result, region);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const bool sameVertices =
        meshes[i].vertexCount() == result.vertexCount() && meshes[i].triangles == result.triangles;
    const bool input = i == 0;
    if (!sameVertices && !input)
      throw InputError(inputs[i].second + ": " + std::to_string(meshes[i].vertexCount()) +
                       " vertices, but " + inputs.back().second + " has " +
                       std::to_string(result.vertexCount()) + " (or other faces)");
    render::ViewerMesh m;
    m.name = inputs[i].first + ": " + std::filesystem::path(inputs[i].second).filename().string();
    m.triangles = meshes[i].triangles;
    m.frames.push_back(meshes[i].positions);
    if (sameVertices) m.outline = outline;
    page.meshes.push_back(std::move(m));
  }
  frameOnRegion(page, meshes, result, region);
}

}  // namespace flexure::reports
