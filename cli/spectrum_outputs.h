// The outputs of `flexure converge --measure modes` (optimize/studies/spectrum_study.h):
// spectrum.md (the orders and finest errors per energy and family, also printed), spectrum.json
// (every λ of every level), spectrum.csv (one row per energy, mesh, level and mode) and log-log
// plots spectrum_<family>.png (each energy's largest error over λ₁ … λ_K against h).
#pragma once

#include <string>

#include "cli/commands.h"
#include "optimize/studies/spectrum_study.h"

namespace flexure::cli {

// Whether `name` is a file runSpectrumStudyInto writes.
bool isSpectrumFile(const std::string& name);

// Runs the study (a line per solve on stderr unless quiet), creates `dir` and writes the outputs;
// returns spectrum.md's text.
std::string runSpectrumStudyInto(const optimize::SpectrumStudyOptions& options,
                                 const std::string& dir, const GlobalOptions& global,
                                 const std::string& commandName);

}  // namespace flexure::cli
