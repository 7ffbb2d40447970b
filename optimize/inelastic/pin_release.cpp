#include "optimize/inelastic/pin_release.h"

#include <algorithm>

namespace flexure::optimize {
namespace {

// `part`'s counts added to `total`, which then ends as `part` did.
void addPart(TimeStepper::Advance& total, const TimeStepper::Advance& part) {
  total.completed = part.completed;
  total.steps += part.steps;
  total.halvings += part.halvings;
  total.smallestStep = std::min(total.smallestStep, part.smallestStep);
  total.newtonIterations += part.newtonIterations;
  total.maxNewtonIterations = std::max(total.maxNewtonIterations, part.maxNewtonIterations);
  total.attemptedIterations += part.attemptedIterations;
  total.factorizations += part.factorizations;
  total.pcgSolves += part.pcgSolves;
  total.pcgIterations += part.pcgIterations;
  total.hessians += part.hessians;
  total.failure = part.failure;
  total.failedStep = part.failedStep;
  total.failedTime = part.failedTime;
}

void releasePins(FracturingDynamics& dynamics, PlasticDynamics* plastic, double time) {
  if (dynamics.releasePins(time) && plastic != nullptr) plastic->follow(dynamics.stepper());
}

}  // namespace

TimeStepper::Advance advanceReleasingPins(FracturingDynamics& dynamics, PlasticDynamics* plastic,
                                          double h, double minStep, long step) {
  TimeStepper::Advance total;
  total.completed = true;
  total.smallestStep = h;
  const double slack = 1e-9 * h;
  double left = h;  // a step that reaches no release time is exactly h, as without releases
  while (true) {
    const double release = dynamics.nextRelease();
    const bool reached = release - dynamics.stepper().time() < left + slack;
    const double part = reached ? release - dynamics.stepper().time() : left;
    if (part > slack) {
      addPart(total, dynamics.advance(part, minStep, step + total.steps));
      if (!total.completed) return total;
      if (plastic != nullptr) plastic->afterStep();
      left -= part;
    }
    if (!reached) return total;
    releasePins(dynamics, plastic, release);
    if (left <= slack) return total;
  }
}

}  // namespace flexure::optimize
