// JSON views of modeling results shared by the commands (info, demo).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "modeling/mesh_check.h"
#include "modeling/mesh_info.h"

namespace flexure::cli {

nlohmann::json meshInfoJson(const modeling::MeshInfo& info);
nlohmann::json meshCheckJson(const modeling::MeshCheck& check);

// Writes `json` (2-space indent, trailing newline) to `path` atomically; staged with the run's
// other outputs (modeling::OutputBatch).
void writeJsonFile(const std::string& path, const nlohmann::json& json);
// As writeJsonFile, but at once: the report of a run that fails (exit 3) says why, so it outlives
// the failure that removes the run's other outputs.
void writeFailureReport(const std::string& path, const nlohmann::json& json);

// "1 iteration", "3 iterations", "2 vertices"; `plural` defaults to `singular` + "s" ("vertices"
// for "vertex").
std::string counted(long long n, const std::string& singular, const std::string& plural = "");

}  // namespace flexure::cli
