#include "optimize/studies/spectrum_study.h"

#include <algorithm>
#include <cmath>

#include "curvature/bending_energy.h"
#include "curvature/energy_registry.h"
#include "modeling/errors.h"
#include "modeling/rest_state.h"

namespace flexure::optimize {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

std::vector<double> squarePlateLambdas(Support support, int count) {
  if (support == Support::SimplySupported) {
    std::vector<double> lambdas;
    for (int m = 1; m <= count; ++m)
      for (int k = 1; k <= count; ++k) lambdas.push_back(kPi * kPi * (m * m + k * k));
    std::sort(lambdas.begin(), lambdas.end());
    lambdas.resize(count);
    return lambdas;
  }
  if (support == Support::Clamped) {
    const std::vector<double> leissa = {35.992, 73.413, 73.413, 108.27, 131.64, 132.24};
    if (count > static_cast<int>(leissa.size()))
      throw InputError("the clamped square's reference has " + std::to_string(leissa.size()) +
                       " frequencies (Leissa 1973); ask for at most that many modes");
    return {leissa.begin(), leissa.begin() + count};
  }
  throw InputError("the free square plate has no reference frequencies in flexure");
}

const char* squarePlateSource(Support support) {
  return support == Support::Clamped
             ? "Leissa, The free vibration of rectangular plates, J. Sound Vib. 31(3), 1973 "
               "(the square clamped on all four edges)"
             : "exact: pi^2 (m^2 + n^2)";
}

void SpectrumStudyOptions::validate() const {
  if (energies.empty()) throw InputError("SpectrumStudyOptions.energies: give at least one energy");
  if (families.empty())
    throw InputError("SpectrumStudyOptions.families: give at least one mesh family");
  if (baseN < 4)
    throw InputError("SpectrumStudyOptions.baseN " + std::to_string(baseN) +
                     ": expected at least 4");
  if (levels < 1 || levels > 8)
    throw InputError("SpectrumStudyOptions.levels " + std::to_string(levels) + ": expected 1 .. 8");
  if (count < 1 || count > 12)
    throw InputError("SpectrumStudyOptions.count " + std::to_string(count) + ": expected 1 .. 12");
  if (support == Support::Free)
    throw InputError(
        "SpectrumStudyOptions.support free: the spectrum study needs reference frequencies "
        "(simply-supported or clamped)");
  try {
    squarePlateLambdas(support, count);
  } catch (const InputError& e) {
    throw InputError("SpectrumStudyOptions.count " + std::to_string(count) + ": " + e.what());
  }
  for (const EnergyVariant& v : energies) {
    if (v.normals != BoundaryNormals::Free) continue;
    const std::string& name = curvature::energyEntry(v.bending.discretization).name;
    throw InputError("SpectrumStudyOptions.energies " + v.label + ": " + name +
                     "'s boundary normals follow SpectrumStudyOptions.support; give " + name);
  }
}

std::vector<EnergyVariant> defaultSpectrumEnergies(std::optional<double> poisson) {
  std::vector<const curvature::EnergyEntry*> ranked;
  for (const curvature::EnergyEntry& e : curvature::registeredEnergies())
    if (e.spectrumRank) ranked.push_back(&e);
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto* a, const auto* b) {
    return *a->spectrumRank < *b->spectrumRank;
  });
  std::vector<EnergyVariant> variants;
  for (const curvature::EnergyEntry* e : ranked)
    variants.push_back(parseEnergyVariant(e->name, poisson));
  return variants;
}

std::string spectrumLabel(const EnergyVariant& variant) {
  const curvature::EnergyEntry& entry = curvature::energyEntry(variant.bending.discretization);
  return entry.hasEdgeUnknowns() && variant.normals == BoundaryNormals::Clamped ? entry.name
                                                                                : variant.label;
}

std::vector<SpectrumSeries> runSpectrumStudy(
    const SpectrumStudyOptions& o, const std::function<void(const std::string&)>& progress) {
  o.validate();
  const std::vector<double> reference = squarePlateLambdas(o.support, o.count);
  std::vector<SpectrumSeries> all;
  for (int e = 0; e < static_cast<int>(o.energies.size()); ++e) {
    const EnergyVariant& variant = o.energies[e];
    // An energy with edge unknowns (midedge's ξ) clamps by its boundary normals.
    const bool midedge = curvature::energyEntry(variant.bending.discretization).hasEdgeUnknowns();
    for (const modeling::MeshFamily family : o.families) {
      std::vector<std::optional<std::uint64_t>> seeds = {std::nullopt};
      if (family == modeling::MeshFamily::Delaunay) seeds.assign(o.seeds.begin(), o.seeds.end());
      for (const auto& seed : seeds) {
        SpectrumSeries series;
        series.energy = e;
        series.family = std::string(modeling::meshFamilyName(family));
        series.seed = seed;
        series.clamp = midedge ? Clamp::Normals : Clamp::Rings;
        const std::vector<modeling::Mesh> meshes =
            modeling::refinementSequence({family, o.baseN, seed.value_or(1), {}}, o.levels);
        for (int level = 0; level < o.levels; ++level) {
          const modeling::Stencils stencils = modeling::compileStencils(meshes[level]);
          const modeling::RestState rest =
              modeling::precomputeRestState(stencils, meshes[level].positions);
          const auto term = curvature::makeBendingEnergy(stencils, rest, variant.bending);
          const Eigen::VectorXd restXi =
              midedge ? curvature::restEdgeUnknowns(stencils, rest, variant.bending)
                      : Eigen::VectorXd();
          ModesOptions modes;
          modes.count = o.count;
          modes.support = o.support;
          modes.clamp = series.clamp;
          const ModesResult result = vibrationModes({term.get()}, stencils, rest, restXi, modes);
          std::vector<double> lambdas, errors;
          for (const VibrationMode& mode : result.modes) {
            if (mode.zero) continue;
            errors.push_back(std::abs(mode.lambda / reference[lambdas.size()] - 1.0));
            lambdas.push_back(mode.lambda);
          }
          if (static_cast<int>(lambdas.size()) < o.count)
            throw NumericalError(variant.label + " on " + series.family + ": " +
                                 std::to_string(result.spuriousZeroModes) +
                                 " spurious zero modes took the place of flexible ones");
          series.n.push_back(o.baseN << level);
          series.h.push_back(1.0 / series.n.back());
          series.lambdas.push_back(lambdas);
          series.errors.push_back(errors);
          if (progress)
            progress(variant.label + " on " + series.family +
                     (seed ? " seed " + std::to_string(*seed) : "") +
                     " n=" + std::to_string(series.n.back()));
        }
        for (int k = 0; k < o.count; ++k) {
          std::vector<double> modeErrors;
          for (const auto& level : series.errors) modeErrors.push_back(level[k]);
          series.verdicts.push_back(classifyRefinement(modeErrors));
          series.orders.push_back(seriesOrder(series.h, modeErrors, series.verdicts.back()));
        }
        all.push_back(std::move(series));
      }
    }
  }
  return all;
}

}  // namespace flexure::optimize
