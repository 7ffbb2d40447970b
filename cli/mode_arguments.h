// The command-line names of the vibration-mode choices (optimize/modes/vibration_modes.h):
// --support,
// --clamp (--mass: modeling::parseMassLumping). The library names them back with supportName,
// clampName.
#pragma once

#include <string>

#include "optimize/modes/vibration_modes.h"

namespace flexure::cli {

// "clamped" | "simply-supported" | "free"; "rings" | "normals".
// InputError naming the flag and listing the names otherwise.
optimize::Support parseSupport(const std::string& name);
optimize::Clamp parseClamp(const std::string& name);

}  // namespace flexure::cli
