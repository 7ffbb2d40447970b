// `flexure converge` and `flexure demo` running a convergence study into a folder: the refusal of a
// study too large for the memory, progress on stderr, then the library's writers
// (reports/study_outputs.h).
#pragma once

#include <string>

#include "cli/commands.h"
#include "optimize/studies/convergence_study.h"
#include "reports/study_outputs.h"

namespace flexure::cli {

using reports::isStudyFile;

// Runs the study (progress on stderr unless quiet: a bar on a terminal, else a line per tenth),
// creates `dir` and writes every output there atomically (reports::writeStudyOutputs); returns
// summary.md's text. The outputs depend only on the options, not on the thread count or the time.
std::string runStudyInto(const optimize::StudyOptions& options, const std::string& dir,
                         const GlobalOptions& global, const std::string& commandName);

}  // namespace flexure::cli
