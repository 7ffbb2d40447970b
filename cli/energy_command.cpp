// flexure energy: the bending energy of a current mesh against a rest mesh, for any of the five
// discretizations, nonlinear or linearized (docs/energies.md).
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/bending_arguments.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "curvature/bending_energy.h"
#include "curvature/energy_registry.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "optimize/problem.h"
#include "optimize/solvers/energy_evaluation.h"

namespace flexure::cli {
namespace {

struct EnergyCommandOptions {
  BendingArguments bending;
  std::string restFile, currentFile;
  std::string boundarySurface;
  bool linearized = false;
  bool json = false;
};

// Rest and current must be the same mesh in two positions.
void requireSameConnectivity(const EnergyCommandOptions& o, const modeling::Mesh& rest,
                             const modeling::Mesh& current) {
  if (current.vertexCount() != rest.vertexCount() || current.faceCount() != rest.faceCount()) {
    throw InputError(o.currentFile + ": has " + std::to_string(current.vertexCount()) +
                     " vertices and " + std::to_string(current.faceCount()) + " faces, but " +
                     o.restFile + " has " + std::to_string(rest.vertexCount()) + " and " +
                     std::to_string(rest.faceCount()) +
                     ": rest and current must share connectivity");
  }
  for (int f = 0; f < rest.faceCount(); ++f) {
    if (current.triangles.row(f) != rest.triangles.row(f)) {
      const auto t = current.triangles.row(f), r = rest.triangles.row(f);
      throw InputError(o.currentFile + ": face " + std::to_string(f) + " has vertices (" +
                       std::to_string(t(0)) + ", " + std::to_string(t(1)) + ", " +
                       std::to_string(t(2)) + "), but in " + o.restFile + " (" +
                       std::to_string(r(0)) + ", " + std::to_string(r(1)) + ", " +
                       std::to_string(r(2)) + "): rest and current must share connectivity");
    }
  }
}

struct EnergyResult {
  double energy;
  std::string boundary;  // midedge: how boundary ξ were set
};

// Midedge: E is the minimum over the free ξ; boundary ξ are clamped to the surface or free.
EnergyResult evaluate(const EnergyCommandOptions& o, const optimize::Problem& problem,
                      const modeling::Positions& current) {
  const modeling::Stencils& stencils = problem.stencils;
  const modeling::RestState& rest = problem.rest;
  const curvature::EnergyTerm& term = problem.bending();
  const std::vector<const curvature::EnergyTerm*> terms = problem.termPointers();
  const Eigen::VectorXd& restXi = problem.restXi;
  std::optional<modeling::PolynomialSurface> surface;
  if (!o.boundarySurface.empty()) surface = modeling::PolynomialSurface::parse(o.boundarySurface);
  const std::vector<bool> onBoundary = curvature::boundaryEdges(stencils);
  std::vector<bool> freeEdge(stencils.edgeCount(), true);
  if (surface)
    for (int e = 0; e < stencils.edgeCount(); ++e) freeEdge[e] = !onBoundary[e];
  const std::string boundary = !term.usesEdgeUnknowns() ? ""
                               : surface                ? "clamped to " + surface->spec()
                                                        : "free";

  if (!o.linearized) {
    Eigen::VectorXd xi = restXi;
    if (term.usesEdgeUnknowns() && surface) {
      const Eigen::VectorXd clamped = curvature::clampedBoundaryXi(stencils, current, *surface);
      for (int e = 0; e < stencils.edgeCount(); ++e)
        if (onBoundary[e]) xi[e] = clamped[e];
    }
    return {optimize::relaxedEnergy(terms, current, xi, freeEdge), boundary};
  }

  // E_lin(δ) = ½ |J u|² with J at rest and u = (δ, ξ − ξ̄).
  const optimize::SparseMatrix jacobian = optimize::residualJacobian(terms, rest.positions, restXi);
  const modeling::Positions delta = current - rest.positions;
  Eigen::VectorXd deltaXi;
  if (term.usesEdgeUnknowns() && surface)
    deltaXi = curvature::linearizedClampedBoundaryXi(stencils, rest.positions, delta, *surface);
  return {
      optimize::linearizedEnergyOfDisplacement(jacobian, rest.positions, delta, deltaXi, freeEdge),
      boundary};
}

void runEnergyCommand(const EnergyCommandOptions& o) {
  const curvature::BendingOptions b = bendingOptions(o.bending);
  if (!o.boundarySurface.empty() && !curvature::energyEntry(b.discretization).takesBoundarySurface)
    throw InputError("--boundary-surface applies to --energy midedge only");
  const modeling::Mesh restMesh = modeling::readMesh(o.restFile);
  const modeling::Mesh current = modeling::readMesh(o.currentFile);
  requireSameConnectivity(o, restMesh, current);

  // The energy of a configuration: nothing held; midedge's boundary ξ are set in evaluate.
  optimize::ProblemOptions options;
  options.bending = b;
  options.fixedRings = 0;
  options.boundaryNormals = optimize::BoundaryNormals::Free;
  const optimize::Problem problem = optimize::buildProblem(restMesh, options);
  const curvature::EnergyTerm* term = &problem.bending();
  const EnergyResult result = evaluate(o, problem, current.positions);
  const double perArea = term->coveredArea() > 0 ? result.energy / term->coveredArea() : 0.0;

  nlohmann::json report = {
      {"energy_name", std::string(curvature::discretizationName(b.discretization))},
      {"linearized", o.linearized},
      {"energy", result.energy},
      {"elements", term->elementCount()},
      {"element_kind", term->elementKind()},
      {"covered_area", term->coveredArea()},
      {"energy_per_area", perArea},
      {"poisson", curvature::effectivePoisson(b)},
      {"stiffness", b.stiffness},
      {"rest", o.restFile},
      {"current", o.currentFile},
  };
  if (curvature::energyEntry(b.discretization).readsVertexArea)
    report["vertex_area"] =
        b.vertexArea == curvature::VertexArea::Voronoi ? "voronoi" : "barycentric";
  if (curvature::energyEntry(b.discretization).readsHingeAngle)
    report["hinge_angle"] = b.hingeAngle == curvature::HingeAngle::Theta ? "theta" : "tan";
  if (!result.boundary.empty()) report["boundary_xi"] = result.boundary;

  if (o.json) {
    std::cout << report.dump(2) << '\n';
    return;
  }
  std::printf("%s%s energy  %.17g\n", report["energy_name"].get<std::string>().c_str(),
              o.linearized ? " (linearized)" : "", result.energy);
  std::printf("elements        %s\n", counted(term->elementCount(), term->elementKind()).c_str());
  std::printf("covered area    %.17g\n", term->coveredArea());
  std::printf("energy / area   %.17g\n", perArea);
  if (!result.boundary.empty()) std::printf("boundary xi     %s\n", result.boundary.c_str());
}

}  // namespace

void registerEnergyCommand(CLI::App& app, const GlobalOptions&) {
  auto options = std::make_shared<EnergyCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "energy", "Bending energy of a current mesh against a rest mesh (docs/energies.md)");
  addBendingArguments(*sub, options->bending);
  sub->add_option("--rest", options->restFile, "Rest (undeformed) mesh")->required();
  sub->add_option("--current", options->currentFile, "Current (deformed) mesh, same connectivity")
      ->required();
  sub->add_option("--boundary-surface", options->boundarySurface,
                  "midedge: clamp boundary xi to this surface's normals (quadratic:a,b,c or "
                  "polynomial:EXPR); free otherwise");
  sub->add_flag("--linearized", options->linearized,
                "The second-order expansion about rest, E_lin(delta) = |J delta|^2");
  sub->add_flag("--json", options->json, "Print the result as JSON");
  sub->footer(
      "Example: flexure energy --energy midedge --rest flat.obj --current bowl.obj "
      "--boundary-surface quadratic:1,0,1 --linearized --json");
  sub->callback([options] { runEnergyCommand(*options); });
}

}  // namespace flexure::cli
