#include "reports/study_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <utility>

#include "curvature/bending_spec.h"
#include "curvature/energy_registry.h"
#include "modeling/atomic_write.h"
#include "render/plot.h"
#include "reports/output_files.h"

namespace flexure::reports {
namespace {

using optimize::RecordKind;
using optimize::Refinement;
using optimize::StudyOptions;
using optimize::StudyRecord;
using optimize::StudyResults;
using optimize::StudySummary;

// Fixed formats keep the text outputs byte-identical from run to run.
std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}
std::string scientific(double value) {
  return format("%.1e", value);
}
std::string order(double value) {
  return format("%.2f", value);
}

// "1/2", "1/4", … for ε = 2⁻ᵏ.
std::string amplitudeText(double eps) {
  return "1/" + std::to_string(static_cast<long long>(std::llround(1.0 / eps)));
}

nlohmann::json optional(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::string normalsName(optimize::BoundaryNormals normals) {
  return normals == optimize::BoundaryNormals::Free ? "free" : "clamped";
}

nlohmann::json energyJson(const optimize::EnergyVariant& v) {
  const curvature::EnergyEntry& entry = curvature::energyEntry(v.bending.discretization);
  nlohmann::json j = {
      {"label", v.label},
      {"energy", std::string(curvature::discretizationName(v.bending.discretization))},
      {"poisson", curvature::effectivePoisson(v.bending)},
      {"stiffness", v.bending.stiffness}};
  if (entry.readsVertexArea) j["vertex_area"] = curvature::vertexAreaName(v.bending.vertexArea);
  if (entry.readsHingeAngle) j["hinge_angle"] = curvature::hingeAngleName(v.bending.hingeAngle);
  if (entry.restEdgeUnknowns) j["boundary_normals"] = normalsName(v.normals);
  return j;
}

nlohmann::json recordJson(const StudyOptions& o, const StudyRecord& r) {
  nlohmann::json j = {
      {"kind", std::string(optimize::recordKindName(r.kind))},
      {"energy", o.energies[r.energy].label},
      {"options", energyJson(o.energies[r.energy])},
      {"family", r.family},
      {"seed", r.seed ? nlohmann::json(*r.seed) : nlohmann::json(nullptr)},
      {"n", r.n ? nlohmann::json(*r.n) : nlohmann::json(nullptr)},
      {"level", r.level},
      {"h", r.h},
      {"vertices", r.vertices},
      {"free_vertices", r.freeVertices},
      {"factorizations", r.factorizations},
  };
  switch (r.kind) {
    case RecordKind::Quadratic:
      j["quadratic"] = r.data;
      j["energy_per_area"] = optional(r.energyPerArea);
      j["density"] = optional(r.density);
      j["c1"] = optional(r.c1Error);
      j["c1_verdict"] = r.c1Error ? nlohmann::json(std::string(optimize::reproductionName(
                                        optimize::classifyReproduction(*r.c1Error))))
                                  : nlohmann::json(nullptr);
      j["c2"] = r.c2Error;
      j["c2_verdict"] =
          std::string(optimize::reproductionName(optimize::classifyReproduction(r.c2Error)));
      break;
    case RecordKind::NonlinearC2:
      j["quadratic"] = r.data;
      j["amplitudes"] = r.nonlinear.amplitudes;
      j["errors"] = r.nonlinear.errors;
      j["order"] = optional(r.nonlinear.order);
      j["converged"] = r.nonlinear.converged;
      break;
    case RecordKind::Refinement:
      j["solution"] = r.data;
      j["error"] = r.solutionError;
      j["discrete_energy"] = r.discreteEnergy;
      j["exact_energy"] = r.exactEnergy;
      j["energy_error"] = r.energyError;
      j["order"] = optional(r.order);
      j["energy_order"] = optional(r.energyOrder);
      j["verdict"] = std::string(optimize::refinementName(r.verdict));
      j["energy_verdict"] = std::string(optimize::refinementName(r.energyVerdict));
      break;
  }
  return j;
}

nlohmann::json resultsJson(const StudyOptions& o, const StudyResults& results,
                           const StudySummary& summary) {
  nlohmann::json energies = nlohmann::json::array();
  for (const auto& v : o.energies) energies.push_back(energyJson(v));
  nlohmann::json families = nlohmann::json::array(), meshes = nlohmann::json::array(),
                 quadratics = nlohmann::json::array();
  for (const auto f : o.families) families.push_back(std::string(modeling::meshFamilyName(f)));
  for (const auto& m : o.userMeshes) meshes.push_back(m.name);
  for (const auto& q : o.quadratics) quadratics.push_back(q.surface().spec());
  const nlohmann::json study = {
      {"energies", energies},
      {"families", families},
      {"seeds", o.seeds},
      {"meshes", meshes},
      {"n", o.baseN},
      {"levels", o.levels},
      {"quadratics", quadratics},
      {"amplitudes", o.amplitudes},
      {"solver", optimize::solverName(o.solver)},
      {"solution", o.solution.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.solution)},
      {"thresholds",
       {{"pass", optimize::kReproductionPass},
        {"fail", optimize::kReproductionFail},
        {"stall_ratio", optimize::kStallRatio}}}};

  nlohmann::json records = nlohmann::json::array();
  for (const StudyRecord& r : results.records) records.push_back(recordJson(o, r));
  nlohmann::json fits = nlohmann::json::array();
  for (const optimize::RefinementFit& f : results.refinements) {
    fits.push_back({{"energy", o.energies[f.energy].label},
                    {"family", f.family},
                    {"seed", f.seed ? nlohmann::json(*f.seed) : nlohmann::json(nullptr)},
                    {"n", f.n},
                    {"h", f.h},
                    {"errors", f.solutionErrors},
                    {"energy_errors", f.energyErrors},
                    {"order", optional(f.order)},
                    {"energy_order", optional(f.energyOrder)},
                    {"verdict", std::string(optimize::refinementName(f.verdict))},
                    {"energy_verdict", std::string(optimize::refinementName(f.energyVerdict))}});
  }
  nlohmann::json table = nlohmann::json::array();
  for (size_t e = 0; e < summary.energies.size(); ++e) {
    for (size_t f = 0; f < summary.families.size(); ++f) {
      const optimize::SummaryCell& c = summary.cells[e][f];
      table.push_back(
          {{"energy", summary.energies[e]},
           {"family", summary.families[f]},
           {"c1", optional(c.worstC1)},
           {"c1_verdict", c.c1 ? nlohmann::json(std::string(optimize::reproductionName(*c.c1)))
                               : nlohmann::json(nullptr)},
           {"c2", c.worstC2},
           {"c2_verdict", std::string(optimize::reproductionName(c.c2))},
           {"nonlinear_c2_order", optional(c.nonlinearOrder)},
           {"nonlinear_converged", c.nonlinearConverged},
           {"refinement_order", optional(c.refinementOrder)},
           {"refinement_verdict", std::string(optimize::refinementName(c.refinement))},
           {"energy_order", optional(c.energyOrder)},
           {"energy_verdict", std::string(optimize::refinementName(c.energyRefinement))}});
    }
  }
  return {{"study", study}, {"records", records}, {"refinement", fits}, {"summary", table}};
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string csvNumber(double value) {
  return format("%.10g", value);
}
std::string csvNumber(const std::optional<double>& value) {
  return value ? csvNumber(*value) : std::string();
}

// One row per solve: a quadratic's C1 and C2, a nonlinear solve at one amplitude, a refinement
// level.
std::string resultsCsv(const StudyOptions& o, const StudyResults& results) {
  std::ostringstream out;
  out << "kind,energy,poisson,family,seed,n,level,h,vertices,free_vertices,data,"
         "energy_per_area,density,c1,c2,amplitude,nonlinear_error,converged,order,"
         "error,discrete_energy,exact_energy,energy_error,energy_order,verdict,energy_verdict\n";
  for (const StudyRecord& r : results.records) {
    const std::string common =
        std::string(optimize::recordKindName(r.kind)) + "," + csvField(o.energies[r.energy].label) +
        "," + csvNumber(curvature::effectivePoisson(o.energies[r.energy].bending)) + "," +
        csvField(r.family) + "," + (r.seed ? std::to_string(*r.seed) : "") + "," +
        (r.n ? std::to_string(*r.n) : "") + "," + std::to_string(r.level) + "," + csvNumber(r.h) +
        "," + std::to_string(r.vertices) + "," + std::to_string(r.freeVertices) + "," +
        csvField(r.data) + ",";
    switch (r.kind) {
      case RecordKind::Quadratic:
        out << common << csvNumber(r.energyPerArea) << ',' << csvNumber(r.density) << ','
            << csvNumber(r.c1Error) << ',' << csvNumber(r.c2Error) << ",,,,,,,,,,,\n";
        break;
      case RecordKind::NonlinearC2:
        for (size_t k = 0; k < r.nonlinear.amplitudes.size(); ++k) {
          out << common << ",,,," << csvNumber(r.nonlinear.amplitudes[k]) << ','
              << csvNumber(r.nonlinear.errors[k]) << ','
              << (r.nonlinear.converged ? "true" : "false") << ',' << csvNumber(r.nonlinear.order)
              << ",,,,,,,\n";
        }
        break;
      case RecordKind::Refinement:
        out << common << ",,,,,,," << csvNumber(r.order) << ',' << csvNumber(r.solutionError) << ','
            << csvNumber(r.discreteEnergy) << ',' << csvNumber(r.exactEnergy) << ','
            << csvNumber(r.energyError) << ',' << csvNumber(r.energyOrder) << ','
            << optimize::refinementName(r.verdict) << ','
            << optimize::refinementName(r.energyVerdict) << '\n';
        break;
    }
  }
  return out.str();
}

std::string reproductionCell(const std::optional<double>& worst) {
  if (!worst) return "—";
  return std::string(optimize::reproductionName(optimize::classifyReproduction(*worst))) + " " +
         scientific(*worst);
}

std::string refinementCell(Refinement verdict, const std::optional<double>& slope,
                           const std::optional<double>& finest) {
  const std::string error = finest ? " (" + scientific(*finest) + ")" : "";
  switch (verdict) {
    case Refinement::Converges:
      return (slope ? order(*slope) : "converges") + error;
    case Refinement::DoesNotConverge:
      return "does not converge" + (slope ? " " + order(*slope) : "") + error;
    case Refinement::Exact:
      return "exact" + error;
    case Refinement::Unmeasured:
      return "—";
  }
  return "—";
}

std::string markdownRow(const std::vector<std::string>& cells) {
  std::string row = "|";
  for (const std::string& c : cells) row += " " + c + " |";
  return row + "\n";
}

std::string markdownHeader(const std::vector<std::string>& cells) {
  std::string rule = "|";
  for (size_t k = 0; k < cells.size(); ++k) rule += k == 0 ? "---|" : "---|";
  return markdownRow(cells) + rule + "\n";
}

bool isGenerated(const StudyOptions& o, const std::string& family) {
  return std::any_of(o.families.begin(), o.families.end(),
                     [&](modeling::MeshFamily f) { return modeling::meshFamilyName(f) == family; });
}

// "16, 32, 64": the generated meshes' cells per side, coarsest first.
std::string levelsText(const StudyOptions& o) {
  std::string levels;
  for (int l = 0; l < o.levels; ++l) levels += (l ? ", " : "") + std::to_string(o.baseN << l);
  return levels;
}

// The study's settings as a list: energies, Poisson's ratio, meshes, quadratics, amplitudes and
// the plate solution.
void writeSettingsList(const StudyOptions& o, std::ostringstream& md) {
  std::string energies, meshes, quadratics;
  for (const auto& v : o.energies) energies += (energies.empty() ? "" : ", ") + v.label;
  for (const auto f : o.families) {
    meshes += (meshes.empty() ? "" : ", ") + std::string(modeling::meshFamilyName(f));
    if (f == modeling::MeshFamily::Delaunay) {
      std::string seeds;
      for (auto seed : o.seeds) seeds += (seeds.empty() ? "" : ", ") + std::to_string(seed);
      meshes += " (seed" + std::string(o.seeds.size() > 1 ? "s " : " ") + seeds + ")";
    }
  }
  for (const auto& m : o.userMeshes) meshes += (meshes.empty() ? "" : ", ") + m.name;
  for (const auto& q : o.quadratics) {
    quadratics += (quadratics.empty() ? "(" : ", (") + format("%g", q.a) + ", " +
                  format("%g", q.b) + ", " + format("%g", q.c) + ")";
  }
  md << "- energies: " << energies << "\n";
  // The first energy that takes a Poisson's ratio names it (hinge and cotan are ν = 1).
  for (const auto& v : o.energies) {
    const double nu = curvature::effectivePoisson(v.bending);
    if (nu != 1.0) {
      md << "- Poisson's ratio ν = " << format("%g", nu) << " for the energies that take one ("
         << curvature::energyNamesWhere(
                [](const curvature::EnergyEntry& e) {
                  return e.poissonRule == curvature::PoissonRule::MeanCurvatureOnly;
                },
                ", ", " and ")
         << " are ν = 1 models)\n";
      break;
    }
  }
  md << "- meshes: " << meshes;
  if (!o.families.empty())
    md << "; generated on [−½, ½]² with n = " << levelsText(o) << " cells per side";
  md << "\n- quadratics (a, b, c) of p = a x² + b xy + c y²: " << quadratics << "\n";
  if (o.amplitudes > 0) {
    md << "- nonlinear C2 at ε = 1/2 … " << amplitudeText(std::ldexp(1.0, -o.amplitudes))
       << " on the coarsest meshes\n";
  }
  if (!o.solution.empty() && !o.families.empty())
    md << "- refinement data: the plate solution u = " << o.solution << "\n";
}

void writeReproductionTable(const StudyOptions& o, const StudySummary& s, std::ostringstream& md) {
  md << "\n## C1 and C2 (linearized, n = " << o.baseN << ")\n\n"
     << "C1 = |E_lin(p)/A_cov − Ψ_ν(∇²p)| / |∇²p|², C2 = max over the free vertices |z − p| / max "
        "|p| with rings 0 and 1 fixed on p ("
     << curvature::energyNamesWhere(&curvature::EnergyEntry::hasEdgeUnknowns)
     << ": boundary ξ clamped, or free). Each cell: the verdict on the worst error over the "
        "quadratics"
     << (o.seeds.size() > 1 ? " and seeds" : "")
     << " — pass below 1e-9, fail above 1e-4, inconclusive between — and that error."
     << (o.userMeshes.empty() ? "" : " User meshes count at their own size.") << "\n\n";
  std::vector<std::string> header = {"energy"};
  for (const auto& f : s.families) {
    header.push_back("C1 " + f);
    header.push_back("C2 " + f);
  }
  md << markdownHeader(header);
  for (size_t e = 0; e < s.energies.size(); ++e) {
    std::vector<std::string> row = {s.energies[e]};
    for (const auto& c : s.cells[e]) {
      row.push_back(reproductionCell(c.worstC1));
      row.push_back(reproductionCell(c.worstC2));
    }
    md << markdownRow(row);
  }
}

void writeNonlinearOrderTable(const StudyOptions& o, const StudySummary& s,
                              std::ostringstream& md) {
  std::vector<std::string> familyHeader = {"energy"};
  for (const auto& f : s.families) familyHeader.push_back(f);
  md << "\n## Nonlinear C2: order in ε\n\n"
     << "The full energy's minimizer with boundary data εp, ε = 1/2 … "
     << amplitudeText(std::ldexp(1.0, -o.amplitudes))
     << ": the least-squares order of max |z − εp| ∝ ε^order, smallest over the quadratics. "
        "About 1 "
        "where linearized C2 fails; where it passes the minimizer is odd in ε (a flat rest "
        "mirrors z → −z), so the order is 3. \"exact\": every error is round-off.\n\n"
     << markdownHeader(familyHeader);
  for (size_t e = 0; e < s.energies.size(); ++e) {
    std::vector<std::string> row = {s.energies[e]};
    for (const auto& c : s.cells[e]) {
      std::string cell = c.nonlinearOrder ? order(*c.nonlinearOrder) : "exact";
      if (!c.nonlinearConverged) cell += " (a solve did not converge)";
      row.push_back(cell);
    }
    md << markdownRow(row);
  }
}

// One refinement table over the generated families: the minimizer's error against u, or (energy)
// the energy's.
void writeRefinementTable(const StudyOptions& o, const StudySummary& s, bool energy,
                          std::ostringstream& md) {
  std::vector<std::string> generatedHeader = {"energy"};
  for (const auto& f : s.families)
    if (isGenerated(o, f)) generatedHeader.push_back(f);
  md << markdownHeader(generatedHeader);
  for (size_t e = 0; e < s.energies.size(); ++e) {
    std::vector<std::string> row = {s.energies[e]};
    for (size_t f = 0; f < s.families.size(); ++f) {
      if (!isGenerated(o, s.families[f])) continue;
      const auto& c = s.cells[e][f];
      row.push_back(energy ? refinementCell(c.energyRefinement, c.energyOrder, c.finestEnergyError)
                           : refinementCell(c.refinement, c.refinementOrder, c.finestError));
    }
    md << markdownRow(row);
  }
}

void writeRefinementSections(const StudyOptions& o, const StudySummary& s, std::ostringstream& md) {
  const int finest = o.baseN << (o.levels - 1);
  md << "\n## Refinement: the minimizer against u = " << o.solution << "\n\n"
     << "Linearized minimizer with rings 0 and 1 on u, n = " << levelsText(o)
     << ". Each cell: the least-squares order of max interior |z − u| / max |u| in h = 1/n, and "
        "(in parentheses) that error at n = "
     << finest
     << ". \"does not converge\": the error at the finest level is not below 0.7 × the one "
        "before; \"exact\": the coarsest error is below 1e-9 (u is reproduced; finer levels show "
        "only round-off).\n\n";
  writeRefinementTable(o, s, false, md);
  md << "\n## Refinement: the energy against ∫ Ψ_ν(∇²u)\n\n"
     << "|E_lin(z) − ∫ Ψ_ν(∇²u) dA| / ∫ |∇²u|² dA, the integrals over the whole square (an "
        "energy "
        "whose elements leave out a boundary strip carries that O(h) deficit); order in h and "
        "(in parentheses) the error at n = "
     << finest << ".\n\n";
  writeRefinementTable(o, s, true, md);
}

std::string summaryMarkdown(const StudyOptions& o, const StudySummary& s,
                            const std::vector<std::string>& plots) {
  std::ostringstream md;
  md << "# Convergence study\n\n";
  writeSettingsList(o, md);
  writeReproductionTable(o, s, md);
  if (o.amplitudes >= 2) writeNonlinearOrderTable(o, s, md);
  if (!o.solution.empty() && !o.families.empty() && o.levels >= 2)
    writeRefinementSections(o, s, md);
  if (!plots.empty()) {
    md << "\n## Plots\n\n";
    for (const std::string& p : plots) md << "- [" << p << "](" << p << ")\n";
  }
  return md.str();
}

// File-name stem of a column: the family name, or a user mesh's file name without directories and
// extension, anything but letters, digits, '-' and '_' replaced by '_'.
std::string plotStem(const std::string& family) {
  std::string stem = std::filesystem::path(family).stem().string();
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return stem.empty() ? "mesh" : stem;
}

// Errors at or below this are round-off: plotted, they would stretch the axis over ten decades
// that say nothing. Series judged exact (or a C2 pass) are left out whole, since their finer
// levels' round-off grows with the conditioning; the legend says "exact" or "pass".
constexpr double kPlotFloor = 1e-12;

// Largest value per level (or amplitude) over the records of one energy on one column.
struct WorstCurve {
  std::map<double, double> worst;  // x → largest y
  void add(double x, double y) { worst[x] = std::max(worst[x], y); }
  // `roundOff`: the whole series is round-off (an exact reproduction): only its legend entry.
  render::PlotSeries series(const std::string& label, bool roundOff = false) const {
    render::PlotSeries s;
    s.label = label;
    for (const auto& [x, y] : worst) {
      if (roundOff || y <= kPlotFloor) continue;
      s.x.push_back(x);
      s.y.push_back(y);
    }
    return s;
  }
};

std::string seedsNote(const StudyOptions& o, const std::string& family) {
  return family == "delaunay" && o.seeds.size() > 1 ? ", worst over the seeds" : "";
}

// The four plots of one column: titles and axes; addEnergySeries adds the curves.
struct ColumnPlots {
  render::LogLogPlot c2, solution, energy, nonlinear;
};

ColumnPlots columnPlots(const StudyOptions& o, const std::string& family) {
  ColumnPlots p;
  p.c2.title = "Linearized C2 on " + family + " (worst over the quadratics" + seedsNote(o, family) +
               "; verdict at n = " + std::to_string(o.baseN) + ")";
  p.c2.xLabel = "h = 1/n";
  p.c2.yLabel = "max |z − p| / max |p|";
  p.solution.title = "Refinement on " + family + ": u = " + o.solution;
  p.solution.xLabel = "h = 1/n";
  p.solution.yLabel = "max |z − u| / max |u|";
  p.solution.referenceSlopes = {{1.0, "slope 1"}, {2.0, "slope 2"}};
  p.energy.title = "Energy on " + family + ": u = " + o.solution;
  p.energy.xLabel = "h = 1/n";
  p.energy.yLabel = "|E_lin − ∫Ψ(∇²u)| / ∫|∇²u|²";
  p.energy.referenceSlopes = {{1.0, "slope 1"}, {2.0, "slope 2"}};
  p.nonlinear.title =
      "Nonlinear C2 on " + family + " (worst over the quadratics" + seedsNote(o, family) + ")";
  p.nonlinear.xLabel = "boundary amplitude ε";
  p.nonlinear.yLabel = "max |z − εp| / max |p|";
  p.nonlinear.referenceSlopes = {{1.0, "slope 1"}, {3.0, "slope 3"}};
  return p;
}

// Energy e's curves on column f, each the worst over its records; the legends carry the verdicts.
void addEnergySeries(const StudyResults& results, const StudySummary& s, size_t e, size_t f,
                     ColumnPlots& plots) {
  WorstCurve c2Curve, solutionCurve, energyCurve, nonlinearCurve;
  for (const StudyRecord& r : results.records) {
    if (r.energy != static_cast<int>(e) || r.family != s.families[f]) continue;
    if (r.kind == RecordKind::Quadratic) c2Curve.add(r.h, r.c2Error);
    if (r.kind == RecordKind::Refinement) {
      solutionCurve.add(r.h, r.solutionError);
      energyCurve.add(r.h, r.energyError);
    }
    if (r.kind == RecordKind::NonlinearC2) {
      for (size_t k = 0; k < r.nonlinear.amplitudes.size(); ++k) {
        const double eps = r.nonlinear.amplitudes[k];
        nonlinearCurve.add(eps, eps * r.nonlinear.errors[k]);  // relative to max |p|
      }
    }
  }
  const optimize::SummaryCell& cell = s.cells[e][f];
  const std::string& label = s.energies[e];
  plots.c2.series.push_back(
      c2Curve.series(label + "  " + std::string(optimize::reproductionName(cell.c2)),
                     cell.c2 == optimize::Reproduction::Pass));
  plots.solution.series.push_back(solutionCurve.series(
      label + "  " + refinementCell(cell.refinement, cell.refinementOrder, std::nullopt),
      cell.refinement == Refinement::Exact));
  plots.energy.series.push_back(energyCurve.series(
      label + "  " + refinementCell(cell.energyRefinement, cell.energyOrder, std::nullopt),
      cell.energyRefinement == Refinement::Exact));
  plots.nonlinear.series.push_back(nonlinearCurve.series(
      label + "  " + (cell.nonlinearOrder ? order(*cell.nonlinearOrder) : "exact")));
}

struct NamedPlot {
  std::string name;  // its file name in the output folder
  render::LogLogPlot plot;
};

// Per column: c2_<stem>.png (a generated family over ≥ 2 levels) with refinement_ and
// refinement_energy_ when there is a plate solution; nonlinear_c2_<stem>.png over ≥ 2 amplitudes.
std::vector<NamedPlot> studyPlots(const StudyOptions& o, const StudyResults& results,
                                  const StudySummary& s) {
  std::vector<NamedPlot> plots;
  for (size_t f = 0; f < s.families.size(); ++f) {
    const std::string stem = plotStem(s.families[f]);
    ColumnPlots column = columnPlots(o, s.families[f]);
    for (size_t e = 0; e < s.energies.size(); ++e) addEnergySeries(results, s, e, f, column);
    if (isGenerated(o, s.families[f]) && o.levels >= 2) {
      plots.push_back({"c2_" + stem + ".png", std::move(column.c2)});
      if (!o.solution.empty()) {
        plots.push_back({"refinement_" + stem + ".png", std::move(column.solution)});
        plots.push_back({"refinement_energy_" + stem + ".png", std::move(column.energy)});
      }
    }
    if (o.amplitudes >= 2)
      plots.push_back({"nonlinear_c2_" + stem + ".png", std::move(column.nonlinear)});
  }
  return plots;
}

std::vector<std::string> plotNames(const std::vector<NamedPlot>& plots) {
  std::vector<std::string> names;
  for (const NamedPlot& p : plots) names.push_back(p.name);
  return names;
}

}  // namespace

bool isStudyFile(const std::string& name) {
  if (name == "results.json" || name == "results.csv" || name == "summary.md") return true;
  const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
  for (const char* prefix : {"c2_", "refinement_", "nonlinear_c2_"})
    if (png && name.rfind(prefix, 0) == 0) return true;
  return false;
}

nlohmann::json studyResultsJson(const StudyOptions& options, const StudyResults& results,
                                const StudySummary& summary) {
  return resultsJson(options, results, summary);
}

std::string studyResultsCsv(const StudyOptions& options, const StudyResults& results) {
  return resultsCsv(options, results);
}

std::string studySummaryMarkdown(const StudyOptions& options, const StudyResults& results,
                                 const StudySummary& summary) {
  return summaryMarkdown(options, summary, plotNames(studyPlots(options, results, summary)));
}

std::string writeStudyOutputs(const StudyOptions& options, const StudyResults& results,
                              const StudySummary& summary, const std::string& dir) {
  const std::filesystem::path out(dir);
  modeling::createOutputDirectory(out.string());
  const std::vector<NamedPlot> plots = studyPlots(options, results, summary);
  for (const NamedPlot& p : plots) render::writeLogLogPlot(p.plot, (out / p.name).string());
  writeJsonFile((out / "results.json").string(), resultsJson(options, results, summary));
  modeling::writeFileAtomically((out / "results.csv").string(), resultsCsv(options, results));
  const std::string markdown = summaryMarkdown(options, summary, plotNames(plots));
  modeling::writeFileAtomically((out / "summary.md").string(), markdown);
  return markdown;
}

}  // namespace flexure::reports
