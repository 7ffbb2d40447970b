#include "reports/output_files.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "modeling/atomic_write.h"

namespace flexure::reports {

void writeJsonFile(const std::string& path, const nlohmann::json& json) {
  modeling::writeFileAtomically(path, json.dump(2) + "\n");
}

void removeStaleOutputs(const std::string& dir,
                        const std::function<bool(const std::string&)>& owned) {
  namespace fs = std::filesystem;
  std::vector<fs::path> written;
  for (const std::string& target : modeling::stagedOutputs())
    written.push_back(fs::weakly_canonical(target));
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec) || !owned(entry.path().filename().string())) continue;
    if (std::find(written.begin(), written.end(), fs::weakly_canonical(entry.path())) ==
        written.end())
      modeling::removeWhenCommitted(entry.path().string());
  }
}

}  // namespace flexure::reports
