#include "optimize/inelastic/pin_release.h"

#include "modeling/crack_cut.h"

namespace flexure::optimize {
namespace {

void releasePins(FracturingDynamics& dynamics, PlasticDynamics* plastic, double time) {
  if (dynamics.releasePins(time) && plastic != nullptr) plastic->follow(dynamics.stepper());
}

}  // namespace

TimeStepper::Advance advanceReleasingPins(FracturingDynamics& dynamics, PlasticDynamics* plastic,
                                          double h, double minStep, long step) {
  // The plastic state carried to each cut mesh while this call steps (and no longer after it).
  struct CarryAcrossCuts {
    FracturingDynamics& dynamics;
    ~CarryAcrossCuts() { dynamics.onCut(nullptr); }
  } carry{dynamics};
  if (plastic != nullptr && dynamics.fractures())
    dynamics.onCut([plastic](Problem& cut, const modeling::CrackCut& crack) {
      plastic->carryAcrossCut(cut, crack.faceOrigin);
    });
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
      total.addPart(dynamics.advance(part, minStep, step + total.steps));
      if (plastic != nullptr) plastic->follow(dynamics.stepper());  // a cut's, or the same
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
