// flexure._flexure.Simulation: a Problem in xyz and its TimeStepper, set up as flexure simulate
// sets them up (every coordinate free, no boundary rings held but the pins, midedge's boundary ξ
// held at rest with two pinned rings), with pin groups that move on their own, plasticity
// (plastic_dynamics.h: the update after each step) and fracture (fracturing.h: the cut mesh, its
// cracks and fragments).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "curvature/membrane_energy.h"
#include "modeling/errors.h"
#include "modeling/rest_state.h"
#include "optimize/assembly/obstacles.h"
#include "optimize/boundary_conditions.h"
#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracture.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/inelastic/pin_release.h"
#include "optimize/inelastic/plastic_dynamics.h"
#include "optimize/inelastic/plasticity.h"
#include "optimize/inelastic/simulation_spec.h"
#include "optimize/problem.h"
#include "python/bindings/bindings.h"

namespace py = pybind11;

namespace flexure::python {
namespace {

// A pinned group with its own motion, as the Python arguments name it: its vertices (a #V mask, or
// a spec of optimize::parseFixedSet) and a rigid motion (optimize::PinMotion) as in
// SimulationArguments.
// A mesh obstacle as the Python arguments give it: its vertices at time 0 and triangles, and a
// rigid motion (optimize::PinMotion) as in SimulationArguments.
struct MeshObstacleArguments {
  modeling::Positions positions = modeling::Positions(0, 3);
  modeling::Triangles faces = modeling::Triangles(0, 3);
  std::string motion = "none";  // none | rotate | translate
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), point = Eigen::Vector3d::Zero(),
                  velocity = Eigen::Vector3d::Zero();
  double omega = 0.0;
};

struct PinGroupArguments {
  std::optional<std::vector<bool>> mask;
  std::string spec = "none";
  std::string motion = "none";  // none | rotate | translate
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), point = Eigen::Vector3d::Zero(),
                  velocity = Eigen::Vector3d::Zero();
  double omega = 0.0;
  double releaseTime = std::numeric_limits<double>::infinity();  // optimize::PinGroup's
};

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
  std::vector<MeshObstacleArguments> meshObstacles;
  bool selfContact = true;
  double contactOffset = 0.0;  // d̂; 0: the rule's
  std::string integrator = "newmark";
  double beta = optimize::DynamicsOptions().beta, gamma = optimize::DynamicsOptions().gamma;
  double rayleighMass = 0.0, rayleighStiffness = 0.0, bendingDamping = 0.0;
  // The pins' rigid motion (optimize::PinMotion): "none", "rotate" (about `axis` through
  // `point` at `omega` rad/s) or "translate" (at `velocity`).
  std::string pinMotion = "none";
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), point = Eigen::Vector3d::Zero(),
                  velocity = Eigen::Vector3d::Zero();
  double omega = 0.0;
  // Pinned groups, each with its own motion (instead of pinned and pinMotion; the groups are
  // disjoint, DynamicsOptions::validatePinGroups).
  std::vector<PinGroupArguments> pinGroups;
  int maxNewtonIterations = optimize::DynamicsOptions().maxNewtonIterations;
  double stepTolerance = optimize::DynamicsOptions().stepTolerance;  // ε_v
  int quasiNewtonPairs = optimize::DynamicsOptions().quasiNewtonPairs;
  double energyTolerance = optimize::DynamicsOptions().energyTolerance;
  double friction = 0.0;                              // μ at every contact
  optimize::PlasticityOptions plasticity;             // no yield value: elastic
  std::optional<optimize::FractureOptions> fracture;  // empty: the shell never cracks
};

std::string groupName(size_t k) {
  return "pin_groups[" + std::to_string(k) + "]";
}

optimize::DynamicsOptions dynamicsOptions(const SimulationArguments& a) {
  optimize::DynamicsOptions d;
  d.integrator = optimize::parseIntegrator(a.integrator);
  d.beta = a.beta;
  d.gamma = a.gamma;
  d.rayleighMass = a.rayleighMass;
  d.rayleighStiffness = a.rayleighStiffness;
  d.bendingDamping = a.bendingDamping;
  d.pinMotion =
      optimize::makePinMotion(a.pinMotion, a.axis, a.point, a.omega, a.velocity, "pin_motion");
  for (size_t k = 0; k < a.pinGroups.size(); ++k) {
    const PinGroupArguments& g = a.pinGroups[k];
    d.pinGroups.push_back({{},
                           optimize::makePinMotion(g.motion, g.axis, g.point, g.omega, g.velocity,
                                                   groupName(k) + " motion"),
                           g.releaseTime});
  }
  d.maxNewtonIterations = a.maxNewtonIterations;
  d.stepTolerance = a.stepTolerance;
  d.quasiNewtonPairs = a.quasiNewtonPairs;
  d.energyTolerance = a.energyTolerance;
  d.friction = a.friction;
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
  p.load.mass = modeling::parseMassLumping(a.mass, "LoadOptions.mass");
  for (const std::string& spec : a.obstacles)
    p.obstacles.push_back(optimize::parseObstacle("obstacles", spec));
  for (size_t k = 0; k < a.meshObstacles.size(); ++k) {
    const MeshObstacleArguments& m = a.meshObstacles[k];
    const std::string name = "mesh_obstacles[" + std::to_string(k) + "]";
    p.meshObstacles.push_back(
        {modeling::Mesh{m.positions, m.faces},
         optimize::makePinMotion(m.motion, m.axis, m.point, m.omega, m.velocity, name + " motion"),
         name});
  }
  p.selfContact = a.selfContact;
  p.contactOffset = a.contactOffset;
  return p;
}

// The arguments mapped to the run's spec and the spec validated (optimize::SimulationSpec holds
// the rules; their messages name fields, which withKeywordNames turns into these arguments).
// The steps are given to advance, one call at a time.
optimize::SimulationSpec simulationSpec(const SimulationArguments& a) {
  optimize::SimulationSpec spec;
  spec.body = bodyOptions(a);
  spec.dynamics = dynamicsOptions(a);
  spec.plasticity = a.plasticity;
  spec.fracture = a.fracture;
  spec.validate();
  return spec;
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

// The pinned vertices (ProblemOptions.fixedVertex: pinned's and every group's; with an energy
// that owns edge unknowns, the ξ a spec clamps) and each group's vertices (DynamicsOptions.
// pinGroups, whose motions dynamicsOptions set), checked as the library checks them.
void placePins(const SimulationArguments& a, const modeling::Stencils& stencils,
               const Positions& rest, optimize::ProblemOptions& p, optimize::DynamicsOptions& d) {
  const int n = stencils.vertexCount();
  const bool clamps =
      static_cast<bool>(curvature::energyEntry(p.bending.discretization).restEdgeUnknowns);
  const auto vertexSet = [&](const std::optional<std::vector<bool>>& mask, const std::string& spec,
                             const std::string& source) {
    if (mask) return *mask;
    if (spec == "none") return std::vector<bool>(n, false);
    return optimize::parseFixedSet(source, spec, stencils, rest);
  };
  p.fixedVertex = vertexSet(a.pinnedMask, a.pinnedSpec, "pinned");
  if (!a.pinnedMask && clamps) p.fixedEdge = optimize::clampedBoundaryEdges(a.pinnedSpec, stencils);
  for (size_t k = 0; k < a.pinGroups.size(); ++k) {
    const PinGroupArguments& g = a.pinGroups[k];
    d.pinGroups[k].vertices = vertexSet(g.mask, g.spec, groupName(k));
    const std::vector<bool>& group = d.pinGroups[k].vertices;
    for (size_t v = 0; v < group.size() && v < p.fixedVertex.size(); ++v)
      p.fixedVertex[v] = p.fixedVertex[v] || group[v];
    if (g.mask || !clamps) continue;
    const std::vector<bool> clamped = optimize::clampedBoundaryEdges(g.spec, stencils);
    if (clamped.empty()) continue;
    p.fixedEdge.resize(clamped.size(), false);
    for (size_t e = 0; e < clamped.size(); ++e) p.fixedEdge[e] = p.fixedEdge[e] || clamped[e];
  }
  d.validatePinGroups(n);
}

py::dict crackDict(const optimize::CrackEvent& c) {
  py::dict d;
  d["time"] = c.time;
  d["step"] = c.step;
  d["face"] = c.critical.face;
  d["strain"] = c.critical.strain;
  d["strain_direction"] = c.critical.strainDirection;
  d["crack_direction"] = c.critical.crackDirection;
  d["fibre"] = c.critical.fibre;
  d["polyline_rest"] = c.rest;
  d["polyline_current"] = c.current;
  d["released_energy"] = c.released;
  d["fragments"] = c.fragments;
  return d;
}

// A body in time: the problem and its stepper (rebuilt on the cut mesh after each crack,
// fracturing.h) and the plastic state. Not movable: the stepper and the plastic update keep
// references into the problem.
class BoundSimulation {
 public:
  BoundSimulation(const PositionsRef& restV, const TrianglesRef& F, const SimulationArguments& a,
                  const std::optional<Positions>& start, const std::optional<Positions>& velocity) {
    optimize::SimulationSpec spec = simulationSpec(a);
    optimize::DynamicsOptions& dynamics = spec.dynamics;
    optimize::ProblemOptions& p = spec.body;
    const modeling::Mesh rest = checkedMesh(restV, F, "V_rest, F");
    py::gil_scoped_release release;
    modeling::Stencils stencils = modeling::compileStencils(rest);
    modeling::RestState restState = modeling::precomputeRestState(stencils, rest.positions);
    placePins(a, stencils, restState.positions, p, dynamics);
    p.boundaryPositions = start ? *start : rest.positions;
    optimize::Problem problem =
        optimize::buildProblem(std::move(stencils), std::move(restState), p);
    const Positions startPositions = problem.boundary.start;
    dynamics_ = std::make_unique<optimize::FracturingDynamics>(rest, std::move(problem), p,
                                                               dynamics, spec.fracture);
    dynamics_->start(startPositions, velocity ? *velocity : Positions::Zero(rest.vertexCount(), 3));
    if (a.plasticity.enabled())
      plastic_ = std::make_unique<optimize::PlasticDynamics>(dynamics_->problem(),
                                                             dynamics_->stepper(), a.plasticity);
  }

  // h as flexure simulate takes each step: halved while Newton fails or to find a fracture event,
  // the fracture check after each accepted step, split where a pin group is let go, then the
  // plastic update (optimize::advanceReleasingPins; also after the steps that converged when a
  // later one failed).
  // `minStep` 0: the library's default (optimize::TimeSteps::smallestStep).
  py::dict advance(double h, double minStep) {
    optimize::TimeSteps steps;
    steps.dt = h;
    steps.minDt = minStep;
    steps.validate();
    optimize::TimeStepper::Advance a;
    {
      py::gil_scoped_release release;
      a = optimize::advanceReleasingPins(*dynamics_, plastic_.get(), h, steps.smallestStep(),
                                         steps_);
      steps_ += a.steps;
      if (plastic_ && !a.completed && a.steps > 0) plastic_->afterStep();
    }
    return advanceDict(a, stepper().time());
  }

  py::dict energies() const {
    const optimize::EnergySample e = stepper().energies();
    py::dict d;
    d["time"] = e.time;
    d["kinetic"] = e.kinetic;
    const std::vector<const curvature::EnergyTerm*> terms = problem().termPointers();
    for (size_t k = 0; k < terms.size(); ++k) d[py::str(terms[k]->name())] = e.terms[k];
    d["gravity"] = e.gravity;
    d["contact"] = e.contact;
    if (plastic_) d["plastic_dissipation"] = stepper().balance().plastic;
    d["total"] = e.total();
    return d;
  }

  // The run's energy balance (time_stepping.h EnergyBalance), as simulate's report.json has it.
  py::dict balance() const {
    const optimize::EnergyBalance& b = stepper().balance();
    py::dict d;
    d["largest_drift"] = b.largestDrift;
    d["relative_drift"] = b.relativeDrift();
    d["time"] = b.driftTime;
    d["step"] = b.driftStep;
    d["scale"] = b.scale();
    d["peak_kinetic"] = b.peakKinetic;
    d["initial_total"] = b.initial;
    d["dissipated"] = b.dissipated;
    d["plastic_dissipation"] = b.plastic;
    d["contact_stiffening"] = b.stiffening;
    d["checked"] = stepper().balanceChecked();
    d["tolerance"] = dynamics_->dynamics().energyTolerance;
    d["verdict"] = optimize::balanceVerdictName(stepper().balanceVerdict());
    const std::string failure = stepper().balanceFailure();
    d["failure"] = failure.empty() ? py::object(py::none()) : py::object(py::str(failure));
    return d;
  }

  // The plastic state (plasticity.h PlasticState): the bending term's elements' and the membrane's
  // faces'; None without plasticity.
  py::object plasticState() const {
    if (!plastic_) return py::none();
    const optimize::PlasticState& s = plastic_->state();
    py::dict d;
    d["element"] = plastic_->elementKind();
    d["plastic_strain"] = s.plasticStrain;
    d["plastic_curvature"] = optimize::equivalentPlasticCurvatures(s);
    d["yielded"] = s.yielded;
    d["vertex_plastic_curvature"] = plastic_->vertexPlasticCurvatures();
    d["membrane_plastic_strain"] = optimize::equivalentPlasticStrains(s);
    d["vertex_membrane_plastic_strain"] = plastic_->vertexPlasticStrains();
    d["dissipation"] = s.dissipation;
    return d;
  }

  py::list cracks() const {
    py::list list;
    for (const optimize::CrackEvent& c : dynamics_->cracks()) list.append(crackDict(c));
    return list;
  }

  // The connected pieces of the current mesh (meshFragments), at their current positions or, with
  // `atRest`, at rest (the same pieces and numbering: both depend on the triangles alone).
  py::list fragments(bool atRest) const {
    std::vector<modeling::Mesh> pieces;
    {
      py::gil_scoped_release release;
      pieces = atRest ? optimize::meshFragments(restMesh()) : dynamics_->fragments();
    }
    py::list list;
    for (const modeling::Mesh& piece : pieces)
      list.append(py::make_tuple(piece.positions, piece.triangles));
    return list;
  }

  std::vector<std::string> termNames() const {
    std::vector<std::string> names;
    for (const curvature::EnergyTerm* term : problem().termPointers())
      names.push_back(term->name());
    return names;
  }

  const optimize::Problem& problem() const { return dynamics_->problem(); }
  const optimize::TimeStepper& stepper() const { return dynamics_->stepper(); }
  const modeling::Mesh& restMesh() const { return dynamics_->restMesh(); }

 private:
  std::unique_ptr<optimize::FracturingDynamics> dynamics_;
  std::unique_ptr<optimize::PlasticDynamics> plastic_;
  long steps_ = 0;  // accepted steps so far (CrackEvent::step)
};

}  // namespace

void bindSimulation(py::module_& m) {
  m.def(
      "step_count",
      [](double dt, double duration) {
        optimize::TimeSteps steps;
        steps.dt = dt;
        steps.duration = duration;
        steps.validate();
        return steps.stepCount();
      },
      "duration / dt, validated as a run's steps (optimize::TimeSteps)");
  // The library's inelastic options, field by field (their validate() names the fields).
  py::class_<optimize::PlasticityOptions>(m, "PlasticityOptions")
      .def(py::init<>())
      .def_readwrite("yield_curvature", &optimize::PlasticityOptions::yieldCurvature)
      .def_readwrite("yield_strain", &optimize::PlasticityOptions::yieldStrain)
      .def_readwrite("hardening", &optimize::PlasticityOptions::hardening);
  py::class_<optimize::FormingOptions>(m, "FormingOptions")
      .def(py::init<>())
      .def_readwrite("load_steps", &optimize::FormingOptions::loadSteps)
      .def_readwrite("release", &optimize::FormingOptions::release)
      .def_readwrite("max_updates_per_step", &optimize::FormingOptions::maxUpdatesPerStep)
      .def_readwrite("tolerance", &optimize::FormingOptions::tolerance);
  py::class_<optimize::FractureOptions>(m, "FractureOptions")
      .def(py::init<>())
      .def_readwrite("fracture_strain", &optimize::FractureOptions::fractureStrain)
      .def_readwrite("thickness", &optimize::FractureOptions::thickness);

  py::class_<MeshObstacleArguments>(m, "MeshObstacleArguments")
      .def(py::init<>())
      .def_readwrite("positions", &MeshObstacleArguments::positions)
      .def_readwrite("faces", &MeshObstacleArguments::faces)
      .def_readwrite("motion", &MeshObstacleArguments::motion)
      .def_readwrite("axis", &MeshObstacleArguments::axis)
      .def_readwrite("point", &MeshObstacleArguments::point)
      .def_readwrite("omega", &MeshObstacleArguments::omega)
      .def_readwrite("velocity", &MeshObstacleArguments::velocity);

  py::class_<PinGroupArguments>(m, "PinGroupArguments")
      .def(py::init<>())
      .def_readwrite("mask", &PinGroupArguments::mask)
      .def_readwrite("spec", &PinGroupArguments::spec)
      .def_readwrite("motion", &PinGroupArguments::motion)
      .def_readwrite("axis", &PinGroupArguments::axis)
      .def_readwrite("point", &PinGroupArguments::point)
      .def_readwrite("omega", &PinGroupArguments::omega)
      .def_readwrite("velocity", &PinGroupArguments::velocity)
      .def_readwrite("release_time", &PinGroupArguments::releaseTime);

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
      .def_readwrite("mesh_obstacles", &SimulationArguments::meshObstacles)
      .def_readwrite("self_contact", &SimulationArguments::selfContact)
      .def_readwrite("contact_offset", &SimulationArguments::contactOffset)
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
      .def_readwrite("pin_groups", &SimulationArguments::pinGroups)
      .def_readwrite("max_newton_iterations", &SimulationArguments::maxNewtonIterations)
      .def_readwrite("step_tolerance", &SimulationArguments::stepTolerance)
      .def_readwrite("quasi_newton_pairs", &SimulationArguments::quasiNewtonPairs)
      .def_readwrite("energy_tolerance", &SimulationArguments::energyTolerance)
      .def_readwrite("friction", &SimulationArguments::friction)
      .def_readwrite("plasticity", &SimulationArguments::plasticity)
      .def_readwrite("fracture", &SimulationArguments::fracture);

  py::class_<BoundSimulation>(m, "Simulation")
      .def(py::init<const PositionsRef&, const TrianglesRef&, const SimulationArguments&,
                    const std::optional<Positions>&, const std::optional<Positions>&>())
      .def("advance", &BoundSimulation::advance)
      .def("energies", &BoundSimulation::energies)
      .def("balance", &BoundSimulation::balance)
      .def("plastic_state", &BoundSimulation::plasticState)
      .def("cracks", &BoundSimulation::cracks)
      .def("fragments", &BoundSimulation::fragments)
      .def_property_readonly("rest_positions",
                             [](const BoundSimulation& s) { return s.restMesh().positions; })
      .def_property_readonly("triangles",
                             [](const BoundSimulation& s) { return s.restMesh().triangles; })
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
      .def_property_readonly(
          "smallest_obstacle_distance",
          [](const BoundSimulation& s) {
            return s.stepper().barrier().smallestDistance(s.stepper().positions());
          })
      .def_property_readonly("contact", [](const BoundSimulation& s) {
        const optimize::TimeStepper::ContactStatistics& c = s.stepper().contactStatistics();
        py::dict d;
        d["self_contact"] =
            !s.stepper().selfContact().empty() && s.stepper().selfContact().shellPairs();
        d["offset"] = s.stepper().selfContact().layer();
        d["smallest_distance"] = c.smallestDistance;
        d["mean_pairs"] = c.steps > 0 ? c.pairs / c.steps : 0.0;
        d["peak_pairs"] = c.peakPairs;
        d["detection_seconds"] = c.detectionSeconds;
        d["pattern_growths"] = c.patternGrowths;
        return d;
      });
}

}  // namespace flexure::python
