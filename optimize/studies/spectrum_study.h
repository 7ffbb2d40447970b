// The spectrum as a convergence test (the convergence command's modes measure): the smallest
// vibration frequencies λ₁ … λ_K of the square plate (vibration_modes.h) on every energy and mesh
// family over refinement levels n, 2n, 4n, …, their errors against the exact or tabulated
// values, and the orders of those errors in h = 1/n.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "modeling/generators.h"
#include "optimize/modes/vibration_modes.h"
#include "optimize/studies/convergence_study.h"

namespace flexure::optimize {

// λ = ω L² √(ρh/D) of the square plate of side L, ascending. SimplySupported: π²(m² + n²), m, n ≥
// 1, exact for any ν. Clamped: Leissa, "The free vibration of rectangular plates", J. Sound Vib.
// 31(3), 1973, the square clamped on all four edges (ν-independent) — the first six.
// Throws InputError for Free, or for more clamped modes than are tabulated.
std::vector<double> squarePlateLambdas(Support support, int count);
const char* squarePlateSource(Support support);

struct SpectrumStudyOptions {
  std::vector<EnergyVariant> energies;  // midedge clamps its normals, the others by rings
  std::vector<modeling::MeshFamily> families = {modeling::MeshFamily::Patch48,
                                                modeling::MeshFamily::Delaunay};
  std::vector<std::uint64_t> seeds = {1};  // delaunay: one mesh sequence per seed
  int baseN = 8, levels = 3;
  int count = 6;  // modes λ₁ … λ_K
  Support support = Support::SimplySupported;

  // Throws InputError naming the field for an unusable study (no energies or families, baseN < 4,
  // levels outside 1..8, count outside 1..12 or beyond the reference, a free support,
  // midedge:free) before any work.
  void validate() const;
};

// The study's default energies: every registered energy with a spectrum rank (energy_registry.h)
// once, with its default options (ν = `poisson` where it takes one), sorted by that rank.
std::vector<EnergyVariant> defaultSpectrumEnergies(std::optional<double> poisson = {});
// What the study's tables call `variant`: its label, except for an energy with edge unknowns
// (midedge's ξ), whose boundary normals follow the support here rather than the variant's
// clamped/free: its plain name ("midedge", not "midedge(clamped)").
std::string spectrumLabel(const EnergyVariant& variant);

// One energy on one mesh sequence.
struct SpectrumSeries {
  int energy = 0;  // index into SpectrumStudyOptions::energies
  std::string family;
  std::optional<std::uint64_t> seed;
  Clamp clamp = Clamp::Rings;  // used when clamped
  std::vector<int> n;
  std::vector<double> h;
  std::vector<std::vector<double>> lambdas, errors;  // [level][k]; errors |λ/λ_ref − 1|
  std::vector<std::optional<double>> orders;         // [k]: seriesOrder of mode k's errors
  std::vector<Refinement> verdicts;                  // [k]
};

// Energy-major, then family, seed; validates `options` first. `progress` (may be empty) gets
// "<energy> on <family> n=<n>" after each solve.
std::vector<SpectrumSeries> runSpectrumStudy(
    const SpectrumStudyOptions& options,
    const std::function<void(const std::string&)>& progress = {});

}  // namespace flexure::optimize
