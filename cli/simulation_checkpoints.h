// flexure simulate's checkpoints (internal to cli/): the stepper's state, the run's counts and
// the recording written as DIR/checkpoint.json, and a run continued from one.
#pragma once

#include <string>

#include "cli/simulation_arguments.h"
#include "cli/simulation_recording.h"
#include "modeling/mesh.h"
#include "optimize/dynamics/time_stepping.h"

namespace flexure::cli {

// FNV-1a (64 bits) of the rest mesh's OBJ text: a checkpoint is resumed on the same mesh only.
std::string meshChecksum(const modeling::Mesh& mesh);

// DIR/checkpoint.json after step k, written at once (atomically, outside the run's output batch,
// so that it outlives a kill or a failure): the stepper's state (time_stepping.h State), the run's
// counts and the recording so far, with the options and the mesh it was made with. The stepper
// drops its kept factor, so that the run continues as a resumed one does.
void writeCheckpoint(const SimulateOptions& o, optimize::TimeStepper& stepper,
                     const Recording& recording, const Run& run, long k,
                     const std::string& checksum);

// Continues from --resume DIR's checkpoint: the stepper's state, the run's counts and the
// recording; the step it was written after. InputError (exit 2) when it is missing, unreadable,
// or made with other options or another mesh.
long resumeCheckpoint(const SimulateOptions& o, const std::string& checksum,
                      optimize::TimeStepper& stepper, Recording& recording, Run& run,
                      const modeling::Mesh& restMesh);

}  // namespace flexure::cli
