// Outputs are written to a temporary file next to the target and renamed over it, so a failed
// run never leaves a half-written mesh, image or report.
#pragma once

#include <string>
#include <string_view>

namespace flexure::modeling {

// Writes `bytes` to `path` atomically. Throws InputError naming the path when the directory does
// not exist or is not writable; the target is untouched on failure.
void writeFileAtomically(const std::string& path, std::string_view bytes);

}  // namespace flexure::modeling
