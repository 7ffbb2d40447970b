// The scalar fields of the legend styles: the error |z − p(x, y)| against a polynomial surface,
// the displacement |x − x̄| from a reference, a signed curvature on a symmetric range (a
// percentile of |value| by default), a plastic strain; and one error scale shared by several
// panels.
#include "render/scalar_fields.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <utility>

#include "modeling/errors.h"

namespace flexure::render {
namespace {

std::string rangeWords(const RenderOptions& o, const std::string& rule) {
  return o.rangeNote.empty() ? rule : o.rangeNote;
}

// The curvature style: a signed field on [−m, m], symmetric so that white is 0.
ScalarField curvatureField(const modeling::Mesh& mesh, const RenderOptions& o) {
  ScalarField field;
  field.values = o.vertexScalars;
  if (static_cast<int>(field.values.size()) != mesh.vertexCount()) {
    throw InputError("render: " + std::to_string(field.values.size()) + " curvature values for " +
                     std::to_string(mesh.vertexCount()) + " vertices");
  }
  for (double value : field.values)
    if (!std::isfinite(value)) throw InputError("render: a curvature value is not finite");
  const double bound = o.curvatureMax ? *o.curvatureMax : curvatureRange(field.values);
  char range[128];
  std::snprintf(range, sizeof range, "|%s| ≤ %.3g (%s)", o.scalarSymbol.c_str(), bound,
                rangeWords(o, o.curvatureMax ? "given" : curvatureRangeRule(field.values)).c_str());
  field.minimum = -bound;
  field.maximum = bound;
  field.map = &divergingColourMap();
  field.title = o.scalarLabel;
  field.range = range;
  return field;
}

// A magnitude on [0, max] (given or the largest; an all-zero field still needs a non-empty range:
// it then shows the colour of 0), or on a log scale [log10 floor, log10 max].
ScalarField magnitudeField(std::vector<double> values, std::optional<double> givenMaximum,
                           std::optional<double> logFloor, const RenderOptions& o) {
  ScalarField field;
  const double largest = *std::max_element(values.begin(), values.end());
  const double maximum = givenMaximum ? *givenMaximum : std::max(largest, 1e-12);
  char range[128];
  field.map = &sequentialColourMap();
  if (logFloor && *logFloor < maximum) {
    for (double& v : values) v = std::log10(std::max(v, *logFloor));
    field.minimum = std::log10(*logFloor);
    field.maximum = std::log10(maximum);
    field.logarithmic = true;
    std::snprintf(range, sizeof range, "%.2g to %.3g, log scale (%s)", *logFloor, maximum,
                  rangeWords(o, givenMaximum ? "given" : "largest").c_str());
  } else {
    field.maximum = maximum;
    std::snprintf(range, sizeof range, "0 to %.3g (%s)", maximum,
                  rangeWords(o, givenMaximum ? "given" : "largest").c_str());
  }
  field.values = std::move(values);
  field.range = range;
  return field;
}

}  // namespace

ScalarField legendField(const modeling::Mesh& mesh, const RenderOptions& o) {
  if (o.style == RenderStyle::Curvature) return curvatureField(mesh, o);
  if (o.style == RenderStyle::Displacement) {
    ScalarField field = magnitudeField(vertexDisplacements(mesh.positions, o.referencePositions),
                                       o.displacementMax, std::nullopt, o);
    field.title = "|x − x̄| (mesh length unit)";
    return field;
  }
  if (o.style == RenderStyle::Plastic) {
    if (static_cast<int>(o.vertexScalars.size()) != mesh.vertexCount())
      throw InputError("render: " + std::to_string(o.vertexScalars.size()) +
                       " plastic strains for " + std::to_string(mesh.vertexCount()) + " vertices");
    ScalarField field = magnitudeField(o.vertexScalars, o.plasticMax, std::nullopt, o);
    field.title = o.plasticLabel;
    return field;
  }
  ScalarField field =
      magnitudeField(vertexSurfaceErrors(mesh, o.surface), o.errorMax, o.errorLogFloor, o);
  field.title = "|z − p(x, y)|";
  return field;
}

std::vector<double> vertexSurfaceErrors(const modeling::Mesh& mesh,
                                        const modeling::PolynomialSurface& surface) {
  std::vector<double> errors(mesh.vertexCount());
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const auto x = mesh.positions.row(v);
    errors[v] = std::abs(x(2) - surface.height(x(0), x(1)));
  }
  return errors;
}

ErrorScale sharedErrorScale(const std::vector<std::vector<double>>& panelErrors) {
  ErrorScale scale;
  double largest = 0.0, smallestPositiveMaximum = std::numeric_limits<double>::infinity();
  for (const std::vector<double>& errors : panelErrors) {
    if (errors.empty()) continue;
    const double panelMaximum = *std::max_element(errors.begin(), errors.end());
    largest = std::max(largest, panelMaximum);
    if (panelMaximum > 0.0)
      smallestPositiveMaximum = std::min(smallestPositiveMaximum, panelMaximum);
  }
  scale.errorMax = std::max(largest, 1e-12);
  if (largest > 0.0 && largest > std::pow(10.0, kLogScaleDecades) * smallestPositiveMaximum)
    scale.errorLogFloor = std::max(0.1 * smallestPositiveMaximum, 1e-16 * largest);
  return scale;
}

std::vector<double> vertexDisplacements(const modeling::Positions& positions,
                                        const modeling::Positions& reference) {
  if (positions.rows() != reference.rows()) {
    throw InputError("render: the reference has " + std::to_string(reference.rows()) +
                     " vertices, the mesh " + std::to_string(positions.rows()));
  }
  const Eigen::VectorXd distances = (positions - reference).rowwise().norm();
  return std::vector<double>(distances.data(), distances.data() + distances.size());
}

double curvatureRange(const std::vector<double>& values) {
  if (values.empty()) return 1e-12;
  std::vector<double> magnitudes(values.size());
  std::transform(values.begin(), values.end(), magnitudes.begin(),
                 [](double v) { return std::abs(v); });
  // Nearest rank: the smallest |H| with at least kCurvatureRangePercentile % of the values at or
  // below it.
  const auto rank = static_cast<std::size_t>(
      std::ceil(kCurvatureRangePercentile / 100.0 * static_cast<double>(magnitudes.size())));
  const std::size_t index = std::clamp<std::size_t>(rank, 1, magnitudes.size()) - 1;
  std::nth_element(magnitudes.begin(), magnitudes.begin() + static_cast<std::ptrdiff_t>(index),
                   magnitudes.end());
  const double percentile = magnitudes[index];
  if (percentile > 0.0) return percentile;
  return std::max(*std::max_element(magnitudes.begin(), magnitudes.end()), 1e-12);
}

std::string curvatureRangeRule(const std::vector<double>& values) {
  const double range = curvatureRange(values);
  bool anyAbove = false;
  for (const double v : values) anyAbove = anyAbove || std::abs(v) > range;
  if (!anyAbove) return "largest";
  char rule[32];
  std::snprintf(rule, sizeof rule, "%gth percentile", kCurvatureRangePercentile);
  return rule;
}

}  // namespace flexure::render
