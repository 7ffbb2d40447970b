#include "reports/spectrum_outputs.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "curvature/energy_registry.h"
#include "modeling/atomic_write.h"
#include "render/plot.h"
#include "reports/output_files.h"

namespace flexure::reports {
namespace {

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

std::string seriesName(const optimize::SpectrumSeries& s) {
  return s.family + (s.seed ? " seed " + std::to_string(*s.seed) : "");
}

// The largest error over the modes at each level.
std::vector<double> worstErrors(const optimize::SpectrumSeries& s) {
  std::vector<double> worst;
  for (const auto& level : s.errors) worst.push_back(*std::max_element(level.begin(), level.end()));
  return worst;
}

// How the clamped square is clamped: energies with edge unknowns by their normals, the others by
// rings 0 and 1 (vibration_modes.h).
std::string clampSentence() {
  const auto& energies = curvature::registeredEnergies();
  const auto edgeUnknowns = [](const curvature::EnergyEntry& e) { return e.hasEdgeUnknowns(); };
  const std::string names = curvature::energyNamesWhere(edgeUnknowns, ", ", " and ");
  const bool one = std::count_if(energies.begin(), energies.end(), edgeUnknowns) == 1;
  return "; " + names + (one ? " clamps its" : " clamp their") +
         " normals, the other energies rings 0 and 1";
}

std::string summaryText(const optimize::SpectrumStudyOptions& o,
                        const std::vector<optimize::SpectrumSeries>& all) {
  const std::vector<double> reference = optimize::squarePlateLambdas(o.support, o.count);
  std::ostringstream md;
  md << "# Vibration spectrum of the " << optimize::supportName(o.support) << " square\n\n"
     << "λ₁ … λ" << o.count << " = ω L² √(ρh/D) against " << optimize::squarePlateSource(o.support)
     << "; n = " << o.baseN << " … " << (o.baseN << (o.levels - 1))
     << (o.support == optimize::Support::Clamped ? clampSentence() : "") << ".\n\n"
     << "Each cell: the smallest order over the modes (least-squares slope of |λ/λ_ref − 1| in h)"
     << " and the largest error at the finest level; \"does not converge\" when any mode's "
        "error stalls.\n\n| energy |";
  std::vector<std::string> columns;
  for (const auto& s : all)
    if (std::find(columns.begin(), columns.end(), seriesName(s)) == columns.end())
      columns.push_back(seriesName(s));
  for (const std::string& c : columns) md << ' ' << c << " |";
  md << "\n|---|";
  for (size_t k = 0; k < columns.size(); ++k) md << "---|";
  md << '\n';
  for (size_t e = 0; e < o.energies.size(); ++e) {
    md << "| " << o.energies[e].label << " |";
    for (const std::string& c : columns) {
      for (const auto& s : all) {
        if (s.energy != static_cast<int>(e) || seriesName(s) != c) continue;
        bool stalls = false;
        std::optional<double> smallest;
        for (size_t k = 0; k < s.orders.size(); ++k) {
          stalls = stalls || s.verdicts[k] == optimize::Refinement::DoesNotConverge;
          if (s.orders[k]) smallest = std::min(smallest.value_or(*s.orders[k]), *s.orders[k]);
        }
        const double finest = worstErrors(s).back();
        md << ' '
           << (stalls     ? std::string("does not converge")
               : smallest ? "order " + format("%.2f", *smallest)
                          : std::string("-"))
           << ", " << format("%.1e", finest) << " |";
      }
    }
    md << '\n';
  }
  md << "\nThe finest level's λ against the reference:\n\n| energy | mesh |";
  for (int k = 0; k < o.count; ++k) md << " λ" << k + 1 << " |";
  md << "\n|---|---|";
  for (int k = 0; k < o.count; ++k) md << "---|";
  md << "\n| reference | |";
  for (double r : reference) md << ' ' << format("%.3f", r) << " |";
  md << '\n';
  for (const auto& s : all) {
    md << "| " << o.energies[s.energy].label << " | " << seriesName(s) << " n=" << s.n.back()
       << " |";
    for (double lambda : s.lambdas.back()) md << ' ' << format("%.3f", lambda) << " |";
    md << '\n';
  }
  return md.str();
}

// One plot per family: each energy's largest error over the modes against h.
render::LogLogPlot familyPlot(const optimize::SpectrumStudyOptions& o,
                              const std::vector<optimize::SpectrumSeries>& all,
                              const std::string& family) {
  render::LogLogPlot plot;
  plot.title =
      std::string("Vibration spectrum, ") + optimize::supportName(o.support) + " square, " + family;
  plot.xLabel = "h = 1/n";
  plot.yLabel = "max over λ1..λ" + std::to_string(o.count) + " of |λ/λ_ref − 1|";
  plot.referenceSlopes = {{1.0, "slope 1"}, {2.0, "slope 2"}};
  for (const auto& s : all) {
    if (s.family != family) continue;
    const std::vector<double> worst = worstErrors(s);
    const optimize::Refinement verdict = optimize::classifyRefinement(worst);
    const auto order = optimize::seriesOrder(s.h, worst, verdict);
    plot.series.push_back({o.energies[s.energy].label +
                               (s.seed ? " seed " + std::to_string(*s.seed) : "") +
                               (order ? " (" + format("%.2f", *order) + ")" : ""),
                           s.h, worst});
  }
  return plot;
}

}  // namespace

bool isSpectrumFile(const std::string& name) {
  if (name == "spectrum.md" || name == "spectrum.json" || name == "spectrum.csv") return true;
  return name.rfind("spectrum_", 0) == 0 && name.size() > 4 &&
         name.compare(name.size() - 4, 4, ".png") == 0;
}

std::vector<optimize::EnergyVariant> spectrumEnergies(std::vector<optimize::EnergyVariant> chosen,
                                                      std::optional<double> poisson) {
  if (chosen.empty()) chosen = optimize::defaultSpectrumEnergies(poisson);
  for (optimize::EnergyVariant& v : chosen) v.label = optimize::spectrumLabel(v);
  return chosen;
}

nlohmann::json spectrumJson(const optimize::SpectrumStudyOptions& o,
                            const std::vector<optimize::SpectrumSeries>& all) {
  nlohmann::json series = nlohmann::json::array();
  for (const auto& s : all) {
    nlohmann::json orders = nlohmann::json::array();
    for (const auto& order : s.orders) orders.push_back(order ? nlohmann::json(*order) : nullptr);
    std::vector<std::string> verdicts;
    for (const auto v : s.verdicts) verdicts.emplace_back(optimize::refinementName(v));
    series.push_back({{"energy", o.energies[s.energy].label},
                      {"family", s.family},
                      {"seed", s.seed ? nlohmann::json(*s.seed) : nullptr},
                      {"clamp", o.support == optimize::Support::Clamped
                                    ? nlohmann::json(optimize::clampName(s.clamp))
                                    : nullptr},
                      {"n", s.n},
                      {"h", s.h},
                      {"lambda", s.lambdas},
                      {"relative_error", s.errors},
                      {"order", orders},
                      {"verdict", verdicts}});
  }
  return {{"support", optimize::supportName(o.support)},
          {"count", o.count},
          {"reference", optimize::squarePlateLambdas(o.support, o.count)},
          {"reference_source", optimize::squarePlateSource(o.support)},
          {"lambda", "omega L^2 sqrt(rho h / D), D = 2 k_B"},
          {"series", series}};
}

std::string spectrumCsv(const optimize::SpectrumStudyOptions& o,
                        const std::vector<optimize::SpectrumSeries>& all) {
  const std::vector<double> reference = optimize::squarePlateLambdas(o.support, o.count);
  std::ostringstream csv;
  csv << "energy,family,seed,n,h,mode,lambda,reference,relative_error\n";
  for (const auto& s : all)
    for (size_t level = 0; level < s.n.size(); ++level)
      for (int k = 0; k < o.count; ++k)
        csv << o.energies[s.energy].label << ',' << s.family << ','
            << (s.seed ? std::to_string(*s.seed) : "") << ',' << s.n[level] << ','
            << format("%.17g", s.h[level]) << ',' << k + 1 << ','
            << format("%.17g", s.lambdas[level][k]) << ',' << format("%.17g", reference[k]) << ','
            << format("%.17g", s.errors[level][k]) << '\n';
  return csv.str();
}

std::string spectrumMarkdown(const optimize::SpectrumStudyOptions& options,
                             const std::vector<optimize::SpectrumSeries>& series) {
  return summaryText(options, series);
}

std::string writeSpectrumOutputs(const optimize::SpectrumStudyOptions& o,
                                 const std::vector<optimize::SpectrumSeries>& all,
                                 const std::string& dir) {
  const std::filesystem::path out(dir);
  modeling::createOutputDirectory(out.string());
  writeJsonFile((out / "spectrum.json").string(), spectrumJson(o, all));
  modeling::writeFileAtomically((out / "spectrum.csv").string(), spectrumCsv(o, all));
  std::vector<std::string> families;
  for (const auto& s : all)
    if (std::find(families.begin(), families.end(), s.family) == families.end())
      families.push_back(s.family);
  for (const std::string& family : families)
    render::writeLogLogPlot(familyPlot(o, all, family),
                            (out / ("spectrum_" + family + ".png")).string());
  const std::string summary = summaryText(o, all);
  modeling::writeFileAtomically((out / "spectrum.md").string(), summary);
  return summary;
}

}  // namespace flexure::reports
