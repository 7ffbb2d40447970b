#include "cli/mesh_json.h"

#include "modeling/atomic_write.h"

namespace flexure::cli {
namespace {

nlohmann::json histogram(const std::map<int, int>& valences) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [valence, count] : valences) out[std::to_string(valence)] = count;
  return out;
}

}  // namespace

nlohmann::json meshInfoJson(const modeling::MeshInfo& info) {
  return {
      {"vertices", info.vertices},
      {"faces", info.faces},
      {"edges", info.edges},
      {"components", info.components},
      {"euler_characteristic", info.eulerCharacteristic},
      {"boundary_loops", info.boundaryLoopLengths},
      {"valence_histogram",
       {{"interior", histogram(info.interiorValences)},
        {"boundary", histogram(info.boundaryValences)}}},
      {"edge_length",
       {{"min", info.minEdgeLength}, {"mean", info.meanEdgeLength}, {"max", info.maxEdgeLength}}},
      {"area", info.area},
      {"bounding_box",
       {{"min", {info.boxMin.x(), info.boxMin.y(), info.boxMin.z()}},
        {"max", {info.boxMax.x(), info.boxMax.y(), info.boxMax.z()}}}},
  };
}

nlohmann::json meshCheckJson(const modeling::MeshCheck& check) {
  nlohmann::json problems = nlohmann::json::array();
  for (const auto& p : check.problems) {
    problems.push_back({{"kind", modeling::meshProblemName(p.kind)},
                        {"element", p.element},
                        {"reason", p.reason}});
  }
  nlohmann::json counts = nlohmann::json::object();
  for (size_t k = 0; k < check.problemCounts.size(); ++k) {
    if (check.problemCounts[k] > 0) {
      counts[std::string(modeling::meshProblemName(static_cast<modeling::MeshProblemKind>(k)))] =
          check.problemCounts[k];
    }
  }
  return {{"valid", check.valid()}, {"problem_counts", counts}, {"problems", problems}};
}

void writeFailureReport(const std::string& path, const nlohmann::json& json) {
  modeling::writeFileNow(path, json.dump(2) + "\n");
}

std::string counted(long long n, const std::string& singular, const std::string& plural) {
  if (n == 1) return "1 " + singular;
  if (!plural.empty()) return std::to_string(n) + " " + plural;
  return std::to_string(n) + " " + (singular == "vertex" ? "vertices" : singular + "s");
}

void writeJsonFile(const std::string& path, const nlohmann::json& json) {
  modeling::writeFileAtomically(path, json.dump(2) + "\n");
}

}  // namespace flexure::cli
