// midedge — the midedge-normal shape operator (midedge_normals.h), which owns one unknown ξ per
// edge: its factory, the rest ξ̄ and the registry entry.
#include <Eigen/SparseCholesky>
#include <cmath>

#include "curvature/element_term.h"
#include "curvature/energy_registry.h"
#include "curvature/rest_element_data.h"
#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

// The name users type and the element the energy sums over: the registry entry and the term
// read these, so they cannot disagree.
constexpr const char* kName = "midedge";
constexpr ElementKind kElementKind = ElementKind::Face;

using modeling::RestState;
using modeling::Stencils;

// The midedge residual of face f, without its rest shape operator.
MidedgeResidual midedgeStencil(const Stencils& s, const RestState& rest, int f) {
  const double area = rest.faceAreas[f];
  MidedgeResidual r;
  r.flapCount = 0;
  for (int i = 0; i < 3; ++i) r.vertices[i] = s.faces(f, i);
  for (int i = 0; i < 3; ++i) {
    r.edges[i] = s.faceEdges(f, i);
    r.signs[i] = s.faceEdgeSigns(f, i);
    r.hasFlap[i] = s.faceFlaps(f, i) >= 0;
    if (r.hasFlap[i]) r.vertices[3 + r.flapCount++] = s.faceFlaps(f, i);
    r.edgeTensors[i] = edgeTensor(s, rest, f, i, rest.faceEdgeLengths(f, i) / area);
  }
  return r;
}

std::unique_ptr<EnergyTerm> makeMidedge(const Stencils& s, const RestState& rest,
                                        const BendingOptions& o, double poisson) {
  const Eigen::VectorXd restXi = midedgeRestXi(s, rest, o.restCurvature);
  std::vector<MidedgeResidual> elements;
  std::vector<int> ids;
  double covered = 0.0;
  std::vector<const double*> blocks;
  for (int f = 0; f < s.faceCount(); ++f) {
    MidedgeResidual r = midedgeStencil(s, rest, f);
    r.currentMetric = o.metric == CurvatureMetric::Current;
    r.secureMetric = o.secureMetric;
    r.weights = koiterWeights(o, poisson, rest.faceAreas[f]);
    r.restShapeOperator = {0.0, 0.0, 0.0};
    if (o.restCurvature == RestCurvature::FromRest) {
      parameterBlocks(r, rest.positions.data(), restXi.data(), blocks);
      r.restShapeOperator = r.shapeOperator(blocks.data());
    }
    elements.push_back(r);
    ids.push_back(f);
    covered += rest.faceAreas[f];
  }
  return std::make_unique<ElementTerm<MidedgeResidual>>(
      kName, std::string(elementKindName(kElementKind)), std::move(elements), std::move(ids),
      covered, true);
}

}  // namespace

Eigen::VectorXd midedgeRestXi(const Stencils& s, const RestState& rest,
                              RestCurvature restCurvature) {
  Eigen::VectorXd xi = Eigen::VectorXd::Zero(s.edgeCount());
  if (restCurvature == RestCurvature::Flat) return xi;
  // S̄_T(ξ) = S̄_T(0) + Σ_i σ_i t_i ξ_e(i) is affine in ξ: minimize Σ Ā |S̄_T|² = |A ξ + b|² with
  // rows √Ā (a, √2 b, c) per face, through the normal equations.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd b(3 * s.faceCount());
  std::vector<const double*> blocks;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(s.edgeCount());
  for (int f = 0; f < s.faceCount(); ++f) {
    const MidedgeResidual r = midedgeStencil(s, rest, f);
    parameterBlocks(r, rest.positions.data(), zero.data(), blocks);
    const Sym2<double> s0 = r.shapeOperator(blocks.data());
    const double w = std::sqrt(rest.faceAreas[f]), w2 = w * std::sqrt(2.0);
    b.segment<3>(3 * f) << w * s0.a, w2 * s0.b, w * s0.c;
    for (int i = 0; i < 3; ++i) {
      const Sym2<double>& t = r.edgeTensors[i];
      entries.emplace_back(3 * f, r.edges[i], w * r.signs[i] * t.a);
      entries.emplace_back(3 * f + 1, r.edges[i], w2 * r.signs[i] * t.b);
      entries.emplace_back(3 * f + 2, r.edges[i], w * r.signs[i] * t.c);
    }
  }
  if (b.norm() == 0.0) return xi;  // a flat rest mesh: ξ̄ = 0
  Eigen::SparseMatrix<double> a(3 * s.faceCount(), s.edgeCount());
  a.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseMatrix<double> normal = a.transpose() * a;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  if (solver.info() == Eigen::Success) xi = solver.solve(-(a.transpose() * b));
  if (solver.info() != Eigen::Success || !xi.allFinite()) {
    throw InputError("midedge: the rest ξ̄ (minimizing Σ Ā |S̄|²) is not unique on this rest mesh");
  }
  return xi;
}

EnergyEntry midedgeEnergyEntry() {
  EnergyEntry e;
  e.name = kName;
  e.description = "midedge-normal shape operator with one unknown ξ per edge, on every face";
  e.citation =
      "Grinspun, Gingold, Reisman, Zorin 2006, Computing discrete shape operators on "
      "general meshes";
  e.poissonRule = PoissonRule::Koiter;
  e.elementKind = kElementKind;
  e.make = makeMidedge;
  e.restEdgeUnknowns = midedgeRestXi;
  e.takesBoundarySurface = true;
  e.studyBytesPerVertex = 11e3;
  e.studyVariants = {"midedge", "midedge:free"};
  e.studyRank = 4;
  e.spectrumRank = 0;
  return e;
}

}  // namespace flexure::curvature
