// JSON views of modeling results shared by the commands (info, demo).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "modeling/mesh_check.h"
#include "modeling/mesh_info.h"

namespace flexure::cli {

nlohmann::json meshInfoJson(const modeling::MeshInfo& info);
nlohmann::json meshCheckJson(const modeling::MeshCheck& check);

// Writes `json` (2-space indent, trailing newline) to `path` atomically.
void writeJsonFile(const std::string& path, const nlohmann::json& json);

}  // namespace flexure::cli
