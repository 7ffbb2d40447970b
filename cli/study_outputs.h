// The outputs of a convergence study, shared by `flexure converge` and `flexure demo`: results.json
// (every record, the refinement fits and the summary), results.csv (one row per solve),
// summary.md (the spec's table computed live, plus the orders) and log-log plots (PNG).
#pragma once

#include <string>
#include <vector>

#include "cli/commands.h"
#include "optimize/studies/convergence_study.h"

namespace flexure::cli {

// The files runStudyInto writes: results.json, results.csv, summary.md and the plots
// (c2_*.png, refinement_*.png, refinement_energy_*.png, nonlinear_c2_*.png).
bool isStudyFile(const std::string& name);

// Runs the study (progress on stderr unless quiet: a bar on a terminal, else a line per tenth),
// creates `dir` and writes every output there atomically; returns summary.md's text. The
// outputs depend only on the options, not on the thread count or the time.
std::string runStudyInto(const optimize::StudyOptions& options, const std::string& dir,
                         const GlobalOptions& global, const std::string& commandName);

}  // namespace flexure::cli
