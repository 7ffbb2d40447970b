// cotan — the vertex-averaged cotangent mean curvature (cotan_mean_curvature.h): its factory and
// registry entry.
#include <cmath>

#include "curvature/element_term.h"
#include "curvature/energy_registry.h"
#include "curvature/mean_curvature_field.h"
#include "curvature/rest_element_data.h"

namespace flexure::curvature {
namespace {

// The name users type and the element the energy sums over: the registry entry and the term
// read these, so they cannot disagree.
constexpr const char* kName = "cotan";
constexpr ElementKind kElementKind = ElementKind::Vertex;

using modeling::RestState;
using modeling::Stencils;

std::unique_ptr<EnergyTerm> makeCotan(const Stencils& s, const RestState& rest,
                                      const BendingOptions& o, double /*poisson: 1*/) {
  std::vector<CotanMeanCurvatureResidual> elements;
  std::vector<int> ids;
  double covered = 0.0;
  const Eigen::VectorXd& areas =
      o.vertexArea == VertexArea::Voronoi ? rest.vertexVoronoiAreas : rest.vertexBarycentricAreas;
  for (int v = 0; v < s.vertexCount(); ++v) {
    if (s.vertexOnBoundary[v]) continue;
    CotanMeanCurvatureResidual r;
    r.vertices.push_back(v);
    for (int k = s.oneRingOffsets[v]; k < s.oneRingOffsets[v + 1]; ++k)
      r.vertices.push_back(s.oneRingVertices[k]);
    r.currentMetric = o.metric == CurvatureMetric::Current;
    r.voronoiArea = o.vertexArea == VertexArea::Voronoi;
    r.sqrtWeight = std::sqrt(2.0 * o.stiffness / (r.currentMetric ? 1.0 : areas[v]));
    r.restValue = 0.0;
    if (o.restCurvature == RestCurvature::FromRest) {
      const auto blocks = restBlocks(rest, r.vertices.data(), static_cast<int>(r.vertices.size()));
      r.restValue =
          cotanMeanCurvatureNormal(blocks.data(), static_cast<int>(r.vertices.size()) - 1);
    }
    elements.push_back(std::move(r));
    ids.push_back(v);
    covered += areas[v];
  }
  return std::make_unique<ElementTerm<CotanMeanCurvatureResidual>>(
      kName, std::string(elementKindName(kElementKind)), std::move(elements), std::move(ids),
      covered, false);
}

}  // namespace

EnergyEntry cotanEnergyEntry() {
  EnergyEntry e;
  e.name = kName;
  e.description = "cotangent mean curvature normal per interior vertex, over its vertex area";
  e.citation =
      "Meyer, Desbrun, Schröder, Barr 2003, Discrete Differential-Geometry Operators "
      "for Triangulated 2-Manifolds";
  e.poissonRule = PoissonRule::MeanCurvatureOnly;
  e.elementKind = kElementKind;
  e.make = makeCotan;
  e.readsVertexArea = true;
  e.plasticRestCurvature = false;  // one mean curvature per vertex, no tensor to move
  e.studyBytesPerVertex = 3.5e3;
  e.studyVariants = {"cotan", "cotan:barycentric"};
  e.studyRank = 2;
  e.spectrumRank = 1;
  e.meanCurvatureField = cotanVertexMeanCurvature;
  e.meanCurvatureFormula = "H = K.n / (2 A), the cotan energy's kernel";
  return e;
}

}  // namespace flexure::curvature
