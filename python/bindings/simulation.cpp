// flexure._flexure.Simulation: a Problem in xyz and its TimeStepper, set up as flexure simulate
// sets them up (every coordinate free, no boundary rings held but the pins, midedge's boundary ξ
// held at rest with two pinned rings).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "curvature/membrane_energy.h"
#include "modeling/errors.h"
#include "modeling/rest_state.h"
#include "optimize/boundary_conditions.h"
#include "optimize/dynamics/obstacles.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/problem.h"
#include "python/bindings/bindings.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

// Everything the simulated body and its dynamics take, as the Python arguments name them.
struct SimulationArguments : MembraneFields {
  BendingArguments bending;
  std::string membrane = "stvk";
  // The pinned vertices: a #V mask, or a spec of optimize::parseFixedSet ("rings:K",
  // "vertices:FILE"); neither: none.
  std::optional<std::vector<bool>> pinnedMask;
  std::string pinnedSpec = "none";
  std::optional<Eigen::Vector3d> gravity;
  double density = 1.0;
  std::string mass = "barycentric";
  std::vector<std::string> obstacles;  // plane:nx,ny,nz,d | sphere:x,y,z,r
  std::string integrator = "newmark";
  double beta = 0.25, gamma = 0.5;
  double rayleighMass = 0.0, rayleighStiffness = 0.0, bendingDamping = 0.0;
  // The pins' rigid motion (optimize::PinMotion): "none", "rotate" (about `axis` through
  // `point` at `omega` rad/s) or "translate" (at `velocity`).
  std::string pinMotion = "none";
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), point = Eigen::Vector3d::Zero(),
                  velocity = Eigen::Vector3d::Zero();
  double omega = 0.0;
  int maxNewtonIterations = 30;
  double tolerance = 1e-10;
};

optimize::Integrator integrator(const std::string& name) {
  if (name == "newmark") return optimize::Integrator::Newmark;
  if (name == "backward-euler") return optimize::Integrator::BackwardEuler;
  if (name == "central-difference") return optimize::Integrator::CentralDifference;
  throw InputError("integrator " + name +
                   ": expected newmark, backward-euler or central-difference");
}

modeling::MassLumping massLumping(const std::string& name) {
  if (name == "barycentric") return modeling::MassLumping::Barycentric;
  if (name == "voronoi") return modeling::MassLumping::Voronoi;
  throw InputError("mass " + name + ": expected barycentric or voronoi");
}

optimize::DynamicsOptions dynamicsOptions(const SimulationArguments& a) {
  optimize::DynamicsOptions d;
  d.integrator = integrator(a.integrator);
  d.beta = a.beta;
  d.gamma = a.gamma;
  d.rayleighMass = a.rayleighMass;
  d.rayleighStiffness = a.rayleighStiffness;
  d.bendingDamping = a.bendingDamping;
  if (a.pinMotion == "rotate") {
    if (!(a.axis.norm() > 0.0)) throw InputError("pin_motion: the rotation axis is zero");
    d.pinMotion.kind = optimize::PinMotion::Kind::Rotate;
    d.pinMotion.axis = a.axis.normalized();
    d.pinMotion.point = a.point;
    d.pinMotion.omega = a.omega;
  } else if (a.pinMotion == "translate") {
    d.pinMotion.kind = optimize::PinMotion::Kind::Translate;
    d.pinMotion.velocity = a.velocity;
  } else if (a.pinMotion != "none") {
    throw InputError("pin_motion " + a.pinMotion + ": expected rotate or translate");
  }
  d.maxNewtonIterations = a.maxNewtonIterations;
  d.tolerance = a.tolerance;
  d.validate();
  return d;
}

// simulate's bodyOptions: bending and membrane, every coordinate free, the load and obstacles.
optimize::ProblemOptions bodyOptions(const SimulationArguments& a) {
  optimize::ProblemOptions p;
  p.bending = bendingOptions(a.bending);
  p.membrane = a.membraneOptions(a.membrane);
  p.dof = optimize::DofMode::Xyz;
  p.fixedRings = 0;
  p.boundaryNormals = optimize::BoundaryNormals::Free;
  p.load.gravity = a.gravity;
  p.load.density = a.density;
  p.load.mass = massLumping(a.mass);
  for (const std::string& spec : a.obstacles)
    p.obstacles.push_back(optimize::parseObstacle("obstacles", spec));
  p.validate();
  return p;
}

py::dict advanceDict(const optimize::TimeStepper::Advance& a, double time) {
  py::dict d;
  d["completed"] = a.completed;
  d["time"] = time;
  d["steps"] = a.steps;
  d["halvings"] = a.halvings;
  d["smallest_step"] = a.smallestStep;
  d["newton_iterations"] = a.newtonIterations;
  d["max_newton_iterations"] = a.maxNewtonIterations;
  d["attempted_iterations"] = a.attemptedIterations;
  d["factorizations"] = a.factorizations;
  if (!a.completed) {
    d["failure"] = a.failure.failure;
    d["failed_step"] = a.failedStep;
    d["failed_time"] = a.failedTime;
  }
  return d;
}

// A body in time. The problem is kept here (the stepper keeps references into it); not movable.
class BoundSimulation {
 public:
  BoundSimulation(const PositionsRef& restV, const TrianglesRef& F, const SimulationArguments& a,
                  const std::optional<Positions>& start, const std::optional<Positions>& velocity)
      : dynamics_(dynamicsOptions(a)) {
    optimize::ProblemOptions p = bodyOptions(a);
    const modeling::Mesh rest = checkedMesh(restV, F, "V_rest, F");
    if (start && start->rows() != rest.positions.rows())
      throw InputError("V_start has " + std::to_string(start->rows()) + " rows, the mesh " +
                       std::to_string(rest.positions.rows()) + " vertices");
    if (velocity && velocity->rows() != rest.positions.rows())
      throw InputError("velocities has " + std::to_string(velocity->rows()) + " rows, the mesh " +
                       std::to_string(rest.positions.rows()) + " vertices");
    py::gil_scoped_release release;
    modeling::Stencils stencils = modeling::compileStencils(rest);
    modeling::RestState restState = modeling::precomputeRestState(stencils, rest.positions);
    if (a.pinnedMask) {
      p.fixedVertex = *a.pinnedMask;
    } else {
      p.fixedVertex =
          a.pinnedSpec == "none"
              ? std::vector<bool>(rest.vertexCount(), false)
              : optimize::parseFixedSet("pinned", a.pinnedSpec, stencils, restState.positions);
      if (curvature::energyEntry(p.bending.discretization).restEdgeUnknowns)
        p.fixedEdge = optimize::clampedBoundaryEdges(a.pinnedSpec, stencils);
    }
    p.boundaryPositions = start ? *start : rest.positions;
    problem_ = std::make_unique<optimize::Problem>(
        optimize::buildProblem(std::move(stencils), std::move(restState), p));
    stepper_ = std::make_unique<optimize::TimeStepper>(*problem_, dynamics_);
    stepper_->start(problem_->boundary.start,
                    velocity ? *velocity : Positions::Zero(rest.vertexCount(), 3),
                    Eigen::VectorXd());
  }

  py::dict advance(double h, double minStep) {
    optimize::TimeStepper::Advance a;
    {
      py::gil_scoped_release release;
      a = stepper_->advance(h, minStep);
    }
    return advanceDict(a, stepper_->time());
  }

  py::dict energies() const {
    const optimize::EnergySample e = stepper_->energies();
    py::dict d;
    d["time"] = e.time;
    d["kinetic"] = e.kinetic;
    const std::vector<const curvature::EnergyTerm*> terms = problem_->termPointers();
    for (size_t k = 0; k < terms.size(); ++k) d[py::str(terms[k]->name())] = e.terms[k];
    d["gravity"] = e.gravity;
    d["contact"] = e.contact;
    d["total"] = e.total();
    return d;
  }

  // The run's energy balance (time_stepping.h EnergyBalance), as simulate's report.json has it.
  py::dict balance() const {
    const optimize::EnergyBalance& b = stepper_->balance();
    py::dict d;
    d["largest_drift"] = b.largestDrift;
    d["relative_drift"] = b.relativeDrift();
    d["time"] = b.driftTime;
    d["step"] = b.driftStep;
    d["scale"] = b.scale();
    d["peak_kinetic"] = b.peakKinetic;
    d["initial_total"] = b.initial;
    d["dissipated"] = b.dissipated;
    d["contact_stiffening"] = b.stiffening;
    d["checked"] = stepper_->balanceChecked();
    return d;
  }

  std::vector<std::string> termNames() const {
    std::vector<std::string> names;
    for (const curvature::EnergyTerm* term : problem_->termPointers())
      names.push_back(term->name());
    return names;
  }

  const optimize::Problem& problem() const { return *problem_; }
  const optimize::TimeStepper& stepper() const { return *stepper_; }

 private:
  optimize::DynamicsOptions dynamics_;
  std::unique_ptr<optimize::Problem> problem_;
  std::unique_ptr<optimize::TimeStepper> stepper_;
};

}  // namespace

void bindSimulation(py::module_& m) {
  py::class_<SimulationArguments> simulationArguments(m, "SimulationArguments");
  defMembraneFields(simulationArguments)
      .def(py::init<>())
      .def_readwrite("bending", &SimulationArguments::bending)
      .def_readwrite("membrane", &SimulationArguments::membrane)
      .def_readwrite("pinned_mask", &SimulationArguments::pinnedMask)
      .def_readwrite("pinned_spec", &SimulationArguments::pinnedSpec)
      .def_readwrite("gravity", &SimulationArguments::gravity)
      .def_readwrite("density", &SimulationArguments::density)
      .def_readwrite("mass", &SimulationArguments::mass)
      .def_readwrite("obstacles", &SimulationArguments::obstacles)
      .def_readwrite("integrator", &SimulationArguments::integrator)
      .def_readwrite("beta", &SimulationArguments::beta)
      .def_readwrite("gamma", &SimulationArguments::gamma)
      .def_readwrite("rayleigh_mass", &SimulationArguments::rayleighMass)
      .def_readwrite("rayleigh_stiffness", &SimulationArguments::rayleighStiffness)
      .def_readwrite("bending_damping", &SimulationArguments::bendingDamping)
      .def_readwrite("pin_motion", &SimulationArguments::pinMotion)
      .def_readwrite("axis", &SimulationArguments::axis)
      .def_readwrite("point", &SimulationArguments::point)
      .def_readwrite("omega", &SimulationArguments::omega)
      .def_readwrite("velocity", &SimulationArguments::velocity)
      .def_readwrite("max_newton_iterations", &SimulationArguments::maxNewtonIterations)
      .def_readwrite("tolerance", &SimulationArguments::tolerance);

  py::class_<BoundSimulation>(m, "Simulation")
      .def(py::init<const PositionsRef&, const TrianglesRef&, const SimulationArguments&,
                    const std::optional<Positions>&, const std::optional<Positions>&>())
      .def("advance", &BoundSimulation::advance)
      .def("energies", &BoundSimulation::energies)
      .def("balance", &BoundSimulation::balance)
      .def_property_readonly("term_names", &BoundSimulation::termNames)
      .def_property_readonly("time", [](const BoundSimulation& s) { return s.stepper().time(); })
      .def_property_readonly("positions",
                             [](const BoundSimulation& s) { return s.stepper().positions(); })
      .def_property_readonly("velocities",
                             [](const BoundSimulation& s) { return s.stepper().velocities(); })
      .def_property_readonly("xi", [](const BoundSimulation& s) { return s.stepper().xi(); })
      .def_property_readonly("masses",
                             [](const BoundSimulation& s) { return s.stepper().masses(); })
      .def_property_readonly(
          "pinned", [](const BoundSimulation& s) { return s.problem().boundary.fixedVertex; })
      .def_property_readonly("gravity",
                             [](const BoundSimulation& s) { return s.problem().gravity; })
      .def_property_readonly("smallest_obstacle_distance", [](const BoundSimulation& s) {
        return s.stepper().barrier().smallestDistance(s.stepper().positions());
      });
}

}  // namespace flexure::python
