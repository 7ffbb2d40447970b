#include "optimize/inelastic/simulation_spec.h"

#include <cmath>
#include <string>

#include "curvature/energy_registry.h"
#include "modeling/errors.h"

namespace flexure::optimize {
namespace {

// The yield field a message names: the curvature's when given, else the strain's.
std::string yieldField(const PlasticityOptions& p) {
  return p.yieldCurvature ? "PlasticityOptions.yieldCurvature" : "PlasticityOptions.yieldStrain";
}

void validatePlasticity(const SimulationSpec& s) {
  const PlasticityOptions& p = s.plasticity;
  p.validate();
  if (!p.enabled()) {
    if (p.hardening != 0.0)
      throw InputError(
          "PlasticityOptions.hardening: the plastic hardening needs a yield value: give "
          "PlasticityOptions.yieldCurvature or PlasticityOptions.yieldStrain");
    return;
  }
  const curvature::EnergyEntry& energy = curvature::energyEntry(s.body.bending.discretization);
  if (p.yieldCurvature && !energy.plasticRestCurvature)
    throw InputError("PlasticityOptions.yieldCurvature: the " + energy.name +
                     " energy has no per-element rest curvature that a plastic strain could "
                     "move; use " +
                     curvature::energyNamesWhere(
                         [](const curvature::EnergyEntry& e) { return e.plasticRestCurvature; }));
  if (p.yieldStrain &&
      (!s.body.membrane || s.body.membrane->model != curvature::MembraneModel::Stvk))
    throw InputError(
        "PlasticityOptions.yieldStrain: membrane plasticity moves the rest metric of "
        "ProblemOptions.membrane stvk");
  if (s.checkpointed)
    throw InputError(yieldField(p) +
                     ": not with SimulationSpec.checkpointed (a checkpoint does not keep the "
                     "plastic strains)");
}

void validateFracture(const SimulationSpec& s) {
  if (!s.fracture) return;
  s.fracture->validate();
  if (s.checkpointed)
    throw InputError(
        "FractureOptions.fractureStrain: not with SimulationSpec.checkpointed (a checkpoint keeps "
        "one mesh; a crack changes it)");
}

void validateReleases(const SimulationSpec& s) {
  for (const PinGroup& group : s.dynamics.pinGroups) {
    if (!std::isfinite(group.releaseTime)) continue;
    if (s.checkpointed)
      throw InputError(
          "PinGroup.releaseTime: not with SimulationSpec.checkpointed (a checkpoint keeps the "
          "pins of the run's start)");
    if (s.steps.duration > 0.0 && group.releaseTime > s.steps.duration)
      throw InputError("PinGroup.releaseTime " + numberText(group.releaseTime) +
                       ": after the run's end (TimeSteps.duration " + numberText(s.steps.duration) +
                       "); the group would never be let go");
  }
}

}  // namespace

void TimeSteps::validate() const {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError("TimeSteps.dt: expected a time step > 0 (got " + numberText(dt) + ")");
  if (!(minDt >= 0.0) || minDt > dt)
    throw InputError("TimeSteps.minDt: expected a step in (0, TimeSteps.dt] (got " +
                     numberText(minDt) + ")");
  if (duration == 0.0) return;
  if (!(duration > 0.0) || !std::isfinite(duration))
    throw InputError("TimeSteps.duration: expected a time > 0 (got " + numberText(duration) + ")");
  const double steps = duration / dt;
  if (steps > kMaxSteps)
    throw InputError("TimeSteps.duration / TimeSteps.dt: more than 10^7 steps");
  const double whole = std::round(steps);
  if (whole >= 1.0 && std::abs(steps - whole) <= 1e-9 * whole) return;
  const double below = std::floor(steps), above = std::ceil(steps);
  throw InputError("TimeSteps.duration " + numberText(duration) +
                   ": not a whole number of steps of " + numberText(dt) + " (" + numberText(steps) +
                   "); give " + (below >= 1.0 ? numberText(below * dt) + " or " : std::string()) +
                   numberText(above * dt));
}

long TimeSteps::stepCount() const {
  return duration > 0.0 ? std::lround(duration / dt) : 0;
}

void SimulationSpec::validate() const {
  if (body.dof != DofMode::Xyz)
    throw InputError("ProblemOptions.dof: a simulation moves every coordinate (xyz)");
  if (!body.membrane)
    throw InputError(
        "ProblemOptions.membrane: a simulation moves every coordinate: give a membrane; bending "
        "alone has no stiffness against stretching");
  body.validate();
  dynamics.validate();
  validatePlasticity(*this);
  validateFracture(*this);
  if (steps.dt != 0.0 || steps.duration != 0.0) steps.validate();
  validateReleases(*this);
}

}  // namespace flexure::optimize
