// A convergence study run in parts — one energy each, e.g. as the cases of a Dask sweep — and
// joined back into the study a single run makes: the parts' results.json read back into records
// and refinement fits, then concatenated in the study's energy order, so the joined tables equal
// a local run's (records are energy-major; results.json keeps every double to the last bit).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "optimize/studies/convergence_study.h"

namespace flexure::reports {

// The records and refinement fits of `results` (a results.json written by writeStudyOutputs for a
// study whose energies all appear, by label, in `options.energies`; each record's energy index
// is the first with its label). Throws InputError naming `where` and the field that is missing,
// of the wrong type, or an energy label not in `options`.
optimize::StudyResults studyResultsFromJson(const nlohmann::json& results,
                                            const optimize::StudyOptions& options,
                                            const std::string& where);

// The study of `parts`, part k being the study of energy k alone: its records and fits, energy
// index set to k, concatenated in part order (the order runConvergenceStudy produces).
optimize::StudyResults joinStudyParts(std::vector<optimize::StudyResults> parts);

}  // namespace flexure::reports
