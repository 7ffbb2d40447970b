// `flexure converge --measure modes` running the spectrum study into a folder: progress on stderr,
// then the library's writers (reports/spectrum_outputs.h).
#pragma once

#include <string>

#include "cli/commands.h"
#include "optimize/studies/spectrum_study.h"
#include "reports/spectrum_outputs.h"

namespace flexure::cli {

using reports::isSpectrumFile;

// Runs the study (a line per solve on stderr unless quiet), creates `dir` and writes the outputs
// (reports::writeSpectrumOutputs); returns spectrum.md's text.
std::string runSpectrumStudyInto(const optimize::SpectrumStudyOptions& options,
                                 const std::string& dir, const GlobalOptions& global,
                                 const std::string& commandName);

}  // namespace flexure::cli
