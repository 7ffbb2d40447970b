// The command-line names of simulate's dynamics: --integrator newmark | backward-euler |
// central-difference and --pin-motion rotate:ax,ay,az,px,py,pz,omega | translate:vx,vy,vz
// (optimize/dynamics/time_stepping.h), and the pinned groups of a repeatable --pin
// SET[@MOTION][@release:T].
#pragma once

#include <string>
#include <vector>

#include "modeling/stencils.h"
#include "optimize/dynamics/time_stepping.h"

namespace flexure::cli {

// newmark | backward-euler | central-difference (InputError naming --integrator otherwise).
optimize::Integrator parseIntegrator(const std::string& name);

// rotate:ax,ay,az,px,py,pz,omega or translate:vx,vy,vz (InputError naming --pin-motion
// otherwise: a zero axis, a number that is not finite, a wrong count).
// `option` names the text's source in the message (--pin-motion, or a --pin group).
optimize::PinMotion parsePinMotion(const std::string& spec,
                                   const std::string& option = "--pin-motion");

// The pinned vertices of the --pin groups, each SET[@MOTION][@release:T] (SET as
// optimize::parseFixedSet reads it, MOTION as parsePinMotion, T the time the group is let go):
// their union and, for the groups with a motion or a release, each group.
struct PinnedGroups {
  std::vector<bool> held;                  // #V
  std::vector<optimize::PinGroup> groups;  // the groups that carry a motion or a release
  std::vector<bool> clampedEdges;          // #E or empty: optimize::clampedBoundaryEdges
};
PinnedGroups pinnedGroups(const std::vector<std::string>& specs, const modeling::Stencils& stencils,
                          const modeling::Positions& rest);

// The --pin texts' checks that need no mesh (each motion and release parses, none stands alone,
// no group moves with --pin-motion given): InputError naming the option and the group.
void checkPinSpecs(const std::vector<std::string>& specs, const std::string& pinMotion);
// Whether a --pin group carries a release.
bool pinsReleased(const std::vector<std::string>& specs);

}  // namespace flexure::cli
