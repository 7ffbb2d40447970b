// flexure energy: the bending energy of a current mesh against a rest mesh, for any of the five
// discretizations, nonlinear or linearized (docs/energies.md).
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/bending_arguments.h"
#include "cli/command_files.h"
#include "cli/commands.h"
#include "cli/mesh_json.h"
#include "curvature/bending_energy.h"
#include "curvature/bending_spec.h"
#include "curvature/energy_registry.h"
#include "curvature/midedge_boundary.h"
#include "modeling/errors.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "optimize/configuration_energy.h"

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

void runEnergyCommand(const EnergyCommandOptions& o) {
  const curvature::BendingOptions b = bendingOptions(o.bending);
  optimize::ConfigurationEnergyOptions options;
  options.bending = b;
  if (!o.boundarySurface.empty())
    options.boundarySurface = modeling::PolynomialSurface::parse(o.boundarySurface);
  options.linearized = o.linearized;
  options.validate();  // before any work
  const modeling::Mesh restMesh = modeling::readMesh(o.restFile);
  const modeling::Mesh current = modeling::readMesh(o.currentFile);
  requireSameConnectivity(o, restMesh, current);

  const optimize::ConfigurationEnergy result =
      optimize::configurationEnergy(restMesh, current.positions, options);

  nlohmann::json report = {
      {"energy_name", std::string(curvature::discretizationName(b.discretization))},
      {"linearized", o.linearized},
      {"energy", result.energy},
      {"elements", result.elements},
      {"element_kind", result.elementKind},
      {"covered_area", result.coveredArea},
      {"energy_per_area", result.perArea()},
      {"poisson", curvature::effectivePoisson(b)},
      {"stiffness", b.stiffness},
      {"rest", o.restFile},
      {"current", o.currentFile},
  };
  if (curvature::energyEntry(b.discretization).readsVertexArea)
    report["vertex_area"] = curvature::vertexAreaName(b.vertexArea);
  if (curvature::energyEntry(b.discretization).readsHingeAngle)
    report["hinge_angle"] = curvature::hingeAngleName(b.hingeAngle);
  if (!result.boundaryXi.empty()) report["boundary_xi"] = result.boundaryXi;

  if (o.json) {
    std::cout << report.dump(2) << '\n';
    return;
  }
  std::printf("%s%s energy  %.17g\n", report["energy_name"].get<std::string>().c_str(),
              o.linearized ? " (linearized)" : "", result.energy);
  std::printf("elements        %s\n", counted(result.elements, result.elementKind).c_str());
  std::printf("covered area    %.17g\n", result.coveredArea);
  std::printf("energy / area   %.17g\n", result.perArea());
  if (!result.boundaryXi.empty()) std::printf("boundary xi     %s\n", result.boundaryXi.c_str());
}

}  // namespace

void registerEnergyCommand(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<EnergyCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "energy", "Bending energy of a current mesh against a rest mesh (docs/energies.md)");
  addBendingArguments(*sub, options->bending);
  sub->add_option("--rest", options->restFile, "Rest (undeformed) mesh")->required();
  sub->add_option("--current", options->currentFile, "Current (deformed) mesh, same connectivity")
      ->required();
  sub->add_option("--boundary-surface", options->boundarySurface,
                  curvature::energyNamesWhere(&curvature::EnergyEntry::takesBoundarySurface) +
                      ": clamp boundary xi to this surface's normals (quadratic:a,b,c or "
                      "polynomial:EXPR); free otherwise")
      ->check(surfaceSpec());
  sub->add_flag("--linearized", options->linearized,
                "The second-order expansion about rest, E_lin(delta) = |J delta|^2");
  sub->add_flag("--json", options->json, "Print the result as JSON");
  sub->footer(
      "Example: flexure energy --energy midedge --rest flat.obj --current bowl.obj "
      "--boundary-surface quadratic:1,0,1 --linearized --json");
  sub->callback([options, &global] {
    // flexure run's check before any step: the option values alone (the meshes may not exist yet).
    if (global.checkOnly) {
      bendingOptions(options->bending);
      return;
    }
    runEnergyCommand(*options);
  });
}

}  // namespace flexure::cli
