// triavg — the triangle-averaged shape operator (triangle_averaged.h): its factory and registry
// entry.
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
constexpr const char* kName = "triavg";
constexpr ElementKind kElementKind = ElementKind::Face;

using modeling::RestState;
using modeling::Stencils;

std::unique_ptr<EnergyTerm> makeTriangleAveraged(const Stencils& s, const RestState& rest,
                                                 const BendingOptions& o, double poisson) {
  std::vector<TriangleAveragedResidual> elements;
  std::vector<int> ids;
  double covered = 0.0;
  for (int f = 0; f < s.faceCount(); ++f) {
    if (!s.faceIsInterior(f)) continue;
    const double area = rest.faceAreas[f];
    TriangleAveragedResidual r;
    for (int i = 0; i < 3; ++i) {
      r.vertices[i] = s.faces(f, i);
      r.vertices[3 + i] = s.faceFlaps(f, i);
      r.edgeTensors[i] = edgeTensor(s, rest, f, i, rest.faceEdgeLengths(f, i) / (2.0 * area));
    }
    r.currentMetric = o.metric == CurvatureMetric::Current;
    r.secureMetric = o.secureMetric;
    r.weights = koiterWeights(o, poisson, area);
    r.restShapeOperator = {0.0, 0.0, 0.0};
    if (o.restCurvature == RestCurvature::FromRest) {
      const auto blocks = restBlocks(rest, r.vertices.data(), 6);
      r.restShapeOperator = r.shapeOperator(blocks.data());
      if (!std::isfinite(r.restShapeOperator.a + r.restShapeOperator.b + r.restShapeOperator.c)) {
        throw InputError(
            "triavg: rest face " + std::to_string(f) +
            " has a hinge folded flat (rest angle ±π): its shape operator is unbounded");
      }
    }
    elements.push_back(r);
    ids.push_back(f);
    covered += area;
  }
  return std::make_unique<ElementTerm<TriangleAveragedResidual>>(
      kName, std::string(elementKindName(kElementKind)), std::move(elements), std::move(ids),
      covered, false);
}

}  // namespace

EnergyEntry triangleAveragedEnergyEntry() {
  EnergyEntry e;
  e.name = kName;
  e.description =
      "triangle-averaged shape operator from 2 tan(θ/2) of the three edges, on faces whose edges "
      "are interior";
  e.citation =
      "Gingold, Secord, Han, Grinspun, Zorin 2004, A Discrete Model for Inelastic "
      "Deformation of Thin Shells";
  e.poissonRule = PoissonRule::Koiter;
  e.elementKind = kElementKind;
  e.make = makeTriangleAveraged;
  e.studyBytesPerVertex = 6.5e3;
  e.studyVariants = {"triavg"};
  e.studyRank = 1;
  e.spectrumRank = 3;
  return e;
}

}  // namespace flexure::curvature
