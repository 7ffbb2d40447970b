// flexure modes, shared with flexure demo: the vibration modes of a plate for one or more bending
// energies, the Chladni figure and the report.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/membrane_arguments.h"

namespace flexure::cli {

struct ModesOptions {
  std::string meshFile, family, outputDir;  // the plate: meshFile, or family with n and seed
  int n = 32;
  std::uint64_t seed = 1;
  std::vector<std::string> energies;
  std::optional<double> poisson;
  double stiffness = 1.0;  // k_B
  std::string support = "clamped", clamp, mass = "barycentric", fix, dof = "height";
  MembraneArguments membrane;  // --dof xyz
  double density = 1.0, length = 0.0, scale = 0.1;
  int count = 12, size = 200;
  std::string reference;
  bool writeShapes = false;
};

// Checks every option and reads or generates the plate (InputError, nothing written), computes
// each energy's modes, prints the λ table on stdout, then creates `outputDir` and writes
// modes.json, chladni.png and the mode shapes. Progress on stderr prefixed by `commandName`
// unless quiet.
void runModes(const ModesOptions& options, const GlobalOptions& global,
              const std::string& commandName);

}  // namespace flexure::cli
