// hinge — Discrete Shells (hinge_bending.h): its factory and registry entry.
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
constexpr const char* kName = "hinge";
constexpr ElementKind kElementKind = ElementKind::Edge;

using modeling::RestState;
using modeling::Stencils;

std::string hingeElement(const Stencils& s, int h) {
  return "edge " + std::to_string(s.hingeEdges[h]) + " (vertices " +
         std::to_string(s.hinges(h, 0)) + ", " + std::to_string(s.hinges(h, 1)) + ")";
}

std::unique_ptr<EnergyTerm> makeHinge(const Stencils& s, const RestState& rest,
                                      const BendingOptions& o, double /*poisson: 1*/) {
  std::vector<HingeBendingResidual> elements;
  std::vector<int> ids;
  double covered = 0.0;
  elements.reserve(s.hingeCount());
  for (int h = 0; h < s.hingeCount(); ++h) {
    const int e = s.hingeEdges[h];
    const double areas = rest.faceAreas[s.edgeFaces(e, 0)] + rest.faceAreas[s.edgeFaces(e, 1)];
    HingeBendingResidual r;
    for (int k = 0; k < 4; ++k) r.vertices[k] = s.hinges(h, k);
    r.currentMetric = o.metric == CurvatureMetric::Current;
    // 3 ℓ̄² / (Ā_f + Ā_g): the current metric's factor at the rest positions.
    const double restFactor =
        hingeMetricFactor(restPoint(rest, r.vertices[0]), restPoint(rest, r.vertices[1]),
                          restPoint(rest, r.vertices[2]), restPoint(rest, r.vertices[3]));
    r.sqrtWeight = std::sqrt(2.0 * o.stiffness * (r.currentMetric ? 1.0 : restFactor));
    r.measure = o.hingeAngle;
    r.restMeasure = 0.0;
    if (o.restCurvature == RestCurvature::FromRest) {
      const auto blocks = restBlocks(rest, r.vertices.data(), 4);
      const double theta = r.angle(blocks.data());
      if (o.hingeAngle == HingeAngle::Tan && std::abs(theta) > M_PI - 1e-6) {
        throw InputError("hinge: rest " + hingeElement(s, h) +
                         " is folded flat (rest angle ±π): 2 tan(θ/2) is unbounded there; use "
                         "BendingOptions.hingeAngle theta");
      }
      r.restMeasure = hingeAngleMeasure(theta, o.hingeAngle);
    }
    elements.push_back(r);
    ids.push_back(e);
    covered += areas / 3.0;
  }
  return std::make_unique<ElementTerm<HingeBendingResidual>>(
      kName, std::string(elementKindName(kElementKind)), std::move(elements), std::move(ids),
      covered, false);
}

}  // namespace

EnergyEntry hingeEnergyEntry() {
  EnergyEntry e;
  e.name = kName;
  e.description = "Discrete Shells: (θ_e − θ̄_e)² 3 ℓ̄_e² / (Ā_f + Ā_g) per interior edge";
  e.citation = "Grinspun, Hirani, Desbrun, Schröder 2003, Discrete Shells";
  e.poissonRule = PoissonRule::MeanCurvatureOnly;
  e.elementKind = kElementKind;
  e.make = makeHinge;
  e.readsHingeAngle = true;
  e.studyBytesPerVertex = 3.5e3;
  e.studyVariants = {"hinge"};
  e.studyRank = 0;
  return e;
}

}  // namespace flexure::curvature
