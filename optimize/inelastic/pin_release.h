// Pin groups let go mid-run (PinGroup::releaseTime; issue #29: a sheet folded by a moving pin and
// released keeps its crease by the simulation's own plastic state). A step that reaches a release
// time is split there: the part up to it, the release (FracturingDynamics::releasePins: the problem
// no longer holds the group's vertices, and a stepper built without them continues the state, as
// after a cut), then the rest. The plastic update runs after each part and follows the new stepper
// (PlasticDynamics::follow), so the plastic strains carry over the release. With fracture each cut
// carries them to the cut mesh (PlasticDynamics::carryAcrossCut, called by the cut:
// FracturingDynamics::onCut), and the plastic update follows the stepper built for it.
#pragma once

#include "optimize/dynamics/time_stepping.h"
#include "optimize/inelastic/fracturing.h"
#include "optimize/inelastic/plastic_dynamics.h"

namespace flexure::optimize {

// Advances by h as FracturingDynamics::advance(h, minStep, step) does, each part followed by the
// plastic update of `plastic` (null: none), letting go of the pin groups whose release time the
// step reaches (within 1e-9 h of its end: at its end). The counts of the parts added up; a part
// that fails ends the advance there. With both plasticity and fracture, `dynamics` calls
// plastic->carryAcrossCut at each cut during the call (its cut listener, cleared on return).
TimeStepper::Advance advanceReleasingPins(FracturingDynamics& dynamics, PlasticDynamics* plastic,
                                          double h, double minStep, long step);

}  // namespace flexure::optimize
