// The command-line names of the vibration-mode choices (optimize/modes/vibration_modes.h):
// --support,
// --clamp, --mass. The library names them back with supportName, clampName, massLumpingName.
#pragma once

#include <string>

#include "optimize/modes/vibration_modes.h"

namespace flexure::cli {

// "clamped" | "simply-supported" | "free"; "rings" | "normals"; "barycentric" | "voronoi".
// InputError naming the flag and listing the names otherwise.
optimize::Support parseSupport(const std::string& name);
optimize::Clamp parseClamp(const std::string& name);
optimize::MassLumping parseMassLumping(const std::string& name);

}  // namespace flexure::cli
