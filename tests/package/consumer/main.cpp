// Uses flexure as an installed package (find_package(flexure), flexure::flexure), with the same
// #includes as the project's own code; docs/cpp.md shows these steps one by one. Each check
// prints its value; any failure exits 1. Argument: a folder to write a mesh into.
//
// Known answers (docs/energies.md): for p(x, y) = a x² + b xy + c y² sampled on a flat 4-8 patch,
// the cotan energy (Voronoi areas) reproduces C1, E_lin(p) / A_cov = (2a + 2c)², and C2, its
// linearized minimizer with two rings held at p is p itself. A plate whose held rings lie on a
// plane has that plane as its hinge-energy minimizer, at energy 0.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "curvature/bending_energy.h"
#include "modeling/generators.h"
#include "modeling/mesh_io.h"
#include "modeling/polynomial_surface.h"
#include "modeling/rest_state.h"
#include "modeling/stencils.h"
#include "optimize/assembly/energy_evaluation.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/problem.h"
#include "optimize/solvers/minimize.h"

namespace {

namespace fc = flexure::curvature;
namespace fm = flexure::modeling;
namespace fo = flexure::optimize;

int failures = 0;

void check(bool passed, const char* what, double value) {
  std::printf("%s %s: %.17g\n", passed ? "ok" : "FAILED", what, value);
  failures += passed ? 0 : 1;
}

// A mesh: the 4-8 patch of 8 × 8 cells on [−½, ½]² (81 vertices), written and read back (the
// writer's shortest round-trip decimals make it exact).
fm::Mesh loadMesh(const std::string& folder) {
  fm::GeneratorOptions options;
  options.family = fm::MeshFamily::Patch48;
  options.n = 8;
  fm::writeMesh(folder + "/patch.obj", fm::generateMesh(options));
  fm::Mesh mesh = fm::readMesh(folder + "/patch.obj");
  check(mesh.vertexCount() == 81 && mesh.faceCount() == 128, "vertices read", mesh.vertexCount());
  return mesh;
}

// An energy and its gradient: the cotan bending energy of the plate lifted onto z = p(x, y).
void energyAndGradient(const fm::Mesh& rest, const fm::PolynomialSurface& p, double expectedRho) {
  fm::Stencils stencils = fm::compileStencils(rest);
  fm::RestState restState = fm::precomputeRestState(stencils, rest.positions);
  fc::BendingOptions bending;
  bending.discretization = fc::Discretization::Cotan;
  std::unique_ptr<fc::EnergyTerm> energy = fc::makeBendingEnergy(stencils, restState, bending);

  fm::Positions x = rest.positions;
  fm::applyHeightField(p, x);
  const Eigen::VectorXd noXi;  // cotan owns no edge unknowns
  fo::EnergyGradient eg = fo::energyGradient({energy.get()}, x, noXi);
  check(eg.energy > 0 && std::abs(eg.energy - energy->energy(x, noXi)) <= 1e-14 * eg.energy, "E(p)",
        eg.energy);

  // ∂E/∂z of vertex 40 (the centre) against a central difference.
  const double h = 1e-6;
  fm::Positions plus = x, minus = x;
  plus(40, 2) += h;
  minus(40, 2) -= h;
  const double difference = (energy->energy(plus, noXi) - energy->energy(minus, noXi)) / (2 * h);
  check(std::abs(eg.gradient[3 * 40 + 2] - difference) <= 1e-6 * eg.gradient.cwiseAbs().maxCoeff(),
        "dE/dz at the centre", eg.gradient[3 * 40 + 2]);

  // C1: the linearized energy ½ |J u|² of the heights u, J the residual Jacobian at rest.
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * rest.vertexCount());
  for (int v = 0; v < rest.vertexCount(); ++v) u[3 * v + 2] = x(v, 2);
  const double rho =
      fo::linearizedEnergy(fo::residualJacobian({energy.get()}, rest.positions, noXi), u) /
      energy->coveredArea();
  check(std::abs(rho - expectedRho) <= 1e-10 * expectedRho, "C1: E_lin / A_cov", rho);
}

// A Problem and its minimizers: two rings held on the boundary surface, the rest free.
void minimizers(const fm::Mesh& rest, const fm::PolynomialSurface& p) {
  fo::ProblemOptions options;
  options.bending.discretization = fc::Discretization::Cotan;
  options.boundarySurface = p;  // fixedRings = 2, height mode: the defaults
  fo::Problem problem = fo::buildProblem(rest, options);

  fo::MinimizeOptions linearized;
  linearized.linearized = true;
  fo::MinimizeResult c2 = fo::minimize(problem, linearized);
  double error = 0.0, scale = 0.0;
  for (int v = 0; v < rest.vertexCount(); ++v) {
    const double pv = p.height(rest.positions(v, 0), rest.positions(v, 1));
    error = std::max(error, std::abs(c2.positions(v, 2) - pv));
    scale = std::max(scale, std::abs(pv));
  }
  check(c2.report.converged && error <= 1e-9 * scale, "C2: max |z - p| / max |p|", error / scale);

  // Newton on the nonlinear hinge energy from the rest heights, held rings on a plane.
  fo::ProblemOptions planeOptions;
  planeOptions.boundarySurface = fm::PolynomialSurface({{0.2, 1, 0}, {-0.1, 0, 1}});
  fo::Problem plane = fo::buildProblem(rest, planeOptions);
  fo::MinimizeOptions newton;
  newton.start = fo::Start::AsGiven;
  fo::MinimizeResult result = fo::minimize(plane, newton);
  double off = 0.0;
  for (int v = 0; v < rest.vertexCount(); ++v)
    off = std::max(off, std::abs(result.positions(v, 2) - 0.2 * rest.positions(v, 0) +
                                 0.1 * rest.positions(v, 1)));
  check(result.report.converged && result.report.iterations >= 1 && off <= 1e-8,
        "Newton: max |z - plane|", off);
  check(result.report.finalEnergy <= 1e-20, "Newton: final energy", result.report.finalEnergy);
}

// Time steps: the plate in xyz with a StVK membrane, one side pinned, falling under gravity.
void simulation(const fm::Mesh& rest) {
  fo::ProblemOptions options;
  options.dof = fo::DofMode::Xyz;
  options.membrane = fc::MembraneOptions{};  // StVK, Y = 1e3, ν = 0.3
  options.fixedVertex.assign(rest.vertexCount(), false);
  for (int v = 0; v < rest.vertexCount(); ++v)
    options.fixedVertex[v] = rest.positions(v, 0) < -0.49;
  options.load.gravity = Eigen::Vector3d(0, 0, -9.81);
  fo::Problem problem = fo::buildProblem(rest, options);

  fo::TimeStepper stepper(problem, fo::DynamicsOptions{});  // Newmark, β = ¼, γ = ½
  stepper.start(rest.positions, fm::Positions::Zero(rest.vertexCount(), 3), Eigen::VectorXd());
  int converged = 0;
  for (int step = 0; step < 20; ++step) converged += stepper.step(0.01).converged ? 1 : 0;
  const fo::TimeStepper::State state = stepper.state();
  const int corner = rest.vertexCount() - 1;  // (½, ½): the free side's corner
  double pinsMoved = 0.0;
  for (int v = 0; v < rest.vertexCount(); ++v)
    if (options.fixedVertex[v]) pinsMoved += (state.x.row(v) - rest.positions.row(v)).norm();
  check(converged == 20 && std::abs(state.time - 0.2) < 1e-12, "steps converged", converged);
  check(state.x(corner, 2) < -0.01 && pinsMoved == 0.0, "free corner's z at t = 0.2",
        state.x(corner, 2));
  check(state.balance.balancedWithin(0.05), "energy balance drift", state.balance.relativeDrift());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer FOLDER\n");
    return 2;
  }
  const fm::Mesh rest = loadMesh(argv[1]);
  const double a = 0.3, b = 0.1, c = -0.5;
  const fm::PolynomialSurface p = fm::PolynomialSurface::quadratic(a, b, c);
  energyAndGradient(rest, p, (2 * a + 2 * c) * (2 * a + 2 * c));
  minimizers(rest, p);
  simulation(rest);
  std::printf("%d check(s) failed\n", failures);
  return failures == 0 ? 0 : 1;
}
