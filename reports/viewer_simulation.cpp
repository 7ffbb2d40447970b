#include "reports/viewer_simulation.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "modeling/errors.h"
#include "optimize/assembly/obstacles.h"

namespace flexure::reports {

void addSimulationObstacles(render::ViewerMesh& mesh, const std::string& dir) {
  const std::string path = (std::filesystem::path(dir) / "report.json").string();
  std::ifstream file(path);
  if (!file) return;
  const nlohmann::json report = nlohmann::json::parse(file, nullptr, false);
  if (report.is_discarded() || !report.is_object() || !report.contains("obstacles") ||
      !report["obstacles"].is_array())
    return;
  for (const nlohmann::json& entry : report["obstacles"]) {
    if (!entry.is_string())
      throw InputError(path + ": an obstacle " + entry.dump() + " is no text");
    const optimize::Obstacle o = optimize::parseObstacle(path, entry.get<std::string>());
    if (o.kind == optimize::Obstacle::Kind::Sphere)
      mesh.spheres.push_back({o.vector, o.scalar});
    else
      mesh.planes.push_back({o.vector, o.scalar});
  }
}

}  // namespace flexure::reports
