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

// rotate:ax,ay,az,px,py,pz,omega or translate:vx,vy,vz (InputError naming --pin-motion
// otherwise: a zero axis, a number that is not finite, a wrong count).
// `option` names the text's source in the message (--pin-motion, or a --pin group).
optimize::PinMotion parsePinMotion(const std::string& spec,
                                   const std::string& option = "--pin-motion");

// The groups of the --pin texts that carry a motion or a release, each SET[@MOTION][@release:T]
// (MOTION as parsePinMotion reads it, T the time the group is let go), in order, without their
// vertices (pinnedGroups sets them on the mesh). A group with a release and no motion of its own
// follows `pinMotion` until it is let go.
std::vector<optimize::PinGroup> pinGroupMotions(const std::vector<std::string>& specs,
                                                const optimize::PinMotion& pinMotion);

// The pinned vertices of the --pin groups (SET as optimize::parseFixedSet reads it): their union,
// and each of `groups`' vertices (`groups` as pinGroupMotions made them).
struct PinnedGroups {
  std::vector<bool> held;          // #V
  std::vector<bool> clampedEdges;  // #E or empty: optimize::clampedBoundaryEdges
};
PinnedGroups pinnedGroups(const std::vector<std::string>& specs, const modeling::Stencils& stencils,
                          const modeling::Positions& rest, std::vector<optimize::PinGroup>& groups);

// The --pin texts' checks that need no mesh (each motion and release parses, none stands alone,
// no group moves with --pin-motion given): InputError naming the option and the group.
void checkPinSpecs(const std::vector<std::string>& specs, const std::string& pinMotion);

}  // namespace flexure::cli
