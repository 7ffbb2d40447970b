// The outputs of the spectrum study (optimize/studies/spectrum_study.h), shared by the
// command-line tool and the Python module: spectrum.md (the orders and finest errors per energy
// and family), spectrum.json (every λ of every level), spectrum.csv (one row per energy, mesh,
// level and mode) and log-log plots spectrum_<family>.png (each energy's largest error over
// λ₁ … λ_K against h).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "optimize/studies/spectrum_study.h"

namespace flexure::reports {

// Whether `name` is a file writeSpectrumOutputs writes.
bool isSpectrumFile(const std::string& name);

// The spectrum study's energies: `chosen`, or when empty optimize::defaultSpectrumEnergies (ν =
// `poisson` where they take one), each labelled by optimize::spectrumLabel (midedge's normals
// follow the support in this study, not the variant's clamped/free: plain "midedge").
std::vector<optimize::EnergyVariant> spectrumEnergies(std::vector<optimize::EnergyVariant> chosen,
                                                      std::optional<double> poisson);

// spectrum.json: {"support", "count", "reference" (λ_ref), "reference_source", "lambda" (its
// definition), "series": one per energy and mesh sequence}.
nlohmann::json spectrumJson(const optimize::SpectrumStudyOptions& options,
                            const std::vector<optimize::SpectrumSeries>& series);

// The text tables: spectrum.csv and spectrum.md.
std::string spectrumCsv(const optimize::SpectrumStudyOptions& options,
                        const std::vector<optimize::SpectrumSeries>& series);
std::string spectrumMarkdown(const optimize::SpectrumStudyOptions& options,
                             const std::vector<optimize::SpectrumSeries>& series);

// Creates `dir` and writes spectrum.json, spectrum.csv, the plots and spectrum.md there, each
// atomically (staged in the open modeling::OutputBatch, if any); returns spectrum.md's text.
std::string writeSpectrumOutputs(const optimize::SpectrumStudyOptions& options,
                                 const std::vector<optimize::SpectrumSeries>& series,
                                 const std::string& dir);

}  // namespace flexure::reports
