// The energy registry: one entry per discretization, holding everything that differs between
// them — name, help text, citation, ν rule, element kind, edge unknowns and their rest values, the
// factory that binds the kernel to a rest state, which options it reads and which default lists
// it is in. Adding an energy is a kernel file with its factory and one registration: a line in
// the built-in table (energy_registry.cpp), or `registerEnergy` at run time.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "curvature/bending_energy.h"
#include "modeling/mesh.h"

namespace flexure::curvature {

// How an energy takes Poisson's ratio: a mean-curvature-only model sees Ψ_1 alone and accepts
// only ν = 1 (or none); a Koiter energy takes ν ∈ [−1, 1], kDefaultPoisson when not given.
enum class PoissonRule { MeanCurvatureOnly, Koiter };
inline constexpr double kDefaultPoisson = 0.3;

// The mesh element an energy sums over; messages name elements by it ("edge 12").
enum class ElementKind { Edge, Face, Vertex };
std::string_view elementKindName(ElementKind kind);  // "edge" | "face" | "vertex"

// The factory: the energy's elements bound to the rest state, with ν already checked by the rule.
// Throws InputError naming a degenerate rest element.
using EnergyFactory = std::function<std::unique_ptr<EnergyTerm>(
    const modeling::Stencils&, const modeling::RestState&, const BendingOptions&, double poisson)>;
// Rest values of the edge unknowns an energy owns (#E), e.g. midedge's ξ̄.
using RestEdgeUnknowns = std::function<Eigen::VectorXd(const modeling::Stencils&,
                                                       const modeling::RestState&, RestCurvature)>;
// Per-vertex mean curvature H (#V) of a mesh as it stands, from the energy's kernel: what a
// curvature map colours. Throws InputError for a mesh the kernel cannot measure.
using MeanCurvatureField = std::function<std::vector<double>(const modeling::Mesh&)>;

struct EnergyEntry {
  std::string name;         // as users type it, lower case: "hinge"
  std::string description;  // one line of help
  std::string citation;     // the paper or seed it follows
  PoissonRule poissonRule = PoissonRule::Koiter;
  ElementKind elementKind = ElementKind::Face;
  EnergyFactory make;
  // Set when the energy owns one unknown per edge (midedge's ξ): their rest values.
  RestEdgeUnknowns restEdgeUnknowns;
  bool hasEdgeUnknowns() const { return static_cast<bool>(restEdgeUnknowns); }
  // Which of BendingOptions' per-energy fields it reads: vertexArea, hingeAngle; and whether the
  // boundary values of its edge unknowns can come from a boundary surface.
  bool readsVertexArea = false, readsHingeAngle = false, takesBoundarySurface = false;
  // Whether its elements carry a rest curvature (a shape operator per face, an angle per hinge)
  // that a plastic strain can move (optimize/inelastic/plasticity.h); cotan's one mean curvature
  // per vertex cannot.
  bool plasticRestCurvature = true;
  // Peak resident memory per vertex of one convergence-study case (five quadratics' linearized
  // solves), measured with /usr/bin/time -v on patch48 between n = 128 and 256 (16 641 and
  // 66 049 vertices), one run each, and rounded up: midedge 9.9 kB (the ξ per edge: four times
  // the unknowns), triavg and quadfit 5.7 kB, hinge and cotan 2.9 kB.
  double studyBytesPerVertex = 11e3;
  // The convergence study's default rows ("cotan", "cotan:barycentric", …; empty: none) and
  // where they go in its table (rows sorted by this rank, stable).
  std::vector<std::string> studyVariants;
  int studyRank = 0;
  // Where the energy goes among the spectrum study's default energies (optimize/studies/
  // spectrum_study.h), which run each energy once with its default options, sorted by this rank;
  // empty: not among them.
  std::optional<int> spectrumRank;
  // Set when the energy's kernel gives a per-vertex mean curvature of a surface (cotan's
  // H = K·n / (2 A)), for curvature maps; `meanCurvatureFormula` says how, for help texts.
  MeanCurvatureField meanCurvatureField;
  std::string meanCurvatureFormula;
};

// All registered energies: the five built-ins first, in docs/energies.md's order, then those
// registered at run time. Entries never move (a deque: references stay valid).
const std::deque<EnergyEntry>& registeredEnergies();
const EnergyEntry& energyEntry(Discretization d);
// The built-in energies (the registry's first entries), in docs/energies.md's order.
std::vector<Discretization> builtinDiscretizations();
// The entry of that name, compared case-insensitively; nullptr when none is registered.
const EnergyEntry* findEnergy(std::string_view name);
// The first registered energy whose kernel gives a mean-curvature field (curvature maps' default).
const EnergyEntry& defaultMeanCurvatureEnergy();
// The registered names, in registry order.
std::vector<std::string> energyNameList();
// "hinge, triavg, cotan, midedge or quadfit" (the last joined by `lastSeparator`).
std::string registeredEnergyNames(std::string_view separator = ", ",
                                  std::string_view lastSeparator = " or ");
// The same of the energies for which `selects` holds: what help texts and messages list.
std::string energyNamesWhere(const std::function<bool(const EnergyEntry&)>& selects,
                             std::string_view separator = ", ",
                             std::string_view lastSeparator = " or ");

// Adds an energy and returns its Discretization. Throws InputError for an empty or taken name
// (names are compared case-insensitively) or an entry without a factory. Not thread-safe: register
// before solving.
Discretization registerEnergy(EnergyEntry entry);

// The rest values of the edge unknowns of `options.discretization` (#E; zero when it owns none).
Eigen::VectorXd restEdgeUnknowns(const modeling::Stencils& stencils,
                                 const modeling::RestState& rest, const BendingOptions& options);

// The built-ins' entries, each defined beside its kernel's factory.
EnergyEntry hingeEnergyEntry();             // hinge_energy.cpp
EnergyEntry triangleAveragedEnergyEntry();  // triangle_averaged_energy.cpp
EnergyEntry cotanEnergyEntry();             // cotan_energy.cpp
EnergyEntry midedgeEnergyEntry();           // midedge_energy.cpp
EnergyEntry quadraticFitEnergyEntry();      // quadratic_fit_energy.cpp

}  // namespace flexure::curvature
