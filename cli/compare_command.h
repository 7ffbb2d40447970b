// flexure compare, shared with flexure demo: every energy's minimizer of the flat-plate test
// problem on every mesh family, rendered alike and composed into one labelled grid.
#pragma once

#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/solver_arguments.h"
#include "curvature/energy_registry.h"

namespace flexure::cli {

struct CompareOptions {
  std::string outputDir = "compare";
  std::vector<std::string> families = {"patch48", "stripe", "delaunay"};  // rows
  std::vector<std::string> energies = curvature::energyNameList();        // the registered energies
  // Flat meshes (z = 0) of the user's, one row each after the families (rows and files named
  // mesh-<file stem>).
  std::vector<std::string> meshFiles;
  std::string boundary = "quadratic:0.3,-0.7,0.5";
  int n = 16;
  std::string solve = "linearized";  // or "nonlinear"
  std::string style = "reflection";
  int size = 400;  // panel width and height in pixels
  int stripes = 12;
  int threads = 2;
  SolverArguments solver;
};

// Checks every option and generates the meshes (InputError, nothing written), solves and renders
// every panel, then creates `outputDir` and writes compare.png, compare.json and the panels
// (<family>-<energy>.png) atomically. Progress on stderr prefixed by `commandName` unless quiet.
void runCompare(const CompareOptions& options, const GlobalOptions& global,
                const std::string& commandName);

}  // namespace flexure::cli
