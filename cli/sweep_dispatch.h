// A sweep on Dask from the command line: Python's flexure.sweep (docs/sweeps.md), started as
// `python3 -m flexure sweep` with this executable as the command its cases run. `flexure run
// --grid` and `flexure converge --scheduler` dispatch their cases through it.
#pragma once

#include <string>

#include "cli/commands.h"

namespace flexure::cli {

struct SweepDispatch {
  std::string specFile, gridFile;  // the run spec with ${name} placeholders and its grid
  std::string outputDir;           // case folders, sweep.csv and sweep.json
  std::string scheduler;           // a Dask scheduler's address ("": local worker processes)
  int workers = 0;                 // local worker processes (0: one per CPU)
};

// Runs the sweep and returns its exit code: 0 when every case is done (or was already), 2 when
// the grid or a case is refused (nothing run; also when Python, flexure's module or Dask's
// distributed cannot be started), else the largest exit code of the failed cases. `commandName`
// ("flexure run --grid") prefixes its messages.
int runSweep(const SweepDispatch& sweep, const GlobalOptions& global,
             const std::string& commandName);

}  // namespace flexure::cli
