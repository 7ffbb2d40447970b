// The outputs of a convergence study (optimize/studies/convergence_study.h), shared by the
// command-line tool and the Python module: results.json (every record, the refinement fits and the
// summary), results.csv (one row per solve), summary.md (the spec's table computed live, plus the
// orders) and log-log plots (PNG). Fixed number formats: the text outputs depend only on the
// options, not on the thread count or the time.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "optimize/studies/convergence_study.h"

namespace flexure::reports {

// Whether `name` is a file writeStudyOutputs writes: results.json, results.csv, summary.md and
// the plots (c2_*.png, refinement_*.png, refinement_energy_*.png, nonlinear_c2_*.png).
bool isStudyFile(const std::string& name);

// results.json: {"study": the options, "records": one per record, "refinement": the fits,
// "summary": the energy × family table}.
nlohmann::json studyResultsJson(const optimize::StudyOptions& options,
                                const optimize::StudyResults& results,
                                const optimize::StudySummary& summary);

// The text tables: results.csv and summary.md (which links the plots writeStudyOutputs writes).
std::string studyResultsCsv(const optimize::StudyOptions& options,
                            const optimize::StudyResults& results);
std::string studySummaryMarkdown(const optimize::StudyOptions& options,
                                 const optimize::StudyResults& results,
                                 const optimize::StudySummary& summary);

// Creates `dir` and writes results.json, results.csv, summary.md and the plots there, each
// atomically (staged in the open modeling::OutputBatch, if any); returns summary.md's text.
// Throws InputError naming the path that cannot be written.
std::string writeStudyOutputs(const optimize::StudyOptions& options,
                              const optimize::StudyResults& results,
                              const optimize::StudySummary& summary, const std::string& dir);

}  // namespace flexure::reports
