// The five bending energies of docs/energies.md, each built once from the stencils and the rest
// state into an EnergyTerm. The axes stay apart (libshell's lesson): discretization × material
// (Poisson's ratio ν, stiffness k_B) × rest curvature (the rest mesh's, or flat for fairing).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string_view>

#include "curvature/bending_angle.h"
#include "curvature/energy_term.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

enum class Discretization { Hinge, TriangleAveraged, Cotan, Midedge, QuadraticFit };
// All five, in docs/energies.md's order.
inline constexpr std::array<Discretization, 5> kDiscretizations = {
    Discretization::Hinge, Discretization::TriangleAveraged, Discretization::Cotan,
    Discretization::Midedge, Discretization::QuadraticFit};
enum class VertexArea { Voronoi, Barycentric };
// FromRest: a shell, whose rest angles, shape operators and ξ̄ come from the rest mesh.
// Flat: the rest mesh gives only the metric (areas, lengths); rest curvature is zero (fairing).
enum class RestCurvature { FromRest, Flat };
// Whose metric (areas, lengths, in-plane normals, fit matrices) curvature is measured in.
// Rest: the rest mesh's, an elastic energy of the displacement (Discrete Shells, Koiter shells).
// Current: the current surface's (curvature/current_metric.h), a geometric functional of the
// surface alone whose gradient includes the metric's: fairing's Willmore-type energy. Only with
// flat rest curvature.
enum class CurvatureMetric { Rest, Current };

struct BendingOptions {
  Discretization discretization = Discretization::Hinge;
  // ν. Empty: 0.3 for triavg, midedge and quadfit. hinge and cotan are ν = 1 models: they accept
  // only 1 (or nothing).
  std::optional<double> poisson;
  double stiffness = 1.0;  // k_B
  VertexArea vertexArea = VertexArea::Voronoi;
  HingeAngle hingeAngle = HingeAngle::Theta;
  RestCurvature restCurvature = RestCurvature::FromRest;
  CurvatureMetric metric = CurvatureMetric::Rest;
};

// "hinge" | "triavg" | "cotan" | "midedge" | "quadfit"; throws InputError listing them.
Discretization parseDiscretization(std::string_view name);
std::string_view discretizationName(Discretization d);
VertexArea parseVertexArea(std::string_view name);  // "voronoi" | "barycentric"
HingeAngle parseHingeAngle(std::string_view name);  // "theta" | "tan"

// ν the discretization uses, after the checks above (InputError on a rejected value).
double effectivePoisson(const BendingOptions& options);

// Throws InputError naming the element for a degenerate rest element: a quadratic-fit stencil
// whose six rest points admit no unique quadratic, a rest hinge angle at ±π under the tan
// measure, a rest ξ̄ that cannot be determined; and for the current metric with a rest curvature.
std::unique_ptr<EnergyTerm> makeBendingEnergy(const modeling::Stencils& stencils,
                                              const modeling::RestState& rest,
                                              const BendingOptions& options);

// Rest ξ̄ of the midedge energy: the minimizer of Σ_T Ā_T |S̄_T|² (0 on a flat rest mesh, and
// for RestCurvature::Flat).
Eigen::VectorXd midedgeRestXi(const modeling::Stencils& stencils, const modeling::RestState& rest,
                              RestCurvature restCurvature);

}  // namespace flexure::curvature
