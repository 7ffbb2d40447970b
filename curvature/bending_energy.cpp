#include "curvature/bending_energy.h"

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <string>
#include <vector>

#include "curvature/element_term.h"
#include "curvature/face_frame.h"
#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

using modeling::RestState;
using modeling::Stencils;

std::string lowercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::vector<const double*> restBlocks(const RestState& rest, const int* vertices, int count) {
  std::vector<const double*> blocks;
  for (int k = 0; k < count; ++k) blocks.push_back(rest.positions.data() + 3 * vertices[k]);
  return blocks;
}

FaceFrame restFrame(const Stencils& s, const RestState& rest, int f) {
  return FaceFrame::of(rest.positions.row(s.faces(f, 0)).transpose(),
                       rest.positions.row(s.faces(f, 1)).transpose(),
                       rest.positions.row(s.faces(f, 2)).transpose());
}

Vec3<double> restPoint(const RestState& rest, int v) {
  return {rest.positions(v, 0), rest.positions(v, 1), rest.positions(v, 2)};
}

// scale · n̂_i n̂_iᵀ of face f's edge i in the face's rest frame: current_metric.h's ℓ_i n̂_i n̂_iᵀ
// at the rest positions (the same formula the current metric evaluates at x), times scale / ℓ̄_i.
Sym2<double> edgeTensor(const Stencils& s, const RestState& rest, int f, int i, double scale) {
  const Vec3<double> x[3] = {restPoint(rest, s.faces(f, 0)), restPoint(rest, s.faces(f, 1)),
                             restPoint(rest, s.faces(f, 2))};
  const Sym2<double> t = currentEdgeTensors(x, currentFrame(x[0], x[1], x[2]))[i];
  const double c = scale / rest.faceEdgeLengths(f, i);
  return {c * t.a, c * t.b, c * t.c};
}

// The face energies' Koiter weights: make(ν, 2 k_B Ā_T), or per unit area on the current metric
// (the kernel multiplies by the current √A_T).
KoiterWeights koiterWeights(const BendingOptions& o, double poisson, double restArea) {
  const double area = o.metric == CurvatureMetric::Current ? 1.0 : restArea;
  return KoiterWeights::make(poisson, 2.0 * o.stiffness * area);
}

std::string hingeElement(const Stencils& s, int h) {
  return "edge " + std::to_string(s.hingeEdges[h]) + " (vertices " +
         std::to_string(s.hinges(h, 0)) + ", " + std::to_string(s.hinges(h, 1)) + ")";
}

std::unique_ptr<EnergyTerm> makeHinge(const Stencils& s, const RestState& rest,
                                      const BendingOptions& o) {
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
                         "--hinge-angle theta");
      }
      r.restMeasure = hingeAngleMeasure(theta, o.hingeAngle);
    }
    elements.push_back(r);
    ids.push_back(e);
    covered += areas / 3.0;
  }
  return std::make_unique<ElementTerm<HingeBendingResidual>>("hinge", "edge", std::move(elements),
                                                             std::move(ids), covered, false);
}

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
      "triavg", "face", std::move(elements), std::move(ids), covered, false);
}

std::unique_ptr<EnergyTerm> makeCotan(const Stencils& s, const RestState& rest,
                                      const BendingOptions& o) {
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
      "cotan", "vertex", std::move(elements), std::move(ids), covered, false);
}

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
  return std::make_unique<ElementTerm<MidedgeResidual>>("midedge", "face", std::move(elements),
                                                        std::move(ids), covered, true);
}

std::unique_ptr<EnergyTerm> makeQuadraticFit(const Stencils& s, const RestState& rest,
                                             const BendingOptions& o, double poisson) {
  std::vector<QuadraticFitResidual> elements;
  std::vector<int> ids, singular;
  double covered = 0.0;
  for (int f = 0; f < s.faceCount(); ++f) {
    if (!s.faceIsInterior(f)) continue;
    const double area = rest.faceAreas[f];
    const FaceFrame frame = restFrame(s, rest, f);
    QuadraticFitResidual r;
    for (int i = 0; i < 3; ++i) {
      r.vertices[i] = s.faces(f, i);
      r.vertices[3 + i] = s.faceFlaps(f, i);
    }
    // Rows [1, u, v, u², uv, v²] in units of the face size √Ā, so that the conditioning test is
    // scale-free; c3, c4, c5 then carry a factor 1/Ā.
    const double unit = std::sqrt(area);
    Eigen::Matrix<double, 6, 6> fit;
    for (int k = 0; k < 6; ++k) {
      const Eigen::Vector2d p =
          frame.coordinates(rest.positions.row(r.vertices[k]).transpose()) / unit;
      fit.row(k) << 1.0, p.x(), p.y(), p.x() * p.x(), p.x() * p.y(), p.y() * p.y();
    }
    // Full pivoting: the stencil is singular when a pivot falls below 1e-9 of the largest one
    // (six points on a conic); far cheaper than an SVD per face.
    Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(fit);
    lu.setThreshold(1e-9);
    if (!lu.isInvertible()) {
      singular.push_back(f);
      continue;
    }
    const Eigen::Matrix<double, 6, 6> inverse = lu.inverse();
    for (int row = 0; row < 3; ++row)
      for (int k = 0; k < 6; ++k) r.fitRows[row][k] = inverse(3 + row, k) / area;
    r.currentMetric = o.metric == CurvatureMetric::Current;
    r.weights = koiterWeights(o, poisson, area);
    r.restShapeOperator = {0.0, 0.0, 0.0};
    if (o.restCurvature == RestCurvature::FromRest) {
      const auto blocks = restBlocks(rest, r.vertices.data(), 6);
      r.restShapeOperator = r.shapeOperator(blocks.data());
    }
    elements.push_back(r);
    ids.push_back(f);
    covered += area;
  }
  if (!singular.empty()) {
    std::string list;
    for (size_t k = 0; k < singular.size() && k < 10; ++k)
      list += (k ? ", " : "") + std::to_string(singular[k]);
    if (singular.size() > 10) list += ", … (" + std::to_string(singular.size()) + " in all)";
    throw InputError("quadfit: the six rest points of face " + list +
                     " admit no unique quadratic (they lie on a conic); the quadratic fit is "
                     "undefined there");
  }
  return std::make_unique<ElementTerm<QuadraticFitResidual>>("quadfit", "face", std::move(elements),
                                                             std::move(ids), covered, false);
}

}  // namespace

Discretization parseDiscretization(std::string_view name) {
  const std::string n = lowercase(name);
  if (n == "hinge") return Discretization::Hinge;
  if (n == "triavg") return Discretization::TriangleAveraged;
  if (n == "cotan") return Discretization::Cotan;
  if (n == "midedge") return Discretization::Midedge;
  if (n == "quadfit") return Discretization::QuadraticFit;
  throw InputError("unknown energy '" + std::string(name) +
                   "' (expected hinge, triavg, cotan, midedge or quadfit)");
}

std::string_view discretizationName(Discretization d) {
  switch (d) {
    case Discretization::Hinge:
      return "hinge";
    case Discretization::TriangleAveraged:
      return "triavg";
    case Discretization::Cotan:
      return "cotan";
    case Discretization::Midedge:
      return "midedge";
    case Discretization::QuadraticFit:
      return "quadfit";
  }
  return "unknown";
}

VertexArea parseVertexArea(std::string_view name) {
  const std::string n = lowercase(name);
  if (n == "voronoi") return VertexArea::Voronoi;
  if (n == "barycentric") return VertexArea::Barycentric;
  throw InputError("unknown vertex area '" + std::string(name) +
                   "' (expected voronoi or barycentric)");
}

HingeAngle parseHingeAngle(std::string_view name) {
  const std::string n = lowercase(name);
  if (n == "theta") return HingeAngle::Theta;
  if (n == "tan") return HingeAngle::Tan;
  throw InputError("unknown hinge angle '" + std::string(name) + "' (expected theta or tan)");
}

double effectivePoisson(const BendingOptions& o) {
  const bool meanCurvatureModel =
      o.discretization == Discretization::Hinge || o.discretization == Discretization::Cotan;
  if (meanCurvatureModel) {
    if (o.poisson && *o.poisson != 1.0) {
      throw InputError(std::string(discretizationName(o.discretization)) +
                       " sees only the mean curvature (a ν = 1 model): it takes no --poisson " +
                       "(got " + std::to_string(*o.poisson) + ")");
    }
    return 1.0;
  }
  const double nu = o.poisson.value_or(0.3);
  if (!(nu >= -1.0 && nu <= 1.0)) {
    throw InputError("--poisson " + std::to_string(nu) +
                     " is outside [-1, 1], where Ψ_ν is not "
                     "a non-negative bending density");
  }
  return nu;
}

std::unique_ptr<EnergyTerm> makeBendingEnergy(const Stencils& s, const RestState& rest,
                                              const BendingOptions& o) {
  const double poisson = effectivePoisson(o);
  if (!(o.stiffness > 0.0) || !std::isfinite(o.stiffness)) {
    throw InputError("bending stiffness k_B must be positive (got " + std::to_string(o.stiffness) +
                     ")");
  }
  if (o.metric == CurvatureMetric::Current && o.restCurvature != RestCurvature::Flat) {
    throw InputError(
        "the current metric measures curvature against a flat rest only (a rest curvature "
        "would be measured in the rest mesh's frames)");
  }
  switch (o.discretization) {
    case Discretization::Hinge:
      return makeHinge(s, rest, o);
    case Discretization::TriangleAveraged:
      return makeTriangleAveraged(s, rest, o, poisson);
    case Discretization::Cotan:
      return makeCotan(s, rest, o);
    case Discretization::Midedge:
      return makeMidedge(s, rest, o, poisson);
    case Discretization::QuadraticFit:
      return makeQuadraticFit(s, rest, o, poisson);
  }
  throw std::logic_error("makeBendingEnergy: unknown discretization");
}

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

}  // namespace flexure::curvature
