// What every report writer shares: JSON files, and an output folder that ends a run holding only
// that run's files.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace flexure::reports {

// Writes `json` (2-space indent, trailing newline) to `path` atomically (modeling/atomic_write.h).
void writeJsonFile(const std::string& path, const nlohmann::json& json);

// Schedules for removal, at the open OutputBatch's commit, each regular file in `dir` whose name
// `owned` claims and that the batch has not staged: the files an earlier run wrote there and this
// one did not. Other files are left alone.
void removeStaleOutputs(const std::string& dir,
                        const std::function<bool(const std::string&)>& owned);

}  // namespace flexure::reports
