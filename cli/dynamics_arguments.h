// The command-line names of simulate's dynamics: --integrator newmark | backward-euler |
// central-difference and --pin-motion rotate:ax,ay,az,px,py,pz,omega | translate:vx,vy,vz
// (optimize/dynamics/time_stepping.h).
#pragma once

#include <string>

#include "optimize/dynamics/time_stepping.h"

namespace flexure::cli {

// newmark | backward-euler | central-difference (InputError naming --integrator otherwise).
optimize::Integrator parseIntegrator(const std::string& name);

// rotate:ax,ay,az,px,py,pz,omega or translate:vx,vy,vz (InputError naming --pin-motion
// otherwise: a zero axis, a number that is not finite, a wrong count).
optimize::PinMotion parsePinMotion(const std::string& spec);

}  // namespace flexure::cli
