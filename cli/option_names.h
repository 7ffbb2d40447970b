// The library names an option by its field ("MinimizeOptions.maxIterations"), never by a flag:
// only cli/ knows flags. Every message the library hands the user passes through
// withFlagNames, which rewrites each field it knows into the flag the user typed.
#pragma once

#include <string>

namespace flexure::cli {

// `message` with every known "Struct.field" replaced by its flag ("--max-iterations").
std::string withFlagNames(std::string message);

}  // namespace flexure::cli
