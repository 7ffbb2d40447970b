// quadfit — the triangle quadratic fit (quadratic_fit.h): its factory and registry entry.
#include <cmath>
#include <string>

#include "curvature/element_term.h"
#include "curvature/energy_registry.h"
#include "curvature/rest_element_data.h"
#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

// The name users type and the element the energy sums over: the registry entry and the term
// read these, so they cannot disagree.
constexpr const char* kName = "quadfit";
constexpr ElementKind kElementKind = ElementKind::Face;

using modeling::RestState;
using modeling::Stencils;

// Rows 3, 4, 5 of the inverse rest fit matrix over Ā (quadratic_fit.h's fitRows); false when the
// six rest points admit no unique quadratic.
bool restFitRows(const std::vector<const double*>& x, double area,
                 std::array<std::array<double, 6>, 3>& fitRows) {
  const Vec3<double> x0 = load(x[0]), x1 = load(x[1]), x2 = load(x[2]);
  const Vec3<double> centroid = (1.0 / 3.0) * (x0 + x1 + x2);
  std::array<std::array<double, 6>, 6> fit =
      quadraticFitMatrix(x.data(), centroid, currentFrame(x0, x1, x2), std::sqrt(area));
  std::array<std::array<double, 6>, 6> inverse{};
  for (int k = 0; k < 6; ++k) inverse[k][k] = 1.0;
  if (!solveQuadraticFit(fit, inverse)) return false;
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 6; ++k) fitRows[row][k] = inverse[3 + row][k] / area;
  return true;
}

std::string faceList(const std::vector<int>& faces) {
  std::string list;
  for (size_t k = 0; k < faces.size() && k < 10; ++k)
    list += (k ? ", " : "") + std::to_string(faces[k]);
  if (faces.size() > 10) list += ", … (" + std::to_string(faces.size()) + " in all)";
  return list;
}

std::unique_ptr<EnergyTerm> makeQuadraticFit(const Stencils& s, const RestState& rest,
                                             const BendingOptions& o, double poisson) {
  std::vector<QuadraticFitResidual> elements;
  std::vector<int> ids, singular;
  double covered = 0.0;
  for (int f = 0; f < s.faceCount(); ++f) {
    if (!s.faceIsInterior(f)) continue;
    const double area = rest.faceAreas[f];
    QuadraticFitResidual r;
    for (int i = 0; i < 3; ++i) {
      r.vertices[i] = s.faces(f, i);
      r.vertices[3 + i] = s.faceFlaps(f, i);
    }
    const auto blocks = restBlocks(rest, r.vertices.data(), 6);
    if (!restFitRows(blocks, area, r.fitRows)) {
      singular.push_back(f);
      continue;
    }
    r.currentMetric = o.metric == CurvatureMetric::Current;
    r.weights = koiterWeights(o, poisson, area);
    r.restShapeOperator = {0.0, 0.0, 0.0};
    if (o.restCurvature == RestCurvature::FromRest)
      r.restShapeOperator = r.shapeOperator(blocks.data());
    elements.push_back(r);
    ids.push_back(f);
    covered += area;
  }
  if (!singular.empty()) {
    throw InputError("quadfit: the six rest points of face " + faceList(singular) +
                     " admit no unique quadratic (they lie on a conic); the quadratic fit is "
                     "undefined there");
  }
  return std::make_unique<ElementTerm<QuadraticFitResidual>>(
      kName, std::string(elementKindName(kElementKind)), std::move(elements), std::move(ids),
      covered, false);
}

}  // namespace

EnergyEntry quadraticFitEnergyEntry() {
  EnergyEntry e;
  e.name = kName;
  e.description = "quadratic fit through the six points of each face with interior edges";
  e.citation = "the course slides' triangle quadratic fit (seed 000)";
  e.poissonRule = PoissonRule::Koiter;
  e.elementKind = kElementKind;
  e.make = makeQuadraticFit;
  e.studyBytesPerVertex = 6.5e3;
  e.studyVariants = {"quadfit"};
  e.studyRank = 3;
  e.spectrumRank = 2;
  return e;
}

}  // namespace flexure::curvature
