#include "curvature/membrane_energy.h"

#include <array>
#include <cmath>
#include <string>

#include "curvature/barrier_term.h"
#include "curvature/element_term.h"
#include "curvature/face_frame.h"
#include "modeling/errors.h"

namespace flexure::curvature {
namespace {

using modeling::RestState;
using modeling::Stencils;

void requirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw InputError(std::string(what) + " must be positive (got " + numberText(value) + ")");
}

// D̄⁻¹ (row-major) of face f: its rest edges x̄1 − x̄0, x̄2 − x̄0 in the face's 2D frame.
std::array<double, 4> restEdgeInverse(const Stencils& s, const RestState& rest, int f) {
  Eigen::Vector3d x[3];
  for (int i = 0; i < 3; ++i) x[i] = rest.positions.row(s.faces(f, i)).transpose();
  const FaceFrame frame = FaceFrame::of(x[0], x[1], x[2]);
  Eigen::Matrix2d edges;
  edges.col(0) = frame.components(x[1] - x[0]);
  edges.col(1) = frame.components(x[2] - x[0]);
  const Eigen::Matrix2d inverse = edges.inverse();
  return {inverse(0, 0), inverse(0, 1), inverse(1, 0), inverse(1, 1)};
}

std::array<int, 3> faceVertices(const Stencils& s, int f) {
  return {s.faces(f, 0), s.faces(f, 1), s.faces(f, 2)};
}

std::unique_ptr<EnergyTerm> makeStvk(const Stencils& s, const RestState& rest,
                                     const MembraneOptions& o) {
  const double modulus = o.young / (2.0 * (1.0 - o.poisson * o.poisson));
  std::vector<StvkMembraneResidual> elements;
  std::vector<int> ids;
  for (int f = 0; f < s.faceCount(); ++f) {
    StvkMembraneResidual r;
    r.vertices = faceVertices(s, f);
    r.restEdgeInverse = restEdgeInverse(s, rest, f);
    r.weights = KoiterWeights::make(o.poisson, 2.0 * modulus * rest.faceAreas[f]);
    elements.push_back(r);
    ids.push_back(f);
  }
  return std::make_unique<ElementTerm<StvkMembraneResidual>>(
      "stvk", "face", std::move(elements), std::move(ids), rest.faceAreas.sum(), false);
}

std::unique_ptr<EnergyTerm> makeConformal(const Stencils& s, const RestState& rest,
                                          const MembraneOptions& o) {
  const bool barrier = o.model == MembraneModel::Mips;
  std::vector<ConformalMembraneResidual> elements;
  std::vector<int> ids;
  for (int f = 0; f < s.faceCount(); ++f) {
    elements.push_back({faceVertices(s, f), restEdgeInverse(s, rest, f),
                        std::sqrt(2.0 * o.shapeStiffness), barrier});
    ids.push_back(f);
  }
  return std::make_unique<ElementTerm<ConformalMembraneResidual>>(
      barrier ? "mips" : "conformal", "face", std::move(elements), std::move(ids),
      rest.faceAreas.sum(), false);
}

std::vector<std::unique_ptr<EnergyTerm>> makeSprings(const Stencils& s, const RestState& rest,
                                                     const MembraneOptions& o) {
  std::vector<EdgeSpringResidual> edges;
  std::vector<int> edgeIds;
  for (int e = 0; e < s.edgeCount(); ++e) {
    const double length = rest.edgeLengths[e];
    edges.push_back(
        {{s.edges(e, 0), s.edges(e, 1)}, std::sqrt(2.0 * o.lengthStiffness / length), length});
    edgeIds.push_back(e);
  }
  std::vector<AreaSpringResidual> faces;
  std::vector<int> faceIds;
  for (int f = 0; f < s.faceCount(); ++f) {
    const double area = rest.faceAreas[f];
    faces.push_back({faceVertices(s, f), std::sqrt(2.0 * o.areaStiffness / area), area});
    faceIds.push_back(f);
  }
  std::vector<std::unique_ptr<EnergyTerm>> terms;
  const double total = rest.faceAreas.sum();
  terms.push_back(std::make_unique<ElementTerm<EdgeSpringResidual>>(
      "edge springs", "edge", std::move(edges), std::move(edgeIds), total, false));
  terms.push_back(std::make_unique<ElementTerm<AreaSpringResidual>>(
      "area springs", "face", std::move(faces), std::move(faceIds), total, false));
  return terms;
}

}  // namespace

void MembraneOptions::validate() const {
  switch (model) {
    case MembraneModel::Stvk:
      requirePositive(young, "MembraneOptions.young (Young's modulus × thickness)");
      // Plane stress: 1 − ν² > 0 and a positive bulk modulus.
      if (!(poisson > -1.0 && poisson <= 0.5)) {
        throw InputError("MembraneOptions.poisson " + numberText(poisson) +
                         " is outside (-1, 0.5] (stvk membrane)");
      }
      return;
    case MembraneModel::Springs:
      requirePositive(lengthStiffness,
                      "MembraneOptions.lengthStiffness (edge spring stiffness k_L)");
      requirePositive(areaStiffness, "MembraneOptions.areaStiffness (area spring stiffness k_A)");
      return;
    case MembraneModel::Conformal:
    case MembraneModel::Mips:
      requirePositive(shapeStiffness,
                      model == MembraneModel::Mips
                          ? "MembraneOptions.shapeStiffness (mips membrane k_S)"
                          : "MembraneOptions.shapeStiffness (conformal membrane k_S)");
      return;
  }
}

std::unique_ptr<EnergyTerm> makeAngleBarrier(const Stencils& s, const std::vector<int>& faces,
                                             const modeling::Positions& positions, double stiffness,
                                             double minAngle, double band) {
  requirePositive(stiffness, "angle barrier stiffness");
  requirePositive(band, "angle barrier band");
  std::vector<AngleBarrierResidual> elements;
  for (int f : faces)
    elements.push_back({faceVertices(s, f), std::sqrt(2.0 * stiffness), minAngle, band});
  // Its Gauss–Newton Hessian is each face's exact one projected (barrier_term.h).
  auto term = std::make_unique<BarrierTerm<AngleBarrierResidual>>(
      "angle barrier", "face", std::move(elements), faces, 0.0, false);
  term->energy(positions, Eigen::VectorXd());  // a face at or below the floor throws, naming it
  return term;
}

MembraneModel parseMembraneModel(std::string_view name) {
  if (name == "stvk") return MembraneModel::Stvk;
  if (name == "springs") return MembraneModel::Springs;
  if (name == "conformal") return MembraneModel::Conformal;
  if (name == "mips") return MembraneModel::Mips;
  throw InputError("unknown membrane '" + std::string(name) +
                   "' (expected stvk, springs, conformal or mips)");
}

std::vector<std::unique_ptr<EnergyTerm>> makeMembraneEnergy(const Stencils& s,
                                                            const RestState& rest,
                                                            const MembraneOptions& o) {
  o.validate();
  if (o.model == MembraneModel::Springs) return makeSprings(s, rest, o);
  std::vector<std::unique_ptr<EnergyTerm>> terms;
  terms.push_back(o.model == MembraneModel::Stvk ? makeStvk(s, rest, o)
                                                 : makeConformal(s, rest, o));
  return terms;
}

}  // namespace flexure::curvature
