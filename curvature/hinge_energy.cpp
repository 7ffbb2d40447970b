// hinge — Discrete Shells (hinge_bending.h): its factory and registry entry.
#include <cmath>
#include <optional>
#include <string>

#include "curvature/element_term.h"
#include "curvature/energy_registry.h"
#include "curvature/hinge_face_tensors.h"
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

// The hinge's rest curvature as per-face tensors (hinge_face_tensors.h, docs/energies.md
// "Plasticity"): a face's tensor is T_f(φ(θ)) read from its edges' angle measures, the rest one
// T_f(φ(θ̄⁰)); a new rest tensor S̄ moves each edge's rest angle to
// φ(θ̄_e) = φ(θ̄⁰_e) + ½ (c_e^f · (S̄_f − S̄⁰_f) + c_e^g · (S̄_g − S̄⁰_g)).
// The tensors are built on the first of these calls (HingeRestTensors): the energy and its
// derivatives never read them, so an elastic problem never builds them.
class HingeTerm final : public ElementTerm<HingeBendingResidual> {
 public:
  HingeTerm(std::vector<HingeBendingResidual> elements, std::vector<int> ids, double covered,
            HingeRestGeometry geometry)
      : ElementTerm(kName, std::string(elementKindName(kElementKind)), std::move(elements),
                    std::move(ids), covered, false),
        tensors_(std::move(geometry), restMeasures(this->elements())) {}

  RestCurvatureState* restCurvatureState() override { return this; }
  int elementId(int e) const override { return tensors_.faces().face(e); }
  Eigen::MatrixXd elementCurvatures(const Positions& x, const Eigen::VectorXd&) const override {
    Eigen::VectorXd angles(elements().size());
    std::vector<const double*> blocks;
    for (size_t e = 0; e < elements().size(); ++e) {
      const HingeBendingResidual& r = elements()[e];
      parameterBlocks(r, x.data(), static_cast<const double*>(nullptr), blocks);
      angles[static_cast<Eigen::Index>(e)] = hingeAngleMeasure(r.angle(blocks.data()), r.measure);
    }
    return tensors_.faces().tensors(angles);
  }
  Eigen::MatrixXd restCurvatures() const override {
    return rest_ ? *rest_ : tensors_.restTensors();
  }
  void setRestCurvatures(const Eigen::MatrixXd& rest) override {
    rest_ = rest;
    const Eigen::VectorXd angles =
        tensors_.restAngles() + tensors_.faces().angles(rest - tensors_.restTensors());
    std::vector<HingeBendingResidual>& elements = mutableElements();
    for (size_t e = 0; e < elements.size(); ++e)
      elements[e].restMeasure = angles[static_cast<Eigen::Index>(e)];
  }

 private:
  static Eigen::VectorXd restMeasures(const std::vector<HingeBendingResidual>& elements) {
    Eigen::VectorXd out(elements.size());
    for (size_t e = 0; e < elements.size(); ++e)
      out[static_cast<Eigen::Index>(e)] = elements[e].restMeasure;
    return out;
  }

  HingeRestTensors tensors_;             // φ(θ̄⁰_e) as built; T_f and S̄⁰_f on first use
  std::optional<Eigen::MatrixXd> rest_;  // S̄_f once set; S̄⁰_f until then
};

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
    r.secureMetric = o.secureMetric;
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
  return std::make_unique<HingeTerm>(std::move(elements), std::move(ids), covered,
                                     HingeRestGeometry::of(s, rest));
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
  e.spectrumRank = 4;
  return e;
}

}  // namespace flexure::curvature
