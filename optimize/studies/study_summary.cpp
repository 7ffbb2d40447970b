// A convergence study's summary: the spec's table (energies by mesh families) of C1, C2,
// nonlinear C2 and refinement verdicts, computed from the records.
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "optimize/studies/convergence_study.h"

namespace flexure::optimize {

StudySummary summarizeStudy(const StudyOptions& options, const StudyResults& results) {
  StudySummary summary;
  for (const EnergyVariant& v : options.energies) summary.energies.push_back(v.label);
  for (const modeling::MeshFamily f : options.families)
    summary.families.emplace_back(modeling::meshFamilyName(f));
  for (const UserMesh& user : options.userMeshes) summary.families.push_back(user.name);
  const auto column = [&](const std::string& family) {
    return static_cast<size_t>(std::find(summary.families.begin(), summary.families.end(), family) -
                               summary.families.begin());
  };

  summary.cells.assign(summary.energies.size(), std::vector<SummaryCell>(summary.families.size()));
  for (const StudyRecord& r : results.records) {
    SummaryCell& cell = summary.cells[r.energy][column(r.family)];
    if (r.kind == RecordKind::Quadratic && r.level == 0) {
      if (r.c1Error) cell.worstC1 = std::max(cell.worstC1.value_or(0.0), *r.c1Error);
      cell.worstC2 = std::max(cell.worstC2, r.c2Error);
    } else if (r.kind == RecordKind::NonlinearC2) {
      if (r.nonlinear.order) {
        cell.nonlinearOrder =
            std::min(cell.nonlinearOrder.value_or(*r.nonlinear.order), *r.nonlinear.order);
      }
      cell.nonlinearConverged = cell.nonlinearConverged && r.nonlinear.converged;
    }
  }
  for (size_t e = 0; e < summary.energies.size(); ++e) {
    for (SummaryCell& cell : summary.cells[e]) {
      if (cell.worstC1) cell.c1 = classifyReproduction(*cell.worstC1);
      cell.c2 = classifyReproduction(cell.worstC2);
    }
  }
  // Refinement over seeds: the smallest order; DoesNotConverge if any series stalls, then
  // Converges if any converges, Exact if all are exact.
  const auto combine = [](Refinement a, Refinement b) {
    for (Refinement r : {Refinement::DoesNotConverge, Refinement::Converges, Refinement::Exact})
      if (a == r || b == r) return r;
    return Refinement::Unmeasured;
  };
  const auto smaller = [](std::optional<double> a, std::optional<double> b) {
    if (!a) return b;
    if (!b) return a;
    return std::optional<double>(std::min(*a, *b));
  };
  for (const RefinementFit& fit : results.refinements) {
    SummaryCell& cell = summary.cells[fit.energy][column(fit.family)];
    cell.refinement = combine(cell.refinement, fit.verdict);
    cell.energyRefinement = combine(cell.energyRefinement, fit.energyVerdict);
    cell.refinementOrder = smaller(cell.refinementOrder, fit.order);
    cell.energyOrder = smaller(cell.energyOrder, fit.energyOrder);
    cell.finestError = std::max(cell.finestError.value_or(0.0), fit.solutionErrors.back());
    cell.finestEnergyError =
        std::max(cell.finestEnergyError.value_or(0.0), fit.energyErrors.back());
  }
  return summary;
}

}  // namespace flexure::optimize
