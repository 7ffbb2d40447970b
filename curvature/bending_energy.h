// The bending energies (the five of docs/energies.md, and any registered at run time:
// energy_registry.h), each built once from the stencils and the rest state into an EnergyTerm. The
// axes stay apart (libshell's lesson): discretization × material (Poisson's ratio ν, stiffness k_B)
// × rest curvature (the rest mesh's, or flat for fairing).
#pragma once

#include <memory>
#include <optional>
#include <string_view>

#include "curvature/bending_angle.h"
#include "curvature/energy_term.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"

namespace flexure::curvature {

// One discretization: an index into the energy registry (curvature/energy_registry.h), whose
// entry holds its name, kernel factory, ν rule, element kind and edge unknowns. The built-ins
// have fixed indices, in docs/energies.md's order; `registerEnergy` adds more at run time.
class Discretization {
 public:
  static const Discretization Hinge, TriangleAveraged, Cotan, Midedge, QuadraticFit;
  constexpr Discretization() = default;  // Hinge
  constexpr explicit Discretization(int registryIndex) : index_(registryIndex) {}
  constexpr int index() const { return index_; }
  friend constexpr bool operator==(Discretization a, Discretization b) {
    return a.index_ == b.index_;
  }
  friend constexpr bool operator!=(Discretization a, Discretization b) { return !(a == b); }
  friend constexpr bool operator<(Discretization a, Discretization b) {
    return a.index_ < b.index_;
  }

 private:
  int index_ = 0;
};
inline constexpr Discretization Discretization::Hinge{0};
inline constexpr Discretization Discretization::TriangleAveraged{1};
inline constexpr Discretization Discretization::Cotan{2};
inline constexpr Discretization Discretization::Midedge{3};
inline constexpr Discretization Discretization::QuadraticFit{4};
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
  // ν. Empty: the registry entry's rule (0.3 for the Koiter energies triavg, midedge and quadfit;
  // hinge and cotan are ν = 1 models: they accept only 1, or nothing).
  std::optional<double> poisson;
  double stiffness = 1.0;  // k_B
  VertexArea vertexArea = VertexArea::Voronoi;
  HingeAngle hingeAngle = HingeAngle::Theta;
  RestCurvature restCurvature = RestCurvature::FromRest;
  CurvatureMetric metric = CurvatureMetric::Rest;
  // On the current metric: each edge's ℓ² / 2A capped on slivers (curvature/current_metric.h, the
  // secure metric; hinge, triavg and midedge), or the exact metric.
  bool secureMetric = true;
};

// The registered energy of that name, case-insensitive ("hinge" | "triavg" | "cotan" | "midedge" |
// "quadfit" | any registered later); throws InputError listing the registered names.
Discretization parseDiscretization(std::string_view name);
std::string_view discretizationName(Discretization d);

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
