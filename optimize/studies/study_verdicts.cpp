// A convergence study's verdicts: C1 and C2 against the spec's thresholds, a refinement series
// converging, stalling or exact, and the least-squares log-log slopes that give orders.
#include <cmath>
#include <optional>
#include <string_view>
#include <vector>

#include "optimize/studies/convergence_study.h"

namespace flexure::optimize {

std::optional<double> seriesOrder(const std::vector<double>& h, const std::vector<double>& errors,
                                  Refinement verdict) {
  if (verdict != Refinement::Converges && verdict != Refinement::DoesNotConverge) return {};
  std::vector<double> x, y;
  for (size_t k = 0; k < errors.size(); ++k) {
    if (errors[k] > 0.0) {
      x.push_back(h[k]);
      y.push_back(errors[k]);
    }
  }
  if (x.size() < 2) return {};
  return logLogSlope(x, y);
}

double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t count = x.size();
  double meanX = 0.0, meanY = 0.0;
  for (size_t k = 0; k < count; ++k) {
    meanX += std::log(x[k]) / count;
    meanY += std::log(y[k]) / count;
  }
  double sxy = 0.0, sxx = 0.0;
  for (size_t k = 0; k < count; ++k) {
    const double dx = std::log(x[k]) - meanX;
    sxy += dx * (std::log(y[k]) - meanY);
    sxx += dx * dx;
  }
  return sxy / sxx;
}

Reproduction classifyReproduction(double worstError) {
  if (worstError < kReproductionPass) return Reproduction::Pass;
  if (worstError > kReproductionFail) return Reproduction::Fail;
  return Reproduction::Inconclusive;
}

std::string_view reproductionName(Reproduction r) {
  switch (r) {
    case Reproduction::Pass:
      return "pass";
    case Reproduction::Fail:
      return "fail";
    case Reproduction::Inconclusive:
      return "inconclusive";
  }
  return "unknown";
}

Refinement classifyRefinement(const std::vector<double>& errors) {
  if (!errors.empty() && errors.front() < kReproductionPass) return Refinement::Exact;
  if (errors.size() < 2) return Refinement::Unmeasured;
  if (errors.back() >= kStallRatio * errors[errors.size() - 2]) return Refinement::DoesNotConverge;
  return Refinement::Converges;
}

std::string_view refinementName(Refinement r) {
  switch (r) {
    case Refinement::Converges:
      return "converges";
    case Refinement::DoesNotConverge:
      return "does not converge";
    case Refinement::Exact:
      return "exact";
    case Refinement::Unmeasured:
      return "unmeasured";
  }
  return "unknown";
}

}  // namespace flexure::optimize
