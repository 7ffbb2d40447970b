// The flexure subcommands. Each registers itself on the app with its options and a callback that
// runs it; the callbacks throw InputError (exit 2) or NumericalError (exit 3) on failure.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace flexure::cli {

struct GlobalOptions {
  bool quiet = false;    // no progress or notices on stderr
  bool verbose = false;  // Ceres' and glog's own lines on stderr too
  // Parse and check the options and outputs, run nothing: `flexure run` checks every step
  // before it runs the first.
  bool checkOnly = false;
};

void registerMeshCommand(CLI::App& app, const GlobalOptions& global);
void registerInfoCommand(CLI::App& app, const GlobalOptions& global);
void registerConvertCommand(CLI::App& app, const GlobalOptions& global);
void registerEnergyCommand(CLI::App& app, const GlobalOptions& global);
void registerMinimizeCommand(CLI::App& app, const GlobalOptions& global);
void registerConvergeCommand(CLI::App& app, const GlobalOptions& global);
void registerDemoCommand(CLI::App& app, const GlobalOptions& global);
void registerRunCommand(CLI::App& app, const GlobalOptions& global);
void registerRenderCommand(CLI::App& app, const GlobalOptions& global);
void registerCompareCommand(CLI::App& app, const GlobalOptions& global);
void registerFairCommand(CLI::App& app, const GlobalOptions& global);
void registerModesCommand(CLI::App& app, const GlobalOptions& global);
void registerSimulateCommand(CLI::App& app, const GlobalOptions& global);
void registerRepairCommand(CLI::App& app, const GlobalOptions& global);
void registerViewCommand(CLI::App& app, const GlobalOptions& global);

// Parses `args` (args[0] is the program name) and runs the chosen subcommand; returns the exit
// code: 0 success, 2 bad input or usage, 3 numerical failure. `flexure run` re-enters here.
int runFlexure(const std::vector<std::string>& args, bool checkOnly = false);

}  // namespace flexure::cli
